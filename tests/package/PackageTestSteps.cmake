# Steps shared by the package tests (cmake -P scripts).

# Runs a command; stops the test with its output if it fails.
function(masse_step what)
    message(STATUS "${what}")
    execute_process(COMMAND ${ARGN} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "${what} failed (${status}):\n${out}")
    endif()
endfunction()

# The consumer's own source was compiled with the core's determinism flags (they come from masse::core's interface,
# not from any setting of the consumer), and without Bullet's headers on its path.
function(masse_expect_flags build source)
    file(READ ${build}/compile_commands.json commands)
    string(REGEX MATCH "\"command\": \"[^\"]*${source}[^\"]*\"" command "${commands}")
    if(command STREQUAL "")
        message(FATAL_ERROR "no compile command for ${source} in ${build}/compile_commands.json")
    endif()
    foreach(flag -ffp-contract=off -fno-math-errno -fno-trapping-math)
        string(FIND "${command}" "${flag}" at)
        if(at EQUAL -1)
            message(FATAL_ERROR "${source} was compiled without ${flag}: ${command}")
        endif()
    endforeach()
    string(FIND "${command}" "bullet" at)
    if(NOT at EQUAL -1)
        message(FATAL_ERROR "${source} sees Bullet: ${command}")
    endif()
    message(STATUS "${source}: compiled with -ffp-contract=off -fno-math-errno -fno-trapping-math, no Bullet")
endfunction()

# The sag a build of examples/sheet_sag.cpp prints, in SAG_OUT.
function(masse_run_sag program sag_out)
    execute_process(COMMAND ${program} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT status EQUAL 0)
        message(FATAL_ERROR "${program} failed (${status}): ${out}")
    endif()
    message(STATUS "${program}: ${out}")
    if(NOT out MATCHES "sag of the middle after 12.00 s: ([0-9.e+-]+) m")
        message(FATAL_ERROR "unexpected output of ${program}: ${out}")
    endif()
    set(${sag_out} ${CMAKE_MATCH_1} PARENT_SCOPE)
endfunction()

# The example built outside prints the same sag, to the last of its 17 digits, as the same source built in MaSSE's
# own tree (REFERENCE): same engine, same flags, same bits. The sag is also physical: positive, and below the sag of
# the bottom layer's rows taken alone as elastic cables that carry the whole weight (MAX; the second layer and the
# diagonal springs only stiffen the sheet).
function(masse_expect_sag program reference max)
    masse_run_sag(${program} sag)
    masse_run_sag(${reference} expected)
    if(NOT sag STREQUAL expected)
        message(FATAL_ERROR "sag ${sag} m, but MaSSE's own build of the example prints ${expected} m")
    endif()
    # CMake has no floating-point arithmetic; awk (POSIX, in every Debian) compares the numbers.
    execute_process(COMMAND awk "BEGIN { exit !(${sag} > 0.001 && ${sag} < ${max}) }" RESULT_VARIABLE outside)
    if(NOT outside EQUAL 0)
        message(FATAL_ERROR "sag ${sag} m is not between 1 mm and the cable bound ${max} m")
    endif()
    message(STATUS "sag ${sag} m: the same bits as MaSSE's own build, and between 1 mm and ${max} m")
endfunction()

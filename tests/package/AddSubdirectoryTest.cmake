# ctest Package.AddSubdirectoryLeavesTheParentAlone (cmake -P): a parent project (parent/) that adds MaSSE with
# add_subdirectory and no build type keeps its empty build type, gets masse::core, bridge and scene but no app, viewer
# or tests, and compiles the example with the core's determinism flags; the example prints the in-tree sag.
#   -DSOURCE=the MaSSE tree  -DWORK=a scratch folder (emptied first)  -DLAUNCHER=ccache or ""
#   -DREFERENCE=the example built in MaSSE's tree  -DMAX_SAG=m
include(${CMAKE_CURRENT_LIST_DIR}/PackageTestSteps.cmake)

file(REMOVE_RECURSE ${WORK})
masse_step("configure the parent" ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR}/parent -B ${WORK}
           -DMASSE_SOURCE=${SOURCE} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER})
file(STRINGS ${WORK}/CMakeCache.txt build_type REGEX "^CMAKE_BUILD_TYPE:")
if(NOT build_type MATCHES "^CMAKE_BUILD_TYPE:STRING=$")
    message(FATAL_ERROR "the parent's cached build type changed: ${build_type}")
endif()
masse_step("build the example in the parent" ${CMAKE_COMMAND} --build ${WORK} --target sheet_sag -j2)
masse_expect_flags(${WORK} sheet_sag.cpp)
masse_expect_sag(${WORK}/sheet_sag ${REFERENCE} ${MAX_SAG})

# Finds what the Python module (python/) needs: Debian's Python 3 with its headers (python3-dev), NumPy
# (python3-numpy) and pybind11 (python3-pybind11), all installed by .ci/build. Sets masse_python_found. Debian's
# /usr/bin/python3 is taken first even when another python3 comes first on the PATH (a pyenv one, without NumPy):
# the module must match the interpreter that imports it, and the tests run that one.
set(masse_python_found OFF)
if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
    set(Python3_EXECUTABLE /usr/bin/python3 CACHE FILEPATH "The Python 3 the module masse is built for")
endif()
find_package(Python3 3.8 QUIET COMPONENTS Interpreter Development.Module NumPy)
if(Python3_FOUND)
    find_package(pybind11 2.6 CONFIG QUIET)
    if(pybind11_FOUND)
        set(masse_python_found ON)
    endif()
endif()

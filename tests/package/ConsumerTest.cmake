# ctest Package.ConsumerBuildsAgainstInstalledCore (cmake -P): MaSSE's core installed alone into a temporary prefix,
# then examples/ as a separate project against that install, with Eigen the only other package it may find.
#   -DSOURCE=the MaSSE tree  -DWORK=a scratch folder (emptied first)  -DLAUNCHER=ccache or ""
#   -DREFERENCE=the example built in MaSSE's tree  -DMAX_SAG=m
# Every package the bridge and scene need (Bullet through pkg-config, tinyobjloader, nlohmann_json) and the app's are
# disabled with CMAKE_DISABLE_FIND_PACKAGE_*, for the core's build and the consumer's: a REQUIRED find of any of them
# would stop the configure with an error, so the test fails if the core or its package config ever asks for one.
include(${CMAKE_CURRENT_LIST_DIR}/PackageTestSteps.cmake)

file(REMOVE_RECURSE ${WORK})
set(prefix ${WORK}/prefix)
set(no_other_packages -DCMAKE_DISABLE_FIND_PACKAGE_PkgConfig=ON -DCMAKE_DISABLE_FIND_PACKAGE_tinyobjloader=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON -DCMAKE_DISABLE_FIND_PACKAGE_CLI11=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON -DCMAKE_DISABLE_FIND_PACKAGE_OpenGL=ON -DCMAKE_DISABLE_FIND_PACKAGE_GLUT=ON)

masse_step("configure the core alone" ${CMAKE_COMMAND} -S ${SOURCE} -B ${WORK}/masse-build -DCMAKE_BUILD_TYPE=Release
           -DCMAKE_INSTALL_PREFIX=${prefix} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER} -DMASSE_BUILD_SCENE=OFF
           -DMASSE_BUILD_APP=OFF -DMASSE_BUILD_VIEWER=OFF -DMASSE_BUILD_TESTS=OFF ${no_other_packages})
masse_step("build the core" ${CMAKE_COMMAND} --build ${WORK}/masse-build -j2)
masse_step("install the core" ${CMAKE_COMMAND} --install ${WORK}/masse-build)

# The install: the core's library, its headers, the config and version files; nothing of the other layers.
foreach(file lib/libmasse_core.a include/masse/core/Simulator.h include/masse/core/forces/SpringForce.h
        lib/cmake/masse/masse-config.cmake lib/cmake/masse/masse-config-version.cmake
        lib/cmake/masse/masse-core-targets.cmake)
    if(NOT EXISTS ${prefix}/${file})
        message(FATAL_ERROR "the install lacks ${file}")
    endif()
endforeach()
foreach(absent include/masse/bridge include/masse/scene lib/libmasse_bridge.a lib/cmake/masse/masse-scene-targets.cmake)
    if(EXISTS ${prefix}/${absent})
        message(FATAL_ERROR "a core-only install holds ${absent}")
    endif()
endforeach()

masse_step("configure the consumer" ${CMAKE_COMMAND} -S ${SOURCE}/examples -B ${WORK}/consumer-build
           -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER} ${no_other_packages})
masse_step("build the consumer" ${CMAKE_COMMAND} --build ${WORK}/consumer-build)
masse_expect_flags(${WORK}/consumer-build sheet_sag.cpp)
masse_expect_sag(${WORK}/consumer-build/sheet_sag ${REFERENCE} ${MAX_SAG})

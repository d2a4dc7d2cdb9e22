# install(EXPORT) of the package `masse`: find_package(masse [COMPONENTS core bridge scene]) in a consumer's project.
# Two export sets, so that a core-only install (MASSE_BUILD_SCENE=OFF) and a consumer that asks only for the core need
# nothing but Eigen: masse-core-targets.cmake (masse::core) and masse-scene-targets.cmake (masse::bridge and
# masse::scene, which bring Bullet, tinyobjloader and nlohmann_json).
include(CMakePackageConfigHelpers)

set(MASSE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/masse)

install(TARGETS masse_core EXPORT masse-core-targets COMPONENT core
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
install(EXPORT masse-core-targets NAMESPACE masse:: DESTINATION ${MASSE_CMAKE_DIR} COMPONENT core)
if(MASSE_BUILD_SCENE)
    install(TARGETS masse_bridge masse_scene EXPORT masse-scene-targets COMPONENT scene
            ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
    install(EXPORT masse-scene-targets NAMESPACE masse:: DESTINATION ${MASSE_CMAKE_DIR} COMPONENT scene)
endif()

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/masse-config.cmake.in
                              ${PROJECT_BINARY_DIR}/masse-config.cmake INSTALL_DESTINATION ${MASSE_CMAKE_DIR})
# 0.x: a minor version may break the interface, so only the same minor version is compatible.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/masse-config-version.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/masse-config.cmake ${PROJECT_BINARY_DIR}/masse-config-version.cmake
        DESTINATION ${MASSE_CMAKE_DIR} COMPONENT core)

# Each layer of src/ (core, bridge, scene, viewer) is seen by its users as "layer/Header.h", the style the code uses,
# through an include directory that holds that one layer and nothing else: build/include/<layer>/<layer> is a link to
# src/<layer>. A target therefore sees the headers of the layers it links and no others (the core cannot include a
# bridge header by accident), and a consumer of masse::core does not get the whole src/ tree on its include path.
# Installed, the public headers of every layer go to include/masse/<layer>/, and include/masse is the include
# directory of the exported targets, so "core/Simulator.h" means the same in and out of the tree.
include(GNUInstallDirs)

function(masse_layer target layer)
    set(root ${PROJECT_BINARY_DIR}/include/${layer})
    file(MAKE_DIRECTORY ${root})
    if(NOT EXISTS ${root}/${layer})
        file(CREATE_LINK ${PROJECT_SOURCE_DIR}/src/${layer} ${root}/${layer} SYMBOLIC)
    endif()
    target_include_directories(${target} PUBLIC $<BUILD_INTERFACE:${root}>
                                                $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}/masse>)
    target_compile_features(${target} PUBLIC cxx_std_20)
endfunction()

# Installs a layer's headers into include/masse/<layer>/, keeping their rooms (include/masse/core/lattice/...), except
# the private ones named by their path inside the layer (their #includes name third-party headers that the package
# does not promise, such as Bullet's).
function(masse_install_headers layer)
    cmake_parse_arguments(PARSE_ARGV 1 arg "" "" "PRIVATE")
    set(base ${PROJECT_SOURCE_DIR}/src/${layer})
    file(GLOB_RECURSE headers RELATIVE ${base} ${base}/*.h)
    foreach(private ${arg_PRIVATE})
        list(REMOVE_ITEM headers ${private})
    endforeach()
    foreach(header ${headers})
        get_filename_component(room ${header} DIRECTORY)
        install(FILES ${base}/${header} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/masse/${layer}/${room} COMPONENT ${layer})
    endforeach()
endfunction()

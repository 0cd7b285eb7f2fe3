# Installation of MANTA (docs/tutorial-optimal.md): `cmake --install <build> --prefix P` puts the
# modules' public headers in P/include, their static libraries in P/lib, the `manta` executable
# in P/bin, the CMake package in P/lib/cmake/MANTA (MANTAConfig.cmake, MANTAConfigVersion.cmake,
# MANTATargets.cmake: targets MANTA::<module>) and one pkg-config file per module,
# P/lib/pkgconfig/manta-<module>.pc. Included by the top-level CMakeLists.txt after every module.
#
# The libraries are static, so a module's private dependencies are part of its users' link: the
# exported targets list them as link-only dependencies, MANTAConfig.cmake finds each again, and
# the .pc files name them in Requires/Libs (not the .private fields). Every dependency of a module
# must be in the table below; configuring stops on one that is not.

include(CMakePackageConfigHelpers)

set(MANTA_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/MANTA)
set(MANTA_PKGCONFIG_DIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)

# target | package key (a `find` block of cmake/MANTAConfig.cmake.in) | pkg-config module, or
# `-` when the package has none (its flags are written out)
set(_manta_dep_table
    "Eigen3::Eigen|Eigen3|eigen3"
    "fmt::fmt|fmt|fmt"
    "yaml-cpp|yaml-cpp|yaml-cpp"
    "yaml-cpp::yaml-cpp|yaml-cpp|yaml-cpp"
    "Boost::boost|Boost|-"
    "Boost::headers|Boost|-"
    "NLopt::nlopt|NLopt|nlopt"
    "SQLite::SQLite3|SQLite3|sqlite3"
    "PkgConfig::IPOPT|IPOPT|ipopt"
    "ZLIB::ZLIB|ZLIB|zlib"
    "MPI::MPI_CXX|MPI|-"
    "nlohmann_json::nlohmann_json|nlohmann_json|nlohmann_json"
    "MANTA_deps::cgns|cgns|-"
    "MANTA_deps::metis|metis|-"
    "MANTA_deps::gmsh|gmsh|-")

# The libraries without a CMake package, found again by MANTAConfig.cmake where the build found
# them (manta_find_library, cmake/MANTAFindLibrary.cmake): name, header, library.
set(_manta_plain_libraries "cgns|cgnslib.h|cgns" "metis|metis.h|metis" "gmsh|gmsh.h|gmsh")

# Flags of the dependencies without a pkg-config module, for the .pc files. MPI is found by
# src/parallel in its own scope: found again here in a function, so that no MPI variable
# reaches the folders configured after this file.
function(_manta_mpi_libraries out)
    set(MPI_CXX_SKIP_MPICXX ON)
    find_package(MPI QUIET COMPONENTS CXX)
    string(REPLACE ";" " " libs "${MPI_CXX_LIBRARIES}")
    set(${out} "${libs}" PARENT_SCOPE)
endfunction()
_manta_mpi_libraries(_manta_pc_libs_MPI)
set(_manta_pc_cflags_Boost "")
foreach(d IN LISTS Boost_INCLUDE_DIRS)
    if(NOT d IN_LIST CMAKE_CXX_IMPLICIT_INCLUDE_DIRECTORIES)
        string(APPEND _manta_pc_cflags_Boost " -I${d}")
    endif()
endforeach()
set(_manta_pc_libs_Boost "")
set(_manta_pc_cflags_MPI "")
foreach(entry IN LISTS _manta_plain_libraries)
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 name)
    set(_manta_pc_cflags_${name} "")
    set(_manta_pc_libs_${name} "")
    if(TARGET MANTA_deps::${name})
        get_target_property(_manta_pc_libs_${name} MANTA_deps::${name} IMPORTED_LOCATION)
    endif()
endforeach()

get_property(_manta_modules GLOBAL PROPERTY MANTA_MODULES)
set(MANTA_CONFIG_MODULES "set(_MANTA_modules ${_manta_modules})\n")
set(_manta_hints "")
foreach(m IN LISTS _manta_modules)
    get_property(deps GLOBAL PROPERTY MANTA_MODULE_${m}_DEPS)
    get_property(private GLOBAL PROPERTY MANTA_MODULE_${m}_PRIVATE_DEPS)
    set(modules "")
    set(packages "")
    set(requires "")
    set(cflags "")
    set(libs "")
    foreach(d IN LISTS deps private)
        if(d MATCHES "^manta::(.+)$")
            list(APPEND modules ${CMAKE_MATCH_1})
            list(APPEND requires manta-${CMAKE_MATCH_1})
            continue()
        endif()
        set(found FALSE)
        foreach(row IN LISTS _manta_dep_table)
            string(REPLACE "|" ";" row "${row}")
            list(GET row 0 target)
            if(target STREQUAL d)
                list(GET row 1 key)
                list(GET row 2 pc)
                list(APPEND packages ${key})
                if(pc STREQUAL "-")
                    string(APPEND cflags "${_manta_pc_cflags_${key}}")
                    if(_manta_pc_libs_${key})
                        string(APPEND libs " ${_manta_pc_libs_${key}}")
                    endif()
                else()
                    list(APPEND requires ${pc})
                endif()
                set(found TRUE)
                break()
            endif()
        endforeach()
        if(NOT found)
            message(FATAL_ERROR "cmake/MANTAInstall.cmake: module '${m}' links '${d}', which the "
                                "installed MANTAConfig.cmake cannot find again: expected an imported "
                                "target of its dependency table")
        endif()
    endforeach()
    list(REMOVE_DUPLICATES modules)
    list(REMOVE_DUPLICATES packages)
    list(REMOVE_DUPLICATES requires)
    string(APPEND MANTA_CONFIG_MODULES "set(_MANTA_${m}_modules ${modules})\n"
                                       "set(_MANTA_${m}_packages ${packages})\n")
    # pkg-config: relocatable (the prefix from the .pc file's own folder), so that
    # `cmake --install --prefix P` needs no reconfiguration
    string(REPLACE ";" ", " requires "${requires}")
    set(pc "prefix=\${pcfiledir}/../..\n"
           "libdir=\${prefix}/${CMAKE_INSTALL_LIBDIR}\n"
           "includedir=\${prefix}/${CMAKE_INSTALL_INCLUDEDIR}\n\n"
           "Name: manta-${m}\n"
           "Description: MANTA module ${m} (static library)\n"
           "Version: ${PROJECT_VERSION}\n"
           "Requires: ${requires}\n"
           "Libs: -L\${libdir} -lmanta_${m}${libs}\n"
           "Cflags: -I\${includedir}${cflags}\n")
    string(JOIN "" pc ${pc})
    file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/pkgconfig/manta-${m}.pc CONTENT "${pc}")
    install(FILES ${CMAKE_BINARY_DIR}/pkgconfig/manta-${m}.pc DESTINATION ${MANTA_PKGCONFIG_DIR})
endforeach()
foreach(entry IN LISTS _manta_plain_libraries)
    string(REPLACE "|" ";" entry "${entry}")
    list(GET entry 0 name)
    list(GET entry 1 header)
    list(GET entry 2 library)
    set(paths "")
    if(TARGET MANTA_deps::${name})
        get_target_property(loc MANTA_deps::${name} IMPORTED_LOCATION)
        get_target_property(inc MANTA_deps::${name} INTERFACE_INCLUDE_DIRECTORIES)
        get_filename_component(loc "${loc}" DIRECTORY)
        set(paths "${inc};${loc}")
    endif()
    string(APPEND MANTA_CONFIG_MODULES
           "set(_MANTA_library_${name} HEADER ${header} LIBRARY ${library} PATHS ${paths})\n")
endforeach()

install(EXPORT MANTATargets NAMESPACE MANTA:: DESTINATION ${MANTA_CMAKE_DIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/MANTAConfig.cmake.in
                              ${CMAKE_BINARY_DIR}/cmake/MANTAConfig.cmake
                              INSTALL_DESTINATION ${MANTA_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_BINARY_DIR}/cmake/MANTAConfigVersion.cmake
                                 VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_BINARY_DIR}/cmake/MANTAConfig.cmake
              ${CMAKE_BINARY_DIR}/cmake/MANTAConfigVersion.cmake
              ${CMAKE_CURRENT_LIST_DIR}/MANTAFindLibrary.cmake
        DESTINATION ${MANTA_CMAKE_DIR})
install(TARGETS manta RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})

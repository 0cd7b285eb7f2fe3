# manta_find_library(<name> HEADER <header> LIBRARY <library> [PATHS <dirs...>] [GLOBAL])
# The imported target MANTA_deps::<name> for a system library that ships no CMake package (CGNS,
# METIS, the gmsh API): its header's folder and its library, found in the cache variables
# <NAME>_INCLUDE_DIR and <NAME>_LIBRARY (searched in PATHS too). Sets <name>_FOUND in the
# caller. Used by the build (src/mesh, src/parallel, src/meshgen; GLOBAL, so that the targets
# linking a module see it) and by the installed MANTAConfig.cmake, which finds the same
# libraries again for the modules' link-only dependencies.
function(manta_find_library name)
    cmake_parse_arguments(L "GLOBAL" "HEADER;LIBRARY" "PATHS" ${ARGN})
    string(TOUPPER ${name} upper)
    if(TARGET MANTA_deps::${name})
        set(${name}_FOUND TRUE PARENT_SCOPE)
        return()
    endif()
    find_path(${upper}_INCLUDE_DIR ${L_HEADER} PATHS ${L_PATHS})
    find_library(${upper}_LIBRARY ${L_LIBRARY} PATHS ${L_PATHS})
    if(NOT ${upper}_INCLUDE_DIR OR NOT ${upper}_LIBRARY)
        set(${name}_FOUND FALSE PARENT_SCOPE)
        return()
    endif()
    if(L_GLOBAL)
        add_library(MANTA_deps::${name} UNKNOWN IMPORTED GLOBAL)
    else()
        add_library(MANTA_deps::${name} UNKNOWN IMPORTED)
    endif()
    set_target_properties(MANTA_deps::${name} PROPERTIES
        IMPORTED_LOCATION "${${upper}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${${upper}_INCLUDE_DIR}")
    set(${name}_FOUND TRUE PARENT_SCOPE)
endfunction()

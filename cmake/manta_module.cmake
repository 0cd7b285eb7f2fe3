# manta_module(NAME <name> SOURCES <files...> DEPS <targets...> [PRIVATE_DEPS <targets...>])
# One static library per module, manta::<name> in the tree (and MANTA::<name>, the name the
# installed package exports: cmake/MANTAInstall.cmake); its link list is the module's allowed
# dependencies (docs/architecture: the include-direction check reads the same lists). The static
# library's PRIVATE_DEPS reach its users as link-only dependencies, so every one must be an
# imported target that the installed MANTAConfig.cmake can find again (cmake/MANTAInstall.cmake
# refuses the others at configure time).
function(manta_module)
    cmake_parse_arguments(M "" "NAME" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
    add_library(manta_${M_NAME} STATIC ${M_SOURCES})
    add_library(manta::${M_NAME} ALIAS manta_${M_NAME})
    add_library(MANTA::${M_NAME} ALIAS manta_${M_NAME})
    set_target_properties(manta_${M_NAME} PROPERTIES EXPORT_NAME ${M_NAME})
    target_compile_features(manta_${M_NAME} PUBLIC cxx_std_20)
    target_include_directories(manta_${M_NAME}
        PUBLIC $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>
               $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>
        PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
    target_link_libraries(manta_${M_NAME} PUBLIC ${M_DEPS}
                          PRIVATE $<BUILD_INTERFACE:manta_warnings> ${M_PRIVATE_DEPS})
    install(TARGETS manta_${M_NAME} EXPORT MANTATargets
            ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
            INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    # for the package files (cmake/MANTAInstall.cmake): the module and its direct dependencies
    set_property(GLOBAL APPEND PROPERTY MANTA_MODULES ${M_NAME})
    set_property(GLOBAL PROPERTY MANTA_MODULE_${M_NAME}_DEPS ${M_DEPS})
    set_property(GLOBAL PROPERTY MANTA_MODULE_${M_NAME}_PRIVATE_DEPS ${M_PRIVATE_DEPS})
endfunction()

# manta_test(NAME <name> SOURCES <files...> DEPS <targets...> [LABELS <labels...>])
function(manta_test)
    cmake_parse_arguments(T "" "NAME" "SOURCES;DEPS;LABELS" ${ARGN})
    add_executable(${T_NAME} ${T_SOURCES})
    target_link_libraries(${T_NAME} PRIVATE ${T_DEPS} GTest::gtest manta_gtest_main manta_warnings)
    target_compile_definitions(${T_NAME} PRIVATE
        MANTA_SOURCE_DIR="${CMAKE_SOURCE_DIR}" MANTA_SHARED_DIR="${MANTA_SHARED_DIR}")
    if(NOT T_LABELS)
        set(T_LABELS unit)
    endif()
    gtest_discover_tests(${T_NAME} PROPERTIES LABELS "${T_LABELS}" DISCOVERY_TIMEOUT 60)
endfunction()

# manta_module_tests(PREFIX <prefix> DEPS <targets...>)
# One test executable <prefix>_<stem> per test_*.cpp of the calling folder; files named
# test_*_validation.cpp carry the `validation` label, test_*_slow.cpp `slow` (not in `make test`),
# the others `unit`.
function(manta_module_tests)
    cmake_parse_arguments(MT "" "PREFIX" "DEPS" ${ARGN})
    file(GLOB tests CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/test_*.cpp)
    foreach(f ${tests})
        get_filename_component(stem ${f} NAME_WE)
        if(stem MATCHES "_validation$")
            set(labels validation)
        elseif(stem MATCHES "_slow$")
            set(labels slow)
        else()
            set(labels unit)
        endif()
        manta_test(NAME ${MT_PREFIX}_${stem} SOURCES ${f} DEPS ${MT_DEPS} LABELS ${labels})
    endforeach()
endfunction()

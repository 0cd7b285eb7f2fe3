# manta_module(NAME <name> SOURCES <files...> DEPS <targets...>)
# One static library per module, exported as manta::<name>; its link list is the module's
# allowed dependencies (docs/architecture: the include-direction check reads the same lists).
function(manta_module)
    cmake_parse_arguments(M "" "NAME" "SOURCES;DEPS;PRIVATE_DEPS" ${ARGN})
    add_library(manta_${M_NAME} STATIC ${M_SOURCES})
    add_library(manta::${M_NAME} ALIAS manta_${M_NAME})
    target_include_directories(manta_${M_NAME} PUBLIC ${CMAKE_CURRENT_SOURCE_DIR}/include
                                               PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
    target_link_libraries(manta_${M_NAME} PUBLIC ${M_DEPS} PRIVATE manta_warnings ${M_PRIVATE_DEPS})
endfunction()

# manta_test(NAME <name> SOURCES <files...> DEPS <targets...> [LABELS <labels...>])
function(manta_test)
    cmake_parse_arguments(T "" "NAME" "SOURCES;DEPS;LABELS" ${ARGN})
    add_executable(${T_NAME} ${T_SOURCES})
    target_link_libraries(${T_NAME} PRIVATE ${T_DEPS} GTest::gtest GTest::gtest_main manta_warnings)
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

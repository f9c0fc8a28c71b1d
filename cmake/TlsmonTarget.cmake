# Warnings on the project's own code; third-party headers are included as SYSTEM.
# -Werror only when asked (CI sets it): a new compiler's warning must not break a user's build.
option(TLSMON_WERROR "Treat compiler warnings as errors on the project's own targets" OFF)
function(tlsmon_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  if(TLSMON_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()

# A library made of every .cpp in the calling folder (one target per folder), except the
# files named after EXCLUDE; DEPS are linked publicly. A folder with no .cpp yet gives a
# header-only (INTERFACE) library.
function(tlsmon_folder_library target)
  cmake_parse_arguments(ARG "" "" "DEPS;EXCLUDE" ${ARGN})
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  foreach(_x IN LISTS ARG_EXCLUDE)
    list(REMOVE_ITEM _sources ${CMAKE_CURRENT_SOURCE_DIR}/${_x})
  endforeach()
  if(NOT _sources)
    add_library(${target} INTERFACE)
    target_include_directories(${target} INTERFACE ${PROJECT_SOURCE_DIR})
    target_link_libraries(${target} INTERFACE ${ARG_DEPS})
    return()
  endif()
  add_library(${target} STATIC ${_sources})
  target_include_directories(${target} PUBLIC ${PROJECT_SOURCE_DIR})
  target_link_libraries(${target} PUBLIC ${ARG_DEPS})
  tlsmon_warnings(${target})
endfunction()

# A GoogleTest executable made of every .cpp in tests/<folder>, registered with CTest.
function(tlsmon_test_folder folder)
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.cpp)
  if(NOT _sources)
    return()
  endif()
  set(_target tests_${folder})
  add_executable(${_target} ${_sources})
  # The project root, for the shared helpers: #include "tests/support/temp_dir.hpp".
  target_include_directories(${_target} PRIVATE ${PROJECT_SOURCE_DIR})
  tlsmon_warnings(${_target})
  target_link_libraries(${_target} PRIVATE GTest::gtest GTest::gtest_main ${ARGN})
  target_compile_definitions(${_target} PRIVATE
    TLSMON_DATA_DIR="${TLSMON_DATA_DIR}"
    TLSMON_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    TLSMON_BINARY="$<TARGET_FILE:tlsmon>")
  add_dependencies(${_target} tlsmon)
  gtest_discover_tests(${_target} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT 900)
endfunction()

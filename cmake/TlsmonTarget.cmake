# Warnings on the project's own code; third-party headers are included as SYSTEM.
# -Werror only when asked (CI sets it): a new compiler's warning must not break a user's build.
option(TLSMON_WERROR "Treat compiler warnings as errors on the project's own targets" OFF)
function(tlsmon_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra)
  # GCC 12 at -O3 reports -Wrestrict on std::string concatenation inside libstdc++'s own
  # memcpy (GCC bug 105651, fixed in GCC 13): a false positive on correct code, so it is
  # switched off for that compiler only.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_GREATER_EQUAL 12
     AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
    target_compile_options(${target} PRIVATE -Wno-restrict)
  endif()
  # In a unity build GCC takes every joined .cpp for a header and reports a class holding a
  # type of the .cpp's anonymous namespace (-Wsubobject-linkage): a warning for headers that
  # no such file is.
  get_target_property(_unity ${target} UNITY_BUILD)
  if(_unity AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${target} PRIVATE -Wno-subobject-linkage)
  endif()
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

# The GoogleTest executables of tests/<folder>, registered with CTest and labelled, so that
# `ctest -L unit` runs the fast, in-process tests alone:
#   tests_<folder>          test_*.cpp except test_process_*.cpp       label `unit`
#   tests_<folder>_process  test_process_*.cpp: tests that start the   label `process`
#                           tlsmon binary or a daemon, or mount a tmpfs (root)
# The label goes with the file name, so a file holds tests of one kind only. Only the
# process executables wait for the tlsmon binary, so the unit ones build without it.
function(tlsmon_test_folder folder)
  file(GLOB _sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/${folder}/*.cpp)
  foreach(_src IN LISTS _sources)
    get_filename_component(_name ${_src} NAME)
    if(NOT _name MATCHES "^test_")
      message(FATAL_ERROR "tests/${folder}/${_name}: test files are named test_*.cpp "
                          "(test_process_*.cpp when they start a process or mount a tmpfs)")
    endif()
  endforeach()
  set(_unit ${_sources})
  set(_process ${_sources})
  list(FILTER _unit EXCLUDE REGEX "/test_process_[^/]*$")
  list(FILTER _process INCLUDE REGEX "/test_process_[^/]*$")
  _tlsmon_test_executable(tests_${folder} unit "${_unit}" ${ARGN})
  _tlsmon_test_executable(tests_${folder}_process process "${_process}" ${ARGN})
  if(TARGET tests_${folder}_process)
    add_dependencies(tests_${folder}_process tlsmon)
  endif()
endfunction()

function(_tlsmon_test_executable target label sources)
  if(NOT sources)
    return()
  endif()
  add_executable(${target} ${sources})
  # The project root, for the shared helpers: #include "tests/support/temp_dir.hpp".
  target_include_directories(${target} PRIVATE ${PROJECT_SOURCE_DIR})
  tlsmon_warnings(${target})
  target_link_libraries(${target} PRIVATE GTest::gtest GTest::gtest_main ${ARGN})
  target_compile_definitions(${target} PRIVATE
    TLSMON_DATA_DIR="${TLSMON_DATA_DIR}"
    TLSMON_SOURCE_DIR="${PROJECT_SOURCE_DIR}"
    TLSMON_BINARY="$<TARGET_FILE:tlsmon>"
    TLSMON_TEST_CACHE="${CMAKE_BINARY_DIR}/test-cache")
  # ctest -j starts the costliest tests first. Without the timing history of an earlier run (a
  # fresh clone) every test costs the same and runs in declaration order, so a process test of
  # minutes could start last, with one core idle behind it; process tests are the long ones.
  if(label STREQUAL "process")
    set(_cost 10)
  else()
    set(_cost 1)
  endif()
  gtest_discover_tests(${target} DISCOVERY_TIMEOUT 60
                       PROPERTIES TIMEOUT 900 LABELS ${label} COST ${_cost})
endfunction()

# Shared warning flags and helpers so every layer's CMakeLists stays a few lines long.

add_library(wheelpose_warnings INTERFACE)
target_compile_options(wheelpose_warnings INTERFACE -Wall -Wextra -Werror)

# wheelpose_layer(NAME DEPS ...) builds src/<NAME>/*.cpp (except *_test.cpp) as library
# wheelpose_<NAME>, and all of its *_test.cpp files as one GoogleTest executable <NAME>_test.
# A new source file in a layer therefore needs no CMake edit.
function(wheelpose_layer name)
  cmake_parse_arguments(ARG "" "" "DEPS;TEST_DEPS" ${ARGN})
  file(GLOB sources CONFIGURE_DEPENDS ${CMAKE_CURRENT_SOURCE_DIR}/*.cpp)
  set(tests ${sources})
  list(FILTER sources EXCLUDE REGEX "_test\\.cpp$")
  list(FILTER tests INCLUDE REGEX "_test\\.cpp$")
  if(NOT sources)
    # A layer still being written: nothing to compile yet.
    add_library(wheelpose_${name} INTERFACE)
    target_include_directories(wheelpose_${name} INTERFACE ${CMAKE_SOURCE_DIR}/src)
    target_link_libraries(wheelpose_${name} INTERFACE ${ARG_DEPS})
    return()
  endif()
  add_library(wheelpose_${name} STATIC ${sources})
  target_include_directories(wheelpose_${name} PUBLIC ${CMAKE_SOURCE_DIR}/src)
  target_link_libraries(wheelpose_${name} PUBLIC ${ARG_DEPS} PRIVATE wheelpose_warnings)
  target_compile_definitions(wheelpose_${name} PRIVATE WHEELPOSE_SOURCE_DIR="${CMAKE_SOURCE_DIR}")
  if(tests)
    wheelpose_test(${name}_test SOURCES ${tests} DEPS wheelpose_${name} ${ARG_TEST_DEPS})
  endif()
endfunction()

# wheelpose_test(NAME SOURCES ... DEPS ... [TIMEOUT seconds]) adds a GoogleTest executable
# registered with CTest; each of its tests may take TIMEOUT seconds (default 600).
# Tests find the shared data through WHEELPOSE_SHARED_DIR, the project through
# WHEELPOSE_SOURCE_DIR and the CLI through WHEELPOSE_BINARY.
function(wheelpose_test name)
  if(NOT WHEELPOSE_BUILD_TESTS)
    return()
  endif()
  cmake_parse_arguments(ARG "" "TIMEOUT" "SOURCES;DEPS" ${ARGN})
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 600)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} GTest::gtest_main GTest::gmock wheelpose_warnings)
  target_compile_definitions(${name} PRIVATE
    WHEELPOSE_SHARED_DIR="${WHEELPOSE_SHARED_DIR}"
    WHEELPOSE_SOURCE_DIR="${CMAKE_SOURCE_DIR}"
    WHEELPOSE_BINARY="${CMAKE_BINARY_DIR}/wheelpose")
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60 PROPERTIES TIMEOUT ${ARG_TIMEOUT})
endfunction()

# wheelpose_isa_tests(TARGET FILTER) runs TARGET's tests that match the GoogleTest FILTER once
# more per x86-64 ISA, as a CPU with only that ISA would: WHEELPOSE_EMBREE_CONFIG=isa=<isa> caps
# Embree and our AVX2 loops, OPENCV_CPU_DISABLE caps OpenCV's dispatched kernels (OpenCV reads
# it before main, so only the environment can). On a CPU without that ISA the binary skips every
# test (core/isa_test_environment.h) and CTest reports the run as skipped. Each copy gets its own
# temp folder (TMPDIR for std::filesystem, TEST_TMPDIR for GoogleTest): the copies run at the same
# time under ctest -j and would otherwise race on the fixed file names the tests use.
function(wheelpose_isa_tests target filter)
  if(NOT WHEELPOSE_BUILD_TESTS OR NOT CMAKE_SYSTEM_PROCESSOR MATCHES "x86_64|AMD64")
    return()
  endif()
  set(opencv_off_sse4.2 "AVX512-SKX,AVX512F,AVX2,FMA3,AVX,FP16")
  set(opencv_off_avx "AVX512-SKX,AVX512F,AVX2,FMA3")
  set(opencv_off_avx2 "AVX512-SKX,AVX512F")
  set(opencv_off_avx512 "")
  foreach(isa sse4.2 avx avx2 avx512)
    set(temp_dir "${CMAKE_CURRENT_BINARY_DIR}/tmp-${target}-${isa}")
    file(MAKE_DIRECTORY "${temp_dir}")
    add_test(NAME ${target}.isa_${isa} COMMAND ${target} --gtest_filter=${filter})
    set_tests_properties(${target}.isa_${isa} PROPERTIES
      ENVIRONMENT "WHEELPOSE_EMBREE_CONFIG=isa=${isa};OPENCV_CPU_DISABLE=${opencv_off_${isa}};TMPDIR=${temp_dir};TEST_TMPDIR=${temp_dir}/"
      SKIP_REGULAR_EXPRESSION "but this CPU does not have it"
      LABELS isa
      TIMEOUT 900)
  endforeach()
endfunction()

# nephele_add_gtest(<target> PREFIX <prefix> LABELS <label>...
#                   [ENVIRONMENT <VAR=value>...] [DISCOVERY_TIMEOUT <s>] [FILTER <gtest filter>])
# (every test also gets NEPHELE_CACHE_DIR=<build>/test-cache and NEPHELE_CACHE_MAX_MB=512)
#
# The one way a GoogleTest executable becomes CTest tests (issue 17, "Tests and habits"):
#  - DISCOVERY_MODE PRE_TEST: `--gtest_list_tests` runs when ctest starts, not as a POST_BUILD step,
#    so a slow listing on a loaded machine can no longer fail `make` (it did: a 5 s discovery timeout
#    broke `make test` while another build ran). The list is cached next to the executable and
#    re-read only when the executable changes.
#  - NO_PRETTY_VALUES: value-parameterised tests are named `Suite/Test.Case/N` (or by their name
#    generator) instead of `.../GetParam() = <bytes>`, whose byte dumps changed from run to run.
#  - LABELS and ENVIRONMENT are real lists. gtest_discover_tests (CMake 3.25) flattens a list given
#    in PROPERTIES, so `LABELS "unit;io"` gave the label `unit` and a bogus property `io`; here the
#    properties are set by a second CTest include file, read after the discovered tests, on the
#    TEST_LIST the discovery defines.
#  - FILTER is passed to discovery as --gtest_filter (gtest_discover_tests' TEST_FILTER), so the
#    tests it leaves out are never registered: e.g. a second GL backend that skips the numerical
#    tests whose outcome cannot depend on the context (tests/render/CMakeLists.txt).
# Call it once per environment (e.g. once per GL backend, with distinct prefixes).
function(nephele_add_gtest target)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "PREFIX;DISCOVERY_TIMEOUT;FILTER" "LABELS;ENVIRONMENT")
  if(arg_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "nephele_add_gtest(${target}): unknown arguments ${arg_UNPARSED_ARGUMENTS}")
  endif()
  if(NOT arg_PREFIX OR NOT arg_LABELS)
    message(FATAL_ERROR "nephele_add_gtest(${target}): PREFIX and LABELS are required")
  endif()
  if(NOT arg_DISCOVERY_TIMEOUT)
    # Listing is fast when idle (< 0.1 s); the margin is for a machine kept busy by other builds.
    set(arg_DISCOVERY_TIMEOUT 120)
  endif()
  string(MAKE_C_IDENTIFIER "nephele_tests_${target}_${arg_PREFIX}" list_var)
  set(filter_args)
  if(arg_FILTER)
    set(filter_args TEST_FILTER "${arg_FILTER}")
  endif()
  gtest_discover_tests(${target}
    ${filter_args}
    TEST_PREFIX "${arg_PREFIX}"
    TEST_LIST ${list_var}
    NO_PRETTY_VALUES
    DISCOVERY_MODE PRE_TEST
    DISCOVERY_TIMEOUT ${arg_DISCOVERY_TIMEOUT})

  set(properties "LABELS [==[${arg_LABELS}]==]")
  # The reprojected-basemap cache (src/scene/basemap_cache.h) in the build tree, not the user's home.
  list(APPEND arg_ENVIRONMENT "NEPHELE_CACHE_DIR=${PROJECT_BINARY_DIR}/test-cache" "NEPHELE_CACHE_MAX_MB=512")
  string(APPEND properties " ENVIRONMENT [==[${arg_ENVIRONMENT}]==]")
  set(props_file "${CMAKE_CURRENT_BINARY_DIR}/${list_var}_properties.cmake")
  file(WRITE "${props_file}"
    "# Written by nephele_add_gtest (cmake/NepheleTesting.cmake): list-valued properties.\n"
    "if(${list_var})\n"
    "  set_tests_properties(\${${list_var}} PROPERTIES ${properties})\n"
    "endif()\n")
  set_property(DIRECTORY APPEND PROPERTY TEST_INCLUDE_FILES "${props_file}")
endfunction()

# nephele_sanitize_host_tests(<test>... [DLOPEN_DIRS <dir>...])
# Tests whose script runs a program we did not build (ffmpeg, gst-launch-1.0, melt, python3) that
# loads our instrumented plugin or module. In the sanitizer build (NEPHELE_SANITIZE, make
# test-sanitize) that host must have the ASan runtime loaded before anything else, so the test
# preloads clang's shared runtime (the build links it, CMakeLists.txt) into everything the script
# starts. The hosts' own leaks are not ours: LeakSanitizer is off in these tests (detect_leaks=0);
# the library's leaks are checked where our own executables host it (api.c99, api.soak,
# api.batch_osmesa, cli.*). DLOPEN_DIRS go on LD_LIBRARY_PATH, for a library that our code
# dlopen()s by name and finds through its own RUNPATH: ASan's dlopen interceptor becomes the
# caller, so the loader searches the runtime's RUNPATH instead (upstream, google/sanitizers#1219,
# LLVM bug 27790). Elsewhere this does nothing. docs/reliability.md, "Session 19 run".
function(nephele_sanitize_host_tests)
  cmake_parse_arguments(PARSE_ARGV 0 arg "" "" "DLOPEN_DIRS")
  if(NEPHELE_SANITIZE)
    set(env "LD_PRELOAD=${NEPHELE_SANITIZE_PRELOAD}" "ASAN_OPTIONS=detect_leaks=0:abort_on_error=1")
    if(arg_DLOPEN_DIRS)
      string(REPLACE ";" ":" dirs "${arg_DLOPEN_DIRS}")
      list(APPEND env "LD_LIBRARY_PATH=${dirs}")
    endif()
    set_property(TEST ${arg_UNPARSED_ARGUMENTS} APPEND PROPERTY ENVIRONMENT ${env})
  endif()
endfunction()

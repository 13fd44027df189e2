# Registers a Catch2 test executable with CTest so that every declared test case runs.
#
# catch_discover_tests makes one CTest entry per test case, named PREFIX + the case's name, whose
# command runs the executable with that name as its test spec. Three ways that goes silently
# wrong, and what is done about each:
# - A name holding ';' is split by CTest into two entries, neither of which matches a case.
#   Rejected twice: at configure time from the sources (TEST_CASE/SCENARIO with a literal ';'),
#   and after each build from the executable's own list (names made of several literals).
# - Catch 2.13 exits 0 when its spec matched no case, so an entry that runs nothing passes.
#   Every entry runs with --warn NoTests, which makes that exit 2.
# - Nothing would notice a case without an entry. Each registration leaves a line (executable,
#   prefix, spec) in <build>/test_declarations/, from which scripts/check_tests_ran.sh counts the
#   declared cases and compares them with the entries CTest ran ("declared N, ran N").
#
# prepreg_discover_tests(TARGET [TEST_PREFIX P] [TEST_SPEC S] [other catch_discover_tests args])

set(PREPREG_TEST_NAME_CHECK ${CMAKE_CURRENT_LIST_DIR}/check_test_names.cmake)

# Configure-time half: a literal ';' in a test case's name in any source of `target`.
function(prepreg_reject_unsplittable_names target)
  get_target_property(sources ${target} SOURCES)
  get_target_property(source_dir ${target} SOURCE_DIR)
  foreach(source ${sources})
    if(NOT source MATCHES "\\.cc$")
      continue()
    endif()
    if(NOT IS_ABSOLUTE "${source}")
      set(source "${source_dir}/${source}")
    endif()
    file(STRINGS "${source}" offending REGEX "(TEST_CASE|SCENARIO)[A-Z_]*\\(\"[^\"]*;")
    if(offending)
      message(FATAL_ERROR "${source}: a test case name holds ';', which CTest splits into two "
                          "entries that run nothing: ${offending}\nRename it (a ',' or ':' reads as well).")
    endif()
  endforeach()
endfunction()

function(prepreg_discover_tests target)
  # Every keyword of catch_discover_tests, so that TEST_SPEC (a list) ends where the next begins.
  cmake_parse_arguments(ARG "" "TEST_PREFIX;TEST_SUFFIX;WORKING_DIRECTORY;TEST_LIST;REPORTER;OUTPUT_DIR;OUTPUT_PREFIX;OUTPUT_SUFFIX;DISCOVERY_MODE"
                        "TEST_SPEC;EXTRA_ARGS;PROPERTIES" ${ARGN})
  prepreg_reject_unsplittable_names(${target})
  catch_discover_tests(${target} ${ARGN} EXTRA_ARGS --warn NoTests)

  # Build-time half: the names as the executable lists them.
  get_property(checked TARGET ${target} PROPERTY PREPREG_TEST_NAMES_CHECKED)
  if(NOT checked)
    set_property(TARGET ${target} PROPERTY PREPREG_TEST_NAMES_CHECKED TRUE)
    add_custom_command(TARGET ${target} POST_BUILD
                       COMMAND ${CMAKE_COMMAND} -D EXE=$<TARGET_FILE:${target}> -P ${PREPREG_TEST_NAME_CHECK}
                       VERBATIM)
  endif()

  # One declaration per registration: the same executable may be registered with two specs
  # (tests/CMakeLists.txt: cell_tests with and without [real_time]).
  get_property(count GLOBAL PROPERTY PREPREG_TEST_DECLARATION_COUNT)
  if(NOT count)
    set(count 0)
  endif()
  math(EXPR count "${count} + 1")
  set_property(GLOBAL PROPERTY PREPREG_TEST_DECLARATION_COUNT ${count})
  file(GENERATE OUTPUT ${PROJECT_BINARY_DIR}/test_declarations/${count}_${target}.txt
       CONTENT "$<TARGET_FILE:${target}>\n${ARG_TEST_PREFIX}\n${ARG_TEST_SPEC}\n")
endfunction()

# Fails the build when a Catch2 executable declares a test case whose name CTest cannot carry
# (a ';' splits it into two entries that run nothing). Run after each build of a test executable
# (scripts/cmake/test_registration.cmake):  cmake -D EXE=path -P check_test_names.cmake
execute_process(COMMAND ${EXE} --list-test-names-only
                OUTPUT_VARIABLE names RESULT_VARIABLE result)
if(result LESS 0 OR NOT result MATCHES "^[0-9]+$")
  message(FATAL_ERROR "${EXE} --list-test-names-only failed: ${result}")
endif()
# Bracket the lines before CMake's list splitting sees the ';' inside them.
string(REPLACE ";" "<SEMICOLON>" names "${names}")
string(REPLACE "\n" ";" names "${names}")
set(offending "")
foreach(name IN LISTS names)
  if(name MATCHES "<SEMICOLON>")
    string(REPLACE "<SEMICOLON>" ";" name "${name}")
    string(APPEND offending "\n  ${name}")
  endif()
endforeach()
if(offending)
  message(FATAL_ERROR "${EXE}: test case names holding ';', which CTest splits into two entries "
                      "that run nothing (rename them):${offending}")
endif()

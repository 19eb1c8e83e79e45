# catch_discover.cmake - run after a Catch2 test executable is built (tests/CMakeLists.txt,
# ppcr_add_test): lists its test cases and writes the ctest file that gives each one its own test,
# named "<executable>: <test case>", run as `<executable> <escaped name> -w NoTests`.
#
# Catch2's own catch_discover_tests splits its list at ';' (a test case "a; b" became two tests
# matching nothing, both passing) and drops the prefix's trailing space. Here the names never go
# through a CMake list unprotected: ';' is swapped for a placeholder until each name is written
# as a bracket argument, which CMake does not split (square brackets likewise). In the filter, the characters Catch's test
# specification reads (\ , [ ] * ~ ") are escaped with '\'. -w NoTests: a filter that matches no
# test case fails instead of passing.
#
# Variables: EXE (the executable), NAME (its target name), OUT (the ctest file to write),
# PROPERTIES_FILE (a file defining ppcr_test_properties, the list of properties of every test).
cmake_minimum_required(VERSION 3.16)

execute_process(COMMAND "${EXE}" --list-test-names-only
                OUTPUT_VARIABLE listing RESULT_VARIABLE result ERROR_VARIABLE errors
                WORKING_DIRECTORY "${WORK_DIR}")
# Catch2 v2 exits with the number of test cases listed; a crash or a missing file is not a number.
if(NOT result MATCHES "^[0-9]+$")
  message(FATAL_ERROR "${EXE} --list-test-names-only failed (${result}): ${errors}")
endif()

# ';' and square brackets (which stop a list from splitting at ';') are kept out of the list.
string(REPLACE ";" "@PPCR_SEMICOLON@" listing "${listing}")
string(REPLACE "[" "@PPCR_OPEN@" listing "${listing}")
string(REPLACE "]" "@PPCR_CLOSE@" listing "${listing}")
string(REPLACE "\r" "" listing "${listing}")
string(REPLACE "\n" ";" lines "${listing}")

set(script "include([==[${PROPERTIES_FILE}]==])\n")
set(count 0)
foreach(line IN LISTS lines)
  if(line STREQUAL "")
    continue()
  endif()
  string(REPLACE "@PPCR_SEMICOLON@" ";" test_case "${line}")
  string(REPLACE "@PPCR_OPEN@" "[" test_case "${test_case}")
  string(REPLACE "@PPCR_CLOSE@" "]" test_case "${test_case}")
  set(filter "${test_case}")
  foreach(char "\\" "," "[" "]" "*" "~" "\"")
    string(REPLACE "${char}" "\\${char}" filter "${filter}")
  endforeach()
  string(APPEND script
         "add_test([==[${NAME}: ${test_case}]==] [==[${EXE}]==] [==[${filter}]==] -w NoTests)\n"
         "set_tests_properties([==[${NAME}: ${test_case}]==] PROPERTIES "
         "WORKING_DIRECTORY [==[${WORK_DIR}]==] \${ppcr_test_properties})\n")
  math(EXPR count "${count} + 1")
endforeach()
math(EXPR count_mod "${count} % 256")  # an exit status has 8 bits
if(count EQUAL 0 OR NOT count_mod EQUAL result)
  message(FATAL_ERROR "${EXE} listed ${count} test cases, but its exit status says ${result}")
endif()
file(WRITE "${OUT}" "${script}")

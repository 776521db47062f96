# strata_cli_cases(TABLE [PROGRAM TARGET PREFIX P]): one ctest case, cli.NAME
# (P.NAME), per row of a tab-separated table of the CLI's contract
# (tests/cli_cases.tsv says its columns), each run on the real binary, strata
# (TARGET), by tests/run_cli.cmake.
function(strata_cli_cases table)
  cmake_parse_arguments(PARSE_ARGV 1 arg "" "PROGRAM;PREFIX" "")
  if(NOT arg_PROGRAM)
    set(arg_PROGRAM strata)
  endif()
  if(NOT arg_PREFIX)
    set(arg_PREFIX cli)
  endif()
  # Read as text, with the characters a CMake list treats specially ([, ]
  # and ;) kept out of the way until each column is taken.
  file(READ ${table} text)
  # An edited table is a new set of tests: the build configures again.
  set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${table})
  string(REPLACE ";" "<semicolon>" text "${text}")
  string(REPLACE "[" "<open>" text "${text}")
  string(REPLACE "]" "<close>" text "${text}")
  string(REPLACE "\n" ";" lines "${text}")
  set(row 0)
  foreach(line IN LISTS lines)
    math(EXPR row "${row} + 1")
    if(line MATCHES "^#" OR line STREQUAL "")
      continue()
    endif()
    string(REPLACE "\t" ";" cols "${line}")
    list(LENGTH cols n)
    if(NOT n EQUAL 5)
      message(FATAL_ERROR "${table}:${row}: a row needs 5 tab-separated columns, this has ${n}")
    endif()
    list(GET cols 0 name)
    list(GET cols 1 expect)
    list(GET cols 2 args)
    list(GET cols 3 out)
    list(GET cols 4 err)
    foreach(var args out err)
      string(CONFIGURE "${${var}}" ${var} @ONLY)    # @PROJECT_SOURCE_DIR@, @STRATA_TANK@, ...
      string(REPLACE "<open>" "[" ${var} "${${var}}")
      string(REPLACE "<close>" "]" ${var} "${${var}}")
    endforeach()
    string(REPLACE "\\n" "\n" out "${out}")
    string(REPLACE "\\n" "\n" err "${err}")
    string(REPLACE "<semicolon>" ";" out "${out}")
    string(REPLACE "<semicolon>" ";" err "${err}")
    string(REPLACE " " ";" args "${args}")
    string(REPLACE "<space>" " " args "${args}")  # a space inside one argument
    # Each -D below is one quoted argument: a regex may hold a semicolon.
    set(out_arg "-DSTDOUT_MATCH=${out}")
    set(err_arg "-DSTDERR_MATCH=${err}")
    if(out STREQUAL "-")
      set(out_arg "-DSTDOUT_ANY=1")
    endif()
    if(err STREQUAL "-")
      set(err_arg "-DSTDERR_ANY=1")
    endif()
    set(name ${arg_PREFIX}.${name})
    add_test(NAME ${name}
             COMMAND ${CMAKE_COMMAND} -DSTRATA=$<TARGET_FILE:${arg_PROGRAM}> -DPROGRAM=${arg_PROGRAM}
                     -DEXPECT=${expect} "-DARGS=${args}" "${out_arg}" "${err_arg}"
                     -P ${CMAKE_CURRENT_SOURCE_DIR}/run_cli.cmake)
    set_tests_properties(${name} PROPERTIES ENVIRONMENT "${STRATA_TEST_ENV}")
    # A run starts threads: such a case also runs under TSan, except the
    # survey's, whose threads are the tank runs' over a much longer mission
    # (51 s of the tsan tests for no thread of their own).
    if(args MATCHES "^(run|compare|sonar|studio|campaign);" AND NOT args MATCHES "/missions/survey/")
      set_tests_properties(${name} PROPERTIES LABELS threads)
    endif()
  endforeach()
endfunction()

# strata-pnml answers as `strata verify --pnml` does (cli/pnml_verify.h):
# the same JSON report, and the same deadlock question's answer, with the
# same exit code (and the same error, but for the program's name), for the
# nets of tests/verify and, when ../shared/pnml is present, for each of its
# nets under 10^5 states (the larger ones take minutes under the
# sanitizers).
#   cmake -DSTRATA=... -DSTRATA_PNML=... -DSOURCE_DIR=... -P pnml_same_as_verify.cmake
cmake_minimum_required(VERSION 3.25)

file(GLOB nets ${SOURCE_DIR}/tests/verify/*.pnml)
set(corpus ${SOURCE_DIR}/../shared/pnml)
if(EXISTS ${corpus}/answers.csv)
  file(STRINGS ${corpus}/answers.csv rows)
  list(POP_FRONT rows header)
  string(REPLACE "," ";" header "${header}")
  list(FIND header states states_column)
  foreach(row IN LISTS rows)
    string(REPLACE "," ";" cells "${row}")
    list(GET cells 0 model)
    list(GET cells ${states_column} states)
    if(states LESS 100000)
      list(APPEND nets ${corpus}/${model}/model.pnml)
    endif()
  endforeach()
else()
  message("../shared/pnml not present: the nets of tests/verify only")
endif()

# The report of `ARGN` on net, without what differs between two runs (the
# seconds a question took, the program's name).
function(report out net)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE text ERROR_VARIABLE err TIMEOUT 300)
  string(REGEX REPLACE "\n  \"seconds\": [0-9.e+-]+" "" text "${text}")
  string(REPLACE "strata-pnml: " "strata verify: " err "${err}")
  set(${out} "exit ${rc}\n${text}${err}" PARENT_SCOPE)
endfunction()

list(LENGTH nets count)
foreach(net IN LISTS nets)
  report(a ${net} ${STRATA} verify --pnml ${net} --format json)
  report(b ${net} ${STRATA_PNML} ${net} --format json)
  if(NOT a STREQUAL b OR NOT a MATCHES "^exit (0\n\\{\n  \"states\": [1-9]|65\n)")
    message(FATAL_ERROR "${net}: strata verify --pnml and strata-pnml differ\n--- strata verify --pnml:\n${a}\n"
                        "--- strata-pnml:\n${b}")
  endif()
  report(a ${net} ${STRATA} verify --pnml ${net} --question deadlock --format json)
  report(b ${net} ${STRATA_PNML} ${net} --question deadlock --format json)
  if(NOT a STREQUAL b OR NOT a MATCHES "\"answer\": \"(yes|no)\"|^exit 65\n")
    message(FATAL_ERROR "${net} --question deadlock: strata verify --pnml and strata-pnml differ\n"
                        "--- strata verify --pnml:\n${a}\n--- strata-pnml:\n${b}")
  endif()
endforeach()
message("${count} nets: the same reports")

# verify -> witness file -> run --answers, on the binary: a question's
# witness on the tank mission and a counterexample of a stalling phase, each
# written by `strata verify --witness-out` and run by `strata run --answers`;
# the mission log shows the witness's path: its fire events are compared
# with the path the file gives.
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})

function(strata expect)
  execute_process(COMMAND ${STRATA} ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL expect)
    message(FATAL_ERROR "strata ${ARGN}: exit ${rc}, expected ${expect}\nstdout:\n${out}\nstderr:\n${err}")
  endif()
  set(err "${err}" PARENT_SCOPE)
  set(out "${out}" PARENT_SCOPE)
endfunction()

# The vehicle says its filter is on when it is off: filter_was_on fires.
strata(0 verify ${TANK} --net dive_from_surface --question "EF filter_on >= 1" --witness-out ${OUT}/filter.json)
if(NOT err MATCHES "written to .*filter.json: 2 answers")
  message(FATAL_ERROR "verify did not say it wrote the witness:\n${err}")
endif()
strata(1 run ${TANK} --answers ${OUT}/filter.json --log ${OUT}/filter.jsonl)
if(NOT "${out}${err}" MATCHES "answers: 2 scripted from .*filter.json")
  message(FATAL_ERROR "run did not say its answers were scripted:\n${err}")
endif()
file(READ ${OUT}/filter.jsonl log)
foreach(pattern
    "\"event\":\"answers\",\"file\":\"[^\"]*filter.json\",\"answers\":2"
    "\"event\":\"scripted_answer\",[^\n]*\"primitive\":\"depth_filter_off\",\"vehicle\":1,\"answer\":0"
    "\"event\":\"fire\",[^\n]*\"net\":\"dive_from_surface\",\"transition\":\"filter_was_on\""
    "\"event\":\"answers_end\",\"used\":2,\"of\":2"
    "\"event\":\"mission_end\",\"outcome\":\"failed\"")
  if(NOT log MATCHES "${pattern}")
    message(FATAL_ERROR "the log has no line matching ${pattern}:\n${log}")
  endif()
endforeach()

# A counterexample (exit 65: the phase stalls), written anyway, and run.
strata(65 verify ${STUCK} --witness-out ${OUT}/stuck.json)
strata(1 run ${STUCK} --answers ${OUT}/stuck.json --log ${OUT}/stuck.jsonl)
file(STRINGS ${OUT}/stuck.jsonl fires REGEX "\"event\":\"fire\",.*\"net\":\"stuck_phase\"")
set(seen "")
foreach(line ${fires})
  string(REGEX REPLACE ".*\"transition\":\"([a-z_]+)\".*" "\\1" t "${line}")
  list(APPEND seen ${t})
endforeach()
file(STRINGS ${OUT}/stuck.json path REGEX "\"[0-9]+\\. fire ")
set(want "")
foreach(line ${path})
  string(REGEX REPLACE ".*\\. fire ([a-z_]+).*" "\\1" t "${line}")
  list(APPEND want ${t})
endforeach()
if(NOT seen STREQUAL want OR want STREQUAL "")
  message(FATAL_ERROR "the run fired '${seen}' in stuck_phase; the witness's path fires '${want}'")
endif()

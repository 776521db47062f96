# Rules with a term nested ${DEPTH} levels (${SHAPE}: `f(f(...))` or
# `((...))`), through `strata ${MODE}` (issue 16): never a signal.
#  - check, and run with the term in the file: exit 65 (located error)
#    when the term is deeper than the reader takes, 0 otherwise.
#  - run with the term built by the rules after diving (SHAPE built): the
#    run ends through its safe end: the log has mission_end, no signal.
set(work ${WORK_DIR}/depth_${MODE}_${SHAPE}_${DEPTH}.d)
file(REMOVE_RECURSE ${work})
file(MAKE_DIRECTORY ${work}/run)
file(COPY ${SOURCE_DIR}/tests/run/dive_to_setpoint.pl DESTINATION ${work}/run)
if(SHAPE STREQUAL "built")
  file(WRITE ${work}/deep.pl
       "mission_data('${SOURCE_DIR}/missions/tank/setpoints.toml').\n"
       ":- consult('run/dive_to_setpoint').\n"
       "mission :- dive, nest(${DEPTH}, a, T), format(\"~w~n\", [T]), T == T, copy_term(T, C), C = T.\n"
       "nest(0, T, T) :- !.\n"
       "nest(N, T0, T) :- M is N - 1, nest(M, f(T0), T).\n")
else()
  if(SHAPE STREQUAL "f")
    set(open "f(")
  else()
    set(open "(")
  endif()
  string(REPEAT "${open}" ${DEPTH} opens)
  string(REPEAT ")" ${DEPTH} closes)
  file(WRITE ${work}/deep.pl "mission :- X = ${opens}a${closes}, X = _, exec_sleep(1, _).\n")
endif()
set(extra "")
if(MODE STREQUAL "run")
  set(extra --log deep.log --inference-limit 100000000)
endif()
execute_process(COMMAND ${STRATA} ${MODE} deep.pl ${extra}
                WORKING_DIRECTORY ${work}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 120)
if(NOT rc MATCHES "^[0-9]+$" OR rc GREATER 127)
  message(FATAL_ERROR "strata ${MODE} ended by a signal or did not end: ${rc}\n${err}")
endif()
if(SHAPE STREQUAL "built")
  file(READ ${work}/deep.log log)
  if(NOT log MATCHES "mission_end")
    message(FATAL_ERROR "exit ${rc}: the log has no mission_end:\n${log}\n${err}")
  endif()
elseif(DEPTH GREATER 1000)
  if(NOT rc EQUAL 65 OR NOT err MATCHES "deep.pl:1:[0-9]+: error: a term nested deeper than 1000 levels")
    message(FATAL_ERROR "exit ${rc}, expected 65 with a located error:\n${err}")
  endif()
elseif(NOT rc EQUAL 0)
  message(FATAL_ERROR "exit ${rc}, expected 0:\n${out}\n${err}")
endif()
file(REMOVE_RECURSE ${work})

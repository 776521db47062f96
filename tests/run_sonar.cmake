# `strata run MISSION --sonar DIR --log DIR/run.jsonl` on the real binary: the
# Sonar Manager runs as a child process, writes its scans and summary, and
# the run says what it saw; then `strata plot` draws the log with the
# heading the search turned through (when gnuplot is there).
# Variables: STRATA, MISSION, DIR.
file(REMOVE_RECURSE "${DIR}")
file(MAKE_DIRECTORY "${DIR}")
execute_process(COMMAND ${STRATA} run ${MISSION} --sonar ${DIR} --log ${DIR}/run.jsonl
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 120)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "strata run exited ${rc}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(NOT out MATCHES "sonar: the manager ended normally, [1-9][0-9]* frames, [1-9][0-9]* pings, 0 lost, target at [(]")
  message(FATAL_ERROR "the run's summary does not say the manager saw the target:\n${out}\nmanager.log:\n")
endif()
if(NOT EXISTS "${DIR}/latest.png" OR NOT EXISTS "${DIR}/scan_00001.png")
  message(FATAL_ERROR "no scans in ${DIR}")
endif()
file(READ "${DIR}/latest.png" signature LIMIT 8 HEX)
if(NOT signature STREQUAL "89504e470d0a1a0a")
  message(FATAL_ERROR "latest.png is not a PNG file (starts ${signature})")
endif()
file(STRINGS "${DIR}/sonar.jsonl" lines)
list(GET lines -1 last)
if(NOT last MATCHES "\"event\":\"end\"" OR NOT last MATCHES "\"outcome\":\"ended\"" OR NOT last MATCHES "\"lost_pings\":0")
  message(FATAL_ERROR "the last line of sonar.jsonl is not a clean end: ${last}")
endif()
file(READ "${DIR}/run.jsonl" log)
# The sonar's event names no port: the port is random, and two runs of the
# same mission must log the same bytes.
if(NOT log MATCHES "\"heading_deg\":" OR NOT log MATCHES "\"text\":\"sonar on\"")
  message(FATAL_ERROR "the mission log has no heading telemetry or no sonar announcement")
endif()
if(log MATCHES "pings on port")
  message(FATAL_ERROR "the mission log names the sonar's port")
endif()

find_program(GNUPLOT gnuplot)
if(GNUPLOT)
  execute_process(COMMAND ${STRATA} plot ${DIR}/run.jsonl -o ${DIR}/run.svg
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "strata plot exited ${rc}\n${out}\n${err}")
  endif()
  file(READ "${DIR}/run.svg" svg)
  foreach(want "search" "dive_from_surface" "return_to_surface" "heading")
    if(NOT svg MATCHES "${want}")
      message(FATAL_ERROR "the plot has no '${want}'")
    endif()
  endforeach()
endif()
file(REMOVE_RECURSE "${DIR}")

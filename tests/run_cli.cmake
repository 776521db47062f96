# Runs ${STRATA} with ${ARGS} (a ;-list) and checks the exit code against
# ${EXPECT}, and optionally stdout/stderr against regexes (STDOUT_MATCH,
# STDERR_MATCH; STDERR_NOT_MATCH: one stderr must not match).
execute_process(COMMAND ${STRATA} ${ARGS}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 60)
if(NOT rc EQUAL EXPECT)
  message(FATAL_ERROR "exit code ${rc}, expected ${EXPECT}\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED STDOUT_MATCH AND NOT out MATCHES "${STDOUT_MATCH}")
  message(FATAL_ERROR "stdout does not match '${STDOUT_MATCH}':\n${out}")
endif()
if(DEFINED STDERR_MATCH AND NOT err MATCHES "${STDERR_MATCH}")
  message(FATAL_ERROR "stderr does not match '${STDERR_MATCH}':\n${err}")
endif()
if(DEFINED STDERR_NOT_MATCH AND err MATCHES "${STDERR_NOT_MATCH}")
  message(FATAL_ERROR "stderr matches '${STDERR_NOT_MATCH}', which it must not:\n${err}")
endif()

cmake_policy(SET CMP0057 NEW)  # if(... IN_LIST ...)
# Runs ${STRATA} (the program ${PROGRAM}, strata when not given) with ${ARGS} (a ;-list) and checks the exit code against
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

# One voice for errors (issue 40): a case that ends in an error (usage 64,
# invalid input 65, unavailable 69, internal 70, I/O 74) says so in a line
# that starts with `strata COMMAND:` (`strata:` when the command itself is
# unknown), and stderr starts with that line or with a located diagnostic
# (FILE:LINE[:COL]: error ...) that such a line follows.
# With --format json the answer is for tools: a JSON object on stdout (a
# command line that does not parse may still be refused in words).
if(EXPECT MATCHES "^(65|69|70|74)$" AND "${ARGS}" MATCHES "(^|;)--format;json(;|$)")
  if(NOT out MATCHES "^{")
    message(FATAL_ERROR "--format json, exit ${rc}: stdout is not a JSON object:\n${out}\nstderr:\n${err}")
  endif()
elseif(EXPECT MATCHES "^(64|65|69|70|74)$" AND NOT ("${ARGS}" MATCHES "(^|;)--format;json(;|$)" AND out MATCHES "^{"))
  set(_sub "")
  foreach(_a IN LISTS ARGS)
    if(NOT _a MATCHES "^-")
      set(_sub "${_a}")
      break()
    endif()
  endforeach()
  set(_commands check dump run compare verify export studio vehicle primitives library sonar plot campaign config
                completion manpages)
  if(DEFINED PROGRAM AND NOT PROGRAM STREQUAL "strata")
    set(_voice "${PROGRAM}: ")   # a program of its own (strata-pnml)
  elseif(_sub IN_LIST _commands)
    set(_voice "strata ${_sub}( [a-z]+)?: ")
  else()
    set(_voice "strata: ")
  endif()
  if(NOT err MATCHES "(^|\n)${_voice}")
    message(FATAL_ERROR "no line of stderr starts with '${_voice}':\n${err}")
  endif()
  if(NOT err MATCHES "^${_voice}" AND NOT err MATCHES "^[^\n]+:[0-9]+(:[0-9]+)?: (error|warning)")
    message(FATAL_ERROR "stderr starts neither with '${_voice}' nor with a located diagnostic:\n${err}")
  endif()
endif()

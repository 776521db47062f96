# A PROLOG mission that does what the sandbox forbids (issue 16): `strata
# ${MODE}` on a copy of ${FIXTURE} in a fresh folder (its working folder)
# exits 65 with an error located at FILE:LINE:COL (LINE:COL when
# NO_COLUMN is not set) whose text matches the fixture's first line
# (`% expect: REGEX`), and the fixture's side effect, a file named
# `marker` in that folder, did not happen. Standard input is a file that
# holds a term, so a rule that read it would find one rather than wait.
get_filename_component(name ${FIXTURE} NAME)
set(work ${WORK_DIR}/${name}.${MODE}.d)
file(REMOVE_RECURSE ${work})
file(MAKE_DIRECTORY ${work})
file(COPY ${FIXTURE} DESTINATION ${work})
file(WRITE ${work}/stdin.txt "read_me.\n")
file(STRINGS ${FIXTURE} first LIMIT_COUNT 1)
string(REGEX REPLACE "^% expect: " "" expect "${first}")
execute_process(COMMAND ${STRATA} ${MODE} ${name}
                WORKING_DIRECTORY ${work}
                INPUT_FILE ${work}/stdin.txt
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err
                TIMEOUT 30)
if(NOT rc EQUAL 65)
  message(FATAL_ERROR "exit ${rc}, expected 65\nstdout:\n${out}\nstderr:\n${err}")
endif()
if(DEFINED NO_COLUMN)
  set(place "${name}:[0-9]+(:[0-9]+)?: error: ")
else()
  set(place "${name}:[0-9]+:[0-9]+: error: ")
endif()
if(NOT err MATCHES "${place}[^\n]*${expect}")
  message(FATAL_ERROR "stderr has no '${place}...${expect}':\n${err}")
endif()
if(EXISTS ${work}/marker)
  message(FATAL_ERROR "the side effect happened: ${work}/marker exists")
endif()
file(REMOVE_RECURSE ${work})

# A strata whose studio HTTP module is missing (src/studio/http_module.h)
# says so, with where it looked, and exits 69; the other commands do not
# need it. Run with -DSTRATA= -DWORK_DIR= -DTANK=.
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR}/bin)
file(COPY ${STRATA} DESTINATION ${WORK_DIR}/bin)
set(strata ${WORK_DIR}/bin/strata)
file(MAKE_DIRECTORY ${WORK_DIR}/tmp)
execute_process(COMMAND ${CMAKE_COMMAND} -E env TMPDIR=${WORK_DIR}/tmp ${strata} studio ${WORK_DIR} --listen 127.0.0.1:0
                TIMEOUT 20 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 69 OR NOT err MATCHES "the studio's HTTP module libstrata_studio_http.so is missing \\(looked in [^)]*/bin/libstrata_studio_http.so, [^)]*/lib/strata/libstrata_studio_http.so\\)")
  message(FATAL_ERROR "strata studio without its module: exit ${rc}\n${out}${err}")
endif()
# The sonar folder it made for its runs went with it.
file(GLOB left ${WORK_DIR}/tmp/*)
if(left)
  message(FATAL_ERROR "strata studio without its module left ${left}")
endif()
execute_process(COMMAND ${strata} run ${TANK} --studio --listen 127.0.0.1:0 --speed 1000 TIMEOUT 20
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 69 OR NOT err MATCHES "strata run: --studio: the studio's HTTP module")
  message(FATAL_ERROR "strata run --studio without the module: exit ${rc}\n${out}${err}")
endif()
execute_process(COMMAND ${strata} run ${TANK} TIMEOUT 60 RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "completed")
  message(FATAL_ERROR "strata run without the studio module: exit ${rc}\n${out}${err}")
endif()
file(REMOVE_RECURSE ${WORK_DIR})

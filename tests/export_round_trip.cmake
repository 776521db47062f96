# `strata export --pnml` of the tank mission into a folder, then each file
# read back by `strata verify --pnml`: one file per net, each a P/T net
# Strata reads, with the reachable markings of the analysis net (no exits
# end a run there, so the counts are at least those of `strata verify`).
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${STRATA} export --pnml ${TANK} -o ${OUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "export: exit ${rc}\n${err}")
endif()
foreach(net initialize dive_from_surface submerge_to_depth return_to_surface tank)
  if(NOT EXISTS ${OUT}/${net}.pnml)
    message(FATAL_ERROR "no ${OUT}/${net}.pnml; export said:\n${err}")
  endif()
  execute_process(COMMAND ${STRATA} verify --pnml ${OUT}/${net}.pnml --format json
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\"one_safe\": true")
    message(FATAL_ERROR "verify --pnml ${net}.pnml: exit ${rc}\n${out}\n${err}")
  endif()
endforeach()
execute_process(COMMAND ${STRATA} export --dot ${TANK} --net dive_from_surface
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^digraph \"dive_from_surface\" {.*label=\"check_depth\\\\nASK depth_reached\"")
  message(FATAL_ERROR "export --dot: exit ${rc}\n${out}\n${err}")
endif()
file(REMOVE_RECURSE ${OUT})

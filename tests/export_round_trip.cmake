# `strata export --pnml` of a mission (the tank mission, or any given as
# TANK with its NETS, and the net and label pattern DOT_NET, DOT_MATCH the
# DOT export must show; NETS separated by commas) into a folder, then each file
# read back by `strata verify --pnml`: one file per net, each a P/T net
# Strata reads, with the reachable markings of the analysis net (no exits
# end a run there, so the counts are at least those of `strata verify`).
if(NOT DEFINED NETS)
  set(NETS initialize dive_from_surface submerge_to_depth return_to_surface tank)
endif()
string(REPLACE "," ";" NETS "${NETS}")
if(NOT DEFINED DOT_NET)
  set(DOT_NET dive_from_surface)
  set(DOT_MATCH "label=\"check_depth\\\\nASK depth_reached\"")
endif()
file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${STRATA} export --pnml ${TANK} -o ${OUT}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "export: exit ${rc}\n${err}")
endif()
foreach(net ${NETS})
  if(NOT EXISTS ${OUT}/${net}.pnml)
    message(FATAL_ERROR "no ${OUT}/${net}.pnml; export said:\n${err}")
  endif()
  execute_process(COMMAND ${STRATA} verify --pnml ${OUT}/${net}.pnml --format json
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "\"one_safe\": true")
    message(FATAL_ERROR "verify --pnml ${net}.pnml: exit ${rc}\n${out}\n${err}")
  endif()
endforeach()
execute_process(COMMAND ${STRATA} export --dot ${TANK} --net ${DOT_NET}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^digraph \"${DOT_NET}\" {.*${DOT_MATCH}")
  message(FATAL_ERROR "export --dot: exit ${rc}\n${out}\n${err}")
endif()
file(REMOVE_RECURSE ${OUT})

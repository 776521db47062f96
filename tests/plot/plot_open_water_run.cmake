# A real open-water run (tests/run/open_water_leg.coral: a 60 m track line)
# logged by `strata run` and drawn by `strata plot`: the SVG has the x-y
# panel with the estimated and true tracks and the planned line, and the
# altitude panel. Keeps the plot honest about the log strata writes today,
# not only about the fixture. Skipped without gnuplot.
include(${CMAKE_CURRENT_LIST_DIR}/needs_gnuplot.cmake)
strata_plot_needs_gnuplot()
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
execute_process(COMMAND ${STRATA} run ${RUN}/open_water_leg.coral --scenario ${RUN}/open_water_leg.toml
                        --log ${OUT}/leg.jsonl
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "strata run: exit ${rc}\n${out}\n${err}")
endif()
execute_process(COMMAND ${STRATA} plot ${OUT}/leg.jsonl -o ${OUT}/leg.svg
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT err STREQUAL "wrote ${OUT}/leg.svg\n")
  message(FATAL_ERROR "strata plot: exit ${rc}; expected only 'wrote', got:\n${err}")
endif()
file(READ ${OUT}/leg.svg svg)
foreach(text "<text>x east [(]m[)]</text>" "<text>y north [(]m[)]</text>" "<text>estimated track</text>"
             "<text>true track</text>" "<text>planned track</text>" "<text>waypoint</text>"
             "<text>altitude [(]m[)]</text>" "<text>seabed [(]depth [+] altitude[)]</text>")
  if(NOT svg MATCHES "${text}")
    message(FATAL_ERROR "${OUT}/leg.svg has no '${text}'")
  endif()
endforeach()
file(REMOVE_RECURSE ${OUT})

# `strata plot` of a log someone else wrote: a net name with a newline in it
# ended gnuplot's `set label` line, and the rest of the name ran as a
# gnuplot command (`print system("...")`). Now the picture is drawn and the
# command never runs. Skipped without gnuplot.
include(${CMAKE_CURRENT_LIST_DIR}/needs_gnuplot.cmake)
strata_plot_needs_gnuplot()
file(REMOVE_RECURSE ${OUT})
file(MAKE_DIRECTORY ${OUT})
file(READ ${LOG} log)
string(REPLACE "\"net\":\"initialize\"" "\"net\":\"x\\nprint system(\\\"touch ${OUT}/ran\\\")\\n#\"" evil "${log}")
if(evil STREQUAL log)
  message(FATAL_ERROR "the fixture ${LOG} has no phase 'initialize' to rename")
endif()
file(WRITE ${OUT}/evil.jsonl "${evil}")
execute_process(COMMAND ${STRATA} plot ${OUT}/evil.jsonl -o ${OUT}/evil.svg
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err TIMEOUT 60)
if(NOT rc EQUAL 0 OR NOT EXISTS ${OUT}/evil.svg)
  message(FATAL_ERROR "strata plot: exit ${rc}\n${out}\n${err}")
endif()
if(EXISTS ${OUT}/ran)
  message(FATAL_ERROR "the log's net name ran a command in gnuplot")
endif()
file(REMOVE_RECURSE ${OUT})

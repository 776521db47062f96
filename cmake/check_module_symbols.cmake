# After strata links: every Strata symbol the studio's HTTP module
# (src/studio/http_module.h) leaves undefined must be one strata exports,
# or `strata studio` would fail to load it. Run with -DEXE= -DMODULE= -DNM=.
execute_process(COMMAND ${NM} -D --undefined-only ${MODULE} OUTPUT_VARIABLE undefined RESULT_VARIABLE r1)
execute_process(COMMAND ${NM} -D --defined-only ${EXE} OUTPUT_VARIABLE defined RESULT_VARIABLE r2)
if(NOT r1 EQUAL 0 OR NOT r2 EQUAL 0)
  message(FATAL_ERROR "check_module_symbols: nm failed on ${MODULE} or ${EXE}")
endif()
string(REGEX MATCHALL "_Z[A-Za-z0-9_]*6strata[A-Za-z0-9_]*" needed "${undefined}")
list(REMOVE_DUPLICATES needed)
set(missing "")
foreach(sym IN LISTS needed)
  string(FIND "${defined}" " ${sym}\n" at)
  if(at EQUAL -1)
    list(APPEND missing ${sym})
  endif()
endforeach()
if(missing)
  list(JOIN missing "\n  " text)
  message(FATAL_ERROR "the studio's HTTP module needs Strata symbols that strata does not have (link their library "
                      "whole into strata: src/cli/CMakeLists.txt):\n  ${text}")
endif()

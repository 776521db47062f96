# layers.dependencies_detects_a_back_edge: scripts/check-layers (${SCRIPT},
# run by ${PYTHON}) over a tiny tree written under ${WORK}. The tree first
# keeps the layers (exit 0; a test's include of the vehicle is allowed), then
# gets two back-edges planted, tactical -> coral by an #include and by
# target_link_libraries: exit 1, each named with its file:line.
file(REMOVE_RECURSE "${WORK}")
file(WRITE "${WORK}/src/core/CMakeLists.txt" "add_library(strata_core diagnostic.cpp)\n")
file(WRITE "${WORK}/src/core/diagnostic.h" "#pragma once\n")
file(WRITE "${WORK}/src/coral/CMakeLists.txt" "add_library(strata_coral parser.cpp)\ntarget_link_libraries(strata_coral PUBLIC strata_core)\n")
file(WRITE "${WORK}/src/coral/ast.h" "#pragma once\n#include \"core/diagnostic.h\"\n")
file(WRITE "${WORK}/src/protocol/CMakeLists.txt" "add_library(strata_protocol codec.cpp)\n")
file(WRITE "${WORK}/src/protocol/codec.h" "#pragma once\n")
file(WRITE "${WORK}/src/vehicle/CMakeLists.txt" "add_library(strata_vehicle server.cpp)\n")
file(WRITE "${WORK}/src/vehicle/server.h" "#pragma once\n#include \"protocol/codec.h\"\n")
file(WRITE "${WORK}/src/tactical/CMakeLists.txt"
     "add_library(strata_tactical value.cpp)\n"
     "target_link_libraries(strata_tactical\n"
     "  PUBLIC strata_core strata_protocol)\n"
     "add_executable(vehicle_link_test vehicle_link_test.cpp)\n"
     "target_link_libraries(vehicle_link_test PRIVATE strata_tactical strata_vehicle)\n")
file(WRITE "${WORK}/src/tactical/value.h" "#pragma once\n#include \"core/diagnostic.h\"\n#include <string>\n")
file(WRITE "${WORK}/src/tactical/vehicle_link_test.cpp" "#include \"tactical/value.h\"\n#include \"vehicle/server.h\"\n")

execute_process(COMMAND "${PYTHON}" "${SCRIPT}" "${WORK}/src"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "the tree without back-edges: exit ${rc}, expected 0\n${out}${err}")
endif()

# The planted back-edges: tactical includes the CORAL AST and links strata_coral.
file(WRITE "${WORK}/src/tactical/value.h"
     "#pragma once\n#include \"core/diagnostic.h\"\n#include \"coral/ast.h\"\n")
file(WRITE "${WORK}/src/tactical/CMakeLists.txt"
     "add_library(strata_tactical value.cpp)\n"
     "target_link_libraries(strata_tactical\n"
     "  PUBLIC strata_core strata_coral strata_protocol)\n"
     "add_executable(vehicle_link_test vehicle_link_test.cpp)\n"
     "target_link_libraries(vehicle_link_test PRIVATE strata_tactical strata_vehicle)\n")
execute_process(COMMAND "${PYTHON}" "${SCRIPT}" "${WORK}/src"
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
message(STATUS "check-layers on the planted back-edges (exit ${rc}):\n${out}${err}")
if(NOT rc EQUAL 1)
  message(FATAL_ERROR "exit ${rc}, expected 1")
endif()
set(expected
    "src/tactical/CMakeLists.txt:3: tactical -> coral: target_link_libraries(strata_tactical ... strata_coral) (tactical may use: core, imc, protocol)\n"
    "src/tactical/value.h:3: tactical -> coral: #include \"coral/ast.h\" (tactical may use: core, imc, protocol)\n")
string(JOIN "" expected ${expected})
if(NOT out STREQUAL expected)
  message(FATAL_ERROR "stdout is not the two planted edges; expected:\n${expected}")
endif()

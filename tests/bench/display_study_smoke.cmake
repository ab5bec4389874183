# Smoke test of build/penumbra-display-study on the 992-triangle floating teapot (not timed):
# fails when the driver fails, its JSON is missing, either mesh is empty, or a sample point
# falls outside either mesh's triangles (the errors would then leave part of the floor out).
# cmake -DBENCH=… -DOUT=… -P this file.
include("${CMAKE_CURRENT_LIST_DIR}/bench_outputs.cmake")
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
execute_process(COMMAND "${BENCH}" --model teapot --triangles 1000 --samples 2000 --json "${OUT}/study.json"
                RESULT_VARIABLE result OUTPUT_QUIET ERROR_QUIET)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "penumbra-display-study exited with ${result}")
endif()
require_outputs("${OUT}" study.json)
file(READ "${OUT}/study.json" json)
foreach(mesh product study)
  string(JSON vertices GET "${json}" ${mesh} vertices)
  string(JSON missing GET "${json}" ${mesh} errors missing)
  string(JSON type TYPE "${json}" ${mesh} errors worst)
  if(vertices LESS 100 OR NOT missing EQUAL 0 OR NOT type STREQUAL "NUMBER")
    message(FATAL_ERROR "${mesh}: ${vertices} vertices, ${missing} samples outside its triangles, worst error ${type}")
  endif()
endforeach()
string(JSON evaluations GET "${json}" study evaluations)
if(evaluations LESS 100)
  message(FATAL_ERROR "the study mesh took ${evaluations} evaluations")
endif()

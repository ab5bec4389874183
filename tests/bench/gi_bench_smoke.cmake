# Smoke test of build/penumbra-gi-bench --quick (not timed): fails when the driver fails, the
# report or JSON is missing, or an error figure in the JSON is not a finite number.
# cmake -DBENCH=… -DOUT=… -P this file.
include("${CMAKE_CURRENT_LIST_DIR}/bench_outputs.cmake")
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
execute_process(COMMAND "${BENCH}" --quick --html "${OUT}/gi.html" --json "${OUT}/gi.json"
                RESULT_VARIABLE result OUTPUT_QUIET)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "penumbra-gi-bench exited with ${result}")
endif()
require_outputs("${OUT}" gi.html gi.json)
file(READ "${OUT}/gi.json" json)
foreach(ladder by_sensor_size path_tracer)
  require_finite_ladder("${json}" ${ladder} 1 seconds rms_error)
endforeach()

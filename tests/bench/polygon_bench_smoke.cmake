# Smoke test of build/penumbra-polygon-bench on a small dense room (not timed): fails when the
# driver fails, its JSON is missing, a time is not a finite number, or the engine's kernel is
# off the exact reference beyond 1e-9 at any sampled vertex (Boost.Geometry's count is
# reported, not required: it is what the comparison measures).
# cmake -DBENCH=… -DOUT=… -P this file.
include("${CMAKE_CURRENT_LIST_DIR}/bench_outputs.cmake")
file(REMOVE_RECURSE "${OUT}")
file(MAKE_DIRECTORY "${OUT}")
execute_process(COMMAND "${BENCH}" --cubes 15 --samples 200 --json "${OUT}/polygon.json"
                RESULT_VARIABLE result OUTPUT_QUIET ERROR_QUIET)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "penumbra-polygon-bench exited with ${result}")
endif()
require_outputs("${OUT}" polygon.json)
file(READ "${OUT}/polygon.json" json)
foreach(kernel ours boost_geometry reference)
  string(JSON type TYPE "${json}" ${kernel} seconds_per_vertex)
  if(NOT type STREQUAL "NUMBER")
    message(FATAL_ERROR "${kernel}.seconds_per_vertex is ${type}, not a finite number")
  endif()
endforeach()
string(JSON samples GET "${json}" samples)
string(JSON beyond GET "${json}" ours beyond_1e-9)
if(samples LESS 50 OR NOT beyond EQUAL 0)
  message(FATAL_ERROR "${samples} samples, ${beyond} of the engine's values off the reference beyond 1e-9")
endif()

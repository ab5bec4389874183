# Smoke test of build/penumbra-microfacet-bench (not timed): a tiny image, few samples; fails
# when the driver fails, an output is missing or empty, or a number in its JSON is not finite.
# cmake -DBENCH=… -DOUT=… -P this file.
include("${CMAKE_CURRENT_LIST_DIR}/bench_outputs.cmake")
file(REMOVE_RECURSE "${OUT}")
execute_process(COMMAND "${BENCH}" --width 40 --height 30 --dm-samples 1,4 --sr-samples 1,4,16
                        --reference-samples 64 --min-seconds 0 --reference-threads 1 --out-dir "${OUT}"
                RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "penumbra-microfacet-bench exited with ${result}")
endif()
require_outputs("${OUT}" report.html comparison.png comparison_middle.png dm.png shadow_rays.png reference.png
                dm_error.png shadow_rays_error.png error_vs_time.svg microfacet.json)
file(READ "${OUT}/microfacet.json" json)
foreach(ladder dm shadow_rays)
  require_finite_ladder("${json}" ${ladder} 2 seconds cpu_seconds relative_rms)
endforeach()
string(JSON type TYPE "${json}" reference relative_noise)
if(NOT type STREQUAL "NUMBER")
  message(FATAL_ERROR "reference noise is ${type}")
endif()

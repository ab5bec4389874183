# What the bench drivers' smoke tests check of their outputs (included by *_bench_smoke.cmake).

# Fails unless every named file exists in DIR and is not empty.
function(require_outputs dir)
  foreach(name ${ARGN})
    if(NOT EXISTS "${dir}/${name}")
      message(FATAL_ERROR "missing ${dir}/${name}")
    endif()
    file(SIZE "${dir}/${name}" size)
    if(size EQUAL 0)
      message(FATAL_ERROR "empty ${dir}/${name}")
    endif()
  endforeach()
endfunction()

# Fails unless the JSON array LADDER has at least MIN_RUNGS entries and each entry's KEYS are
# finite numbers (nlohmann::json writes NaN and infinities as null).
function(require_finite_ladder json ladder min_rungs)
  string(JSON rungs LENGTH "${json}" ${ladder})
  if(rungs LESS min_rungs)
    message(FATAL_ERROR "${ladder}: ${rungs} rungs")
  endif()
  math(EXPR last "${rungs} - 1")
  foreach(k RANGE ${last})
    foreach(key ${ARGN})
      string(JSON type TYPE "${json}" ${ladder} ${k} ${key})
      if(NOT type STREQUAL "NUMBER")
        message(FATAL_ERROR "${ladder}[${k}].${key} is ${type}, not a finite number")
      endif()
    endforeach()
  endforeach()
endfunction()

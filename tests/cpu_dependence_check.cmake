# Runs tools/cpu_dependence.sh on the engine plugins this build made and
# checks its verdicts: Embree's library may answer differently on another
# CPU; Bullet's, ODE's, OpenSceneGraph's and libccd's code is the same on
# every x86-64 CPU (a library whose package is not installed is not listed).
execute_process(COMMAND bash ${SCRIPT} ${MANIFEST} OUTPUT_VARIABLE out ERROR_VARIABLE err RESULT_VARIABLE rc)
message("${out}${err}")
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "tools/cpu_dependence.sh exited ${rc}")
endif()
string(REPLACE "\n" ";" lines "${out}")
set(previous "")
foreach(line IN LISTS lines)
  if(line MATCHES "^  -> may answer differently" AND NOT previous MATCHES "^libembree3")
    message(FATAL_ERROR "only Embree should hold code that depends on the CPU, not: ${previous}")
  endif()
  if(previous MATCHES "^libembree3" AND NOT line MATCHES "^  -> may answer differently on another CPU: it picks code by the CPU")
    message(FATAL_ERROR "Embree's library should be found to pick its code by the CPU: ${line}")
  endif()
  set(previous "${line}")
endforeach()
if(out MATCHES "libembree3" AND NOT out MATCHES "\n1 of [0-9]+ libraries hold code whose answers can depend on the CPU")
  message(FATAL_ERROR "expected exactly one such library (Embree)")
endif()

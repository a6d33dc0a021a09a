# Compiles tests/cuda/robust_kernel.cu for a GPU (sm_70) with clang in CUDA
# mode and no CUDA SDK, as CLARIFICATIONS ask, with warnings as errors; then
# checks the PTX: both kernels are there, and no function is left to an
# outside library (a host-only call such as std::sqrt would fail to compile;
# a libm call the device cannot resolve would show here as an .extern .func).
# Usage: cmake -DCLANG=… -DSOURCE_DIR=… -DPTX=… -P compile_kernel.cmake
execute_process(
  COMMAND ${CLANG} -x cuda --cuda-device-only -nocudainc -nocudalib --cuda-gpu-arch=sm_70 -std=c++17 -O2
          -Wall -Wextra -Werror -Wno-unknown-cuda-version -I${SOURCE_DIR}/src/intersectors
          -S ${SOURCE_DIR}/tests/cuda/robust_kernel.cu -o ${PTX}
  RESULT_VARIABLE result ERROR_VARIABLE errors OUTPUT_VARIABLE output)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "clang could not compile robust_sphere.h for the GPU (exit ${result}):\n${errors}${output}")
endif()
file(READ ${PTX} ptx)
foreach(kernel intersect_allIfE intersect_allIdE)
  if(NOT ptx MATCHES "\\.entry [^\n]*${kernel}")
    message(FATAL_ERROR "${PTX}: no kernel entry matching ${kernel}")
  endif()
endforeach()
if(ptx MATCHES "\\.extern \\.func")
  string(REGEX MATCHALL "\\.extern \\.func[^\n]*" externs "${ptx}")
  message(FATAL_ERROR "${PTX}: calls the device cannot resolve:\n${externs}")
endif()
string(LENGTH "${ptx}" bytes)
message(STATUS "robust_sphere.h: both kernels compiled to ${bytes} bytes of PTX for sm_70, no external call")

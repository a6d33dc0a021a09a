# CTest driver (cmake -P): install rayverify into a prefix inside the build
# tree, check the installed headers, then configure, build and run
# tests/consumer and the example plugin against it with find_package.
foreach(var RAYVERIFY_BUILD_DIR CONSUMER_SOURCE_DIR WORK_DIR CORPUS_DIR CXX_COMPILER C_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer_test.cmake: -D${var}=... is required")
  endif()
endforeach()

function(run step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT code EQUAL 0)
    message(FATAL_ERROR "${step} failed (${code}):\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
set(prefix ${WORK_DIR}/prefix)
run("install" ${CMAKE_COMMAND} --install ${RAYVERIFY_BUILD_DIR} --prefix ${prefix})

# No installed header may pull in CGAL, GMP or MPFR.
file(GLOB_RECURSE headers ${prefix}/include/rayverify/*.h)
foreach(header IN LISTS headers)
  file(STRINGS ${header} heavy REGEX "^[ \t]*#[ \t]*include[ \t]*<(CGAL/|gmp|mpfr)")
  if(heavy)
    message(FATAL_ERROR "installed header ${header} includes ${heavy}")
  endif()
endforeach()

run("configure consumer" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR} -B ${WORK_DIR}/build
    -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=RelWithDebInfo
    -DRAYVERIFY_CORPUS_DIR=${CORPUS_DIR}
    # Empty, or the sanitizers an instrumented rayverify was built with.
    "-DCMAKE_CXX_FLAGS=${CONSUMER_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${CONSUMER_FLAGS}")
run("build consumer" ${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run("run consumer" ${WORK_DIR}/build/consumer_test)
message(STATUS "${last_output}")

# Built with -mfma and the compiler's default contraction, the header
# intersectors give the library's answers bit for bit (the FP flags are usage
# requirements), and without those requirements they do not.
run("consumer flags" ${WORK_DIR}/build/consumer_flags)
message(STATUS "${last_output}")
run("consumer flags without the usage requirements" ${WORK_DIR}/build/consumer_flags_unguarded --unguarded)
message(STATUS "${last_output}")

# The installed CLI reads the installed corpus when given none, not the
# source tree it was built from.
run("installed default corpus" ${prefix}/bin/rayverify corpus regen --check)
if(NOT last_output MATCHES "${prefix}/share/rayverify/corpus/MANIFEST")
  message(FATAL_ERROR "installed rayverify did not default to its installed corpus:\n${last_output}")
endif()

# The installed CLI draws its plots with the installed script, from any directory.
file(MAKE_DIRECTORY ${WORK_DIR}/elsewhere)
execute_process(COMMAND ${prefix}/bin/rayverify audit --corpus ${CORPUS_DIR}/far_sphere.txt --variant naive
                        --report plotted --plots
                WORKING_DIRECTORY ${WORK_DIR}/elsewhere RESULT_VARIABLE code OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT code EQUAL 1 OR NOT EXISTS ${WORK_DIR}/elsewhere/plotted/ulp_histograms.png)
  message(FATAL_ERROR "installed audit --plots from another directory (${code}):\n${out}\n${err}")
endif()

# The example plugin on its own, against the installed rayverify::plugin_api,
# audited by the installed CLI. A plugin needs none of the library's
# dependencies: the plugin_api component is found with them all disabled.
run("configure example plugin" ${CMAKE_COMMAND} -S ${CONSUMER_SOURCE_DIR}/../../examples/plugin_rtg
    -B ${WORK_DIR}/plugin -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_C_COMPILER=${C_COMPILER}
    -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_DISABLE_FIND_PACKAGE_CGAL=ON -DCMAKE_DISABLE_FIND_PACKAGE_fmt=ON
    -DCMAKE_DISABLE_FIND_PACKAGE_nlohmann_json=ON -DCMAKE_DISABLE_FIND_PACKAGE_PNG=ON)
run("build example plugin" ${CMAKE_COMMAND} --build ${WORK_DIR}/plugin)
file(GLOB plugin ${WORK_DIR}/plugin/*rtg_sphere.so)
run("audit example plugin" ${prefix}/bin/rayverify audit --plugin ${plugin}
    --corpus ${CORPUS_DIR}/far_sphere.txt)
message(STATUS "${last_output}")

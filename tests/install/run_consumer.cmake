# ctest driver for tests/install (label `install`): installs the build tree BUILD_DIR into a fresh prefix under
# WORK_DIR, then configures, builds and runs the project in consumer/ against that prefix alone. Fails (non-zero
# exit of `cmake -P`) on the first step that does.
#   cmake -DBUILD_DIR=... -DWORK_DIR=... -DGENERATOR=... -DCXX_COMPILER=... [-DCONFIG=...] [-DSANITIZE=...]
#         [-DPYTHON=... -DPYTHON_DIR=...] -P run_consumer.cmake
# PYTHON, PYTHON_DIR: where the build has the Python module, the interpreter it is for and its install folder under
# the prefix: that python then imports vkvo from the prefix alone and lists the devices through it.
# SANITIZE: the build's VKVO_SANITIZE; its static libraries then need the sanitizer runtimes, so the consumer is
# compiled and linked with the same -fsanitize= list.
foreach(var BUILD_DIR WORK_DIR GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "run_consumer.cmake: ${var} is not set")
  endif()
endforeach()
if(NOT CONFIG)
  set(CONFIG Release)
endif()
set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(step name)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install test: ${name} failed (${rc}):\n${out}")
  endif()
  message(STATUS "install test: ${name}: ok")
  set(step_output "${out}" PARENT_SCOPE)
endfunction()

step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix} --config ${CONFIG})
# Only the fresh prefix may provide vkvo: no package registry, no build tree.
set(sanitizer_flags)
if(SANITIZE)
  set(sanitizer_flags "-DCMAKE_CXX_FLAGS=-fsanitize=${SANITIZE}" "-DCMAKE_EXE_LINKER_FLAGS=-fsanitize=${SANITIZE}")
endif()
step("configure the consumer" ${CMAKE_COMMAND} -S ${CMAKE_CURRENT_LIST_DIR}/consumer -B ${consumer_build}
     -G ${GENERATOR} -DCMAKE_BUILD_TYPE=${CONFIG} -DCMAKE_CXX_COMPILER=${CXX_COMPILER}
     -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF ${sanitizer_flags})
step("build the consumer" ${CMAKE_COMMAND} --build ${consumer_build} --config ${CONFIG})
find_program(consumer vkvo_consumer PATHS ${consumer_build} ${consumer_build}/${CONFIG} NO_DEFAULT_PATH REQUIRED)
step("run the consumer" ${consumer})
message(STATUS "${step_output}")
if(NOT step_output MATCHES "vkvo consumer: ok")
  message(FATAL_ERROR "install test: the consumer ran but did not report success:\n${step_output}")
endif()

if(PYTHON)
  set(module_dir ${prefix}/${PYTHON_DIR})
  step("import vkvo" ${CMAKE_COMMAND} -E env PYTHONPATH=${module_dir} PYTHONDONTWRITEBYTECODE=1
       ${PYTHON} -s -c [[
import pathlib, sys, vkvo
where = pathlib.Path(vkvo.__file__).resolve()
assert where.parent == pathlib.Path(sys.argv[1]).resolve(), f"vkvo imported from {where}"
print(f"vkvo python: ok, {len(vkvo.devices())} device(s), from {where}")
]] ${module_dir})
  message(STATUS "${step_output}")
  if(NOT step_output MATCHES "vkvo python: ok")
    message(FATAL_ERROR "install test: python imported vkvo but did not report success:\n${step_output}")
  endif()
endif()

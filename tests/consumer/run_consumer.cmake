# The `consumer` CTest test: install the build into a private prefix, bake a generated Cornell box with the
# build's own tools, configure and build tests/consumer against the prefix only (find_package(probebake)),
# and run it under the validation layer. -D: BUILD_DIR, WORK_DIR, SOURCE_DIR (tests/consumer), PROBEBAKE,
# MAKE_SCENE, GENERATOR.
function(step)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  message("${out}${err}")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "failed (${result}): ${ARGN}")
  endif()
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
step("${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
step("${MAKE_SCENE}" cornell -q -o "${WORK_DIR}/cornell.glb")
step("${PROBEBAKE}" bake "${WORK_DIR}/cornell.glb" --max-depth 2 -o "${WORK_DIR}/cornell.probes")
step("${CMAKE_COMMAND}" -S "${SOURCE_DIR}" -B "${WORK_DIR}/build" -G "${GENERATOR}" "-DCMAKE_PREFIX_PATH=${prefix}"
     -DCMAKE_BUILD_TYPE=Release)
step("${CMAKE_COMMAND}" --build "${WORK_DIR}/build")
step("${WORK_DIR}/build/consumer" "${WORK_DIR}/cornell.probes" --validation)

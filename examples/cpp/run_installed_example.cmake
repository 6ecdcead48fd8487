# ctest: install the library of BUILD_DIR into a fresh prefix under WORK_DIR,
# configure and build examples/cpp against that installed package only, run
# the example on INPUT and check its output. Variables: BUILD_DIR, SOURCE_DIR,
# WORK_DIR, INPUT, CXX_FLAGS, LINKER_FLAGS.
file(REMOVE_RECURSE "${WORK_DIR}")
function(run)
  execute_process(COMMAND ${ARGV} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT status EQUAL 0)
    message(FATAL_ERROR "failed (${status}): ${ARGV}\n${out}\n${err}")
  endif()
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

run(${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}/prefix" --component library)
foreach(f include/detexture/pipeline/remove_texture.h lib/cmake/detexture/detextureConfig.cmake)
  if(NOT EXISTS "${WORK_DIR}/prefix/${f}")
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()
run(${CMAKE_COMMAND} -S "${SOURCE_DIR}/examples/cpp" -B "${WORK_DIR}/build"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix"
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/build")
run("${WORK_DIR}/build/remove_texture_example" "${INPUT}" "${WORK_DIR}/out.ply" 2)
message(STATUS "${last_output}")
if(NOT last_output MATCHES "^20000 points, r = [0-9.e-]+: [1-9][0-9]* texture points")
  message(FATAL_ERROR "unexpected output: ${last_output}")
endif()
if(NOT EXISTS "${WORK_DIR}/out.ply")
  message(FATAL_ERROR "the example wrote no ${WORK_DIR}/out.ply")
endif()
file(READ "${WORK_DIR}/out.ply" header LIMIT 1000)
string(REGEX REPLACE "end_header.*" "" header "${header}")
if(NOT header MATCHES "property uchar texture\n" OR NOT header MATCHES "property float texture_height\n")
  message(FATAL_ERROR "out.ply lacks the texture fields:\n${header}")
endif()

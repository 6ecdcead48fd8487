# ctest: install the library of BUILD_DIR into a fresh prefix under WORK_DIR,
# configure and build examples/cpp against that installed package only, run
# the example on INPUT and check its output; then the same for the README's
# "C++ library" snippet (its cmake and cpp blocks, as printed). Variables: BUILD_DIR, SOURCE_DIR,
# WORK_DIR, INPUT, CXX_FLAGS, LINKER_FLAGS, LAUNCHER (the compiler launcher of
# the main build, ccache, if any: the examples are configured from scratch
# every time, their compiles need not be).
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
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}"
    "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
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

# The README's snippet: the first ```cmake and ```cpp blocks of "## C++ library".
file(READ "${SOURCE_DIR}/README.md" readme)
string(FIND "${readme}" "\n## C++ library\n" start)
if(start LESS 0)
  message(FATAL_ERROR "README.md has no '## C++ library' section")
endif()
string(SUBSTRING "${readme}" ${start} -1 section)
function(code_block language out)
  string(FIND "${section}" "```${language}\n" begin)
  if(begin LESS 0)
    message(FATAL_ERROR "no ${language} block in README's C++ library section")
  endif()
  string(LENGTH "```${language}\n" skip)
  math(EXPR begin "${begin} + ${skip}")
  string(SUBSTRING "${section}" ${begin} -1 rest)
  string(FIND "${rest}" "```" end)
  string(SUBSTRING "${rest}" 0 ${end} code)
  set(${out} "${code}" PARENT_SCOPE)
endfunction()
code_block(cmake cmake_text)
code_block(cpp cpp_text)
file(WRITE "${WORK_DIR}/readme_app/CMakeLists.txt" "${cmake_text}")
file(WRITE "${WORK_DIR}/readme_app/main.cpp" "${cpp_text}")
run(${CMAKE_COMMAND} -S "${WORK_DIR}/readme_app" -B "${WORK_DIR}/readme_build"
    -DCMAKE_BUILD_TYPE=Release "-DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix"
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" "-DCMAKE_EXE_LINKER_FLAGS=${LINKER_FLAGS}"
    "-DCMAKE_CXX_COMPILER_LAUNCHER=${LAUNCHER}")
run(${CMAKE_COMMAND} --build "${WORK_DIR}/readme_build")
run("${WORK_DIR}/readme_build/my_app" "${INPUT}" "${WORK_DIR}/readme_out.ply")
if(NOT last_output MATCHES "^[1-9][0-9]* texture points\n$")
  message(FATAL_ERROR "the README snippet printed: ${last_output}")
endif()

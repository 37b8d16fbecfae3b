# The layer rules (cmake/GonioLayers.cmake) fail a real build: a copy of the
# fixture project builds as it is, then with low/low.cpp including a header
# of high/ it must fail naming the file, the line and the rule, and build
# again once the include is gone.
#   cmake -DGONIO_CMAKE_DIR=... -DFIXTURE=... -DWORK=... -P layers_test.cmake
file(REMOVE_RECURSE "${WORK}")
file(COPY "${FIXTURE}/" DESTINATION "${WORK}/src")

function(build expect_ok what)
  execute_process(
    COMMAND "${CMAKE_COMMAND}" -S "${WORK}/src" -B "${WORK}/build" -G Ninja
            "-DGONIO_CMAKE_DIR=${GONIO_CMAKE_DIR}"
    RESULT_VARIABLE configured OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT configured EQUAL 0)
    message(FATAL_ERROR "the fixture did not configure:\n${out}")
  endif()
  execute_process(COMMAND "${CMAKE_COMMAND}" --build "${WORK}/build"
    RESULT_VARIABLE built OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(expect_ok AND NOT built EQUAL 0)
    message(FATAL_ERROR "${what}: the build failed:\n${out}${err}")
  endif()
  if(NOT expect_ok AND built EQUAL 0)
    message(FATAL_ERROR "${what}: the build succeeded")
  endif()
  set(output "${out}${err}" PARENT_SCOPE)
endfunction()

build(TRUE "as it is")

file(READ "${WORK}/src/low/low.cpp" original)
file(WRITE "${WORK}/src/low/low.cpp" "${original}#include \"high/high.h\"\n")
build(FALSE "low/low.cpp including high/high.h")
string(REGEX REPLACE "[ \n]+" " " flat "${output}")
if(NOT flat MATCHES "low/low.cpp:4: includes \"high/high.h\"; low/ may include only low, gonio")
  message(FATAL_ERROR "the failure does not name the file, the line and the rule:\n${output}")
endif()

file(WRITE "${WORK}/src/low/low.cpp" "${original}")
build(TRUE "with the include removed again")
message(STATUS "layers: a wrong include fails the build and names low/low.cpp:4")

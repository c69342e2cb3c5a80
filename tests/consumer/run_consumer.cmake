# Builds and runs a small consumer project against geovoronoi, either through find_package after an
# install into a temporary prefix, or through add_subdirectory of the source tree.
file(REMOVE_RECURSE ${WORK_DIR})
set(consumer_src ${CMAKE_CURRENT_LIST_DIR}/${MODE})
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}")
  endif()
endfunction()
set(common -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release)
if(MODE STREQUAL "find_package")
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/lib-build ${common} -DGEOVORONOI_BUILD_TESTS=OFF
      -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_CUDA=OFF
      -DCMAKE_INSTALL_PREFIX=${WORK_DIR}/prefix)
  run(${CMAKE_COMMAND} --build ${WORK_DIR}/lib-build)
  run(${CMAKE_COMMAND} --install ${WORK_DIR}/lib-build)
  run(${CMAKE_COMMAND} -S ${consumer_src} -B ${WORK_DIR}/build ${common} -DCMAKE_PREFIX_PATH=${WORK_DIR}/prefix)
else()
  run(${CMAKE_COMMAND} -S ${consumer_src} -B ${WORK_DIR}/build ${common} -DGEOVORONOI_SOURCE_DIR=${SOURCE_DIR})
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
message(STATUS "consumer (${MODE}) built and ran")

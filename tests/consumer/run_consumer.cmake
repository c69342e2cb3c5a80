# Builds and runs small consumer projects against geovoronoi, either through find_package after an
# install into a temporary prefix, or through add_subdirectory of the source tree (cmake -P):
#   -DSOURCE_DIR -DWORK_DIR -DMODE=find_package|add_subdirectory -DGENERATOR -DCXX
#   -DBACKENDS=a,b (thrust_omp, thrust_cpp, cuda) -DEXPECT_ZLIB=0|1 -DEXPECT_PNG=0|1
#   [-DCUDA_COMPILER=nvcc -DCUDA_ARCH=80]
# The CUDA consumer is compiled and linked, and run only where it finds a device (exit 77 otherwise).
cmake_minimum_required(VERSION 3.25)
file(REMOVE_RECURSE ${WORK_DIR})
set(consumer_src ${CMAKE_CURRENT_LIST_DIR}/${MODE})
string(REPLACE "," ";" BACKENDS "${BACKENDS}")
function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "command failed (${rc}): ${ARGN}\n${out}")
  endif()
  message(STATUS "${out}")
endfunction()
set(common -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX} -DCMAKE_BUILD_TYPE=Release)
if(cuda IN_LIST BACKENDS)
  list(APPEND common -DCMAKE_CUDA_COMPILER=${CUDA_COMPILER} -DCMAKE_CUDA_ARCHITECTURES=${CUDA_ARCH}
                     -DGEOVORONOI_CUDA_ARCHITECTURES=${CUDA_ARCH})
else()
  list(APPEND common -DGEOVORONOI_CUDA=OFF)
endif()
list(JOIN BACKENDS "," backends_arg)
set(consumer_args -DCONSUMER_BACKENDS=${backends_arg} -DCONSUMER_EXPECT_ZLIB=${EXPECT_ZLIB}
                  -DCONSUMER_EXPECT_PNG=${EXPECT_PNG})
if(MODE STREQUAL "find_package")
  # header-only: configure and install, nothing to build
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${WORK_DIR}/lib-build ${common} -DGEOVORONOI_BUILD_TESTS=OFF
      -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF
      -DCMAKE_INSTALL_PREFIX=${WORK_DIR}/prefix)
  run(${CMAKE_COMMAND} --install ${WORK_DIR}/lib-build)
  # relocatable: the consumer uses a moved copy of the installation
  file(RENAME ${WORK_DIR}/prefix ${WORK_DIR}/moved-prefix)
  file(REMOVE_RECURSE ${WORK_DIR}/lib-build)
  file(GLOB_RECURSE installed_cmake ${WORK_DIR}/moved-prefix/*.cmake)
  foreach(f IN LISTS installed_cmake)
    file(READ ${f} text)
    if(text MATCHES "/usr/local/cuda|${WORK_DIR}")
      message(FATAL_ERROR "${f} names an absolute path (${CMAKE_MATCH_0}): the package cannot move")
    endif()
  endforeach()
  run(${CMAKE_COMMAND} -S ${consumer_src} -B ${WORK_DIR}/build ${common} ${consumer_args}
      -DCMAKE_PREFIX_PATH=${WORK_DIR}/moved-prefix)
else()
  run(${CMAKE_COMMAND} -S ${consumer_src} -B ${WORK_DIR}/build ${common} ${consumer_args}
      -DGEOVORONOI_SOURCE_DIR=${SOURCE_DIR} -DGEOVORONOI_BUILD_TESTS=OFF)
endif()
run(${CMAKE_COMMAND} --build ${WORK_DIR}/build)
run(${WORK_DIR}/build/consumer)
foreach(system omp cpp)
  if(thrust_${system} IN_LIST BACKENDS)
    run(${WORK_DIR}/build/consumer_thrust_${system})
  endif()
endforeach()
if(cuda IN_LIST BACKENDS)
  execute_process(COMMAND ${WORK_DIR}/build/consumer_cuda RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT (rc EQUAL 0 OR rc EQUAL 77))
    message(FATAL_ERROR "consumer_cuda failed (${rc}):\n${out}")
  endif()
  message(STATUS "${out}")
endif()
message(STATUS "consumer (${MODE}; core ${BACKENDS}) built and ran")

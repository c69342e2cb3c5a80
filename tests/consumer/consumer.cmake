# The consumer programs, shared by the find_package and add_subdirectory projects. Expects:
#   CONSUMER_BACKENDS  comma-separated, the backend targets geovoronoi must provide besides the core: any of
#                      thrust_omp, thrust_cpp, cuda (each a configure error when missing)
#   CONSUMER_EXPECT_ZLIB, CONSUMER_EXPECT_PNG  0/1: what geovoronoi::geovoronoi must bring with it
# Only the geovoronoi targets are linked: every dependency must come through them.
string(REPLACE "," ";" CONSUMER_BACKENDS "${CONSUMER_BACKENDS}")
foreach(b IN LISTS CONSUMER_BACKENDS)
  if(NOT TARGET geovoronoi::${b})
    message(FATAL_ERROR "consumer: the package does not provide geovoronoi::${b}")
  endif()
endforeach()

add_executable(consumer ${CMAKE_CURRENT_LIST_DIR}/consumer.cpp)
target_link_libraries(consumer PRIVATE geovoronoi::geovoronoi)
target_compile_definitions(consumer PRIVATE CONSUMER_EXPECT_ZLIB=${CONSUMER_EXPECT_ZLIB}
                                            CONSUMER_EXPECT_PNG=${CONSUMER_EXPECT_PNG})
foreach(system omp cpp)
  if(thrust_${system} IN_LIST CONSUMER_BACKENDS)
    add_executable(consumer_thrust_${system} ${CMAKE_CURRENT_LIST_DIR}/consumer_thrust.cpp)
    target_link_libraries(consumer_thrust_${system} PRIVATE geovoronoi::thrust_${system})
  endif()
endforeach()
if(cuda IN_LIST CONSUMER_BACKENDS)
  add_executable(consumer_cuda ${CMAKE_CURRENT_LIST_DIR}/consumer_cuda.cu)
  target_link_libraries(consumer_cuda PRIVATE geovoronoi::cuda)
endif()

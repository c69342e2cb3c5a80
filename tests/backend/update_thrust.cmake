# The incremental update (update.hpp) with Thrust policies: the update runs the same host algorithm
# for every policy, and must equal the policy's own full solve bit for bit.
if(TARGET geovoronoi::thrust_omp AND GEOVORONOI_TEST_HOST_SUITES)
  geovoronoi_add_test(test_update_thrust_omp backend/update_thrust.cpp LIBS geovoronoi::thrust_omp)
  target_compile_definitions(test_update_thrust_omp PRIVATE GEOVORONOI_TEST_UPDATE_OMP=1)
endif()
if(TARGET geovoronoi::thrust_cpp AND GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS)
  geovoronoi_add_test(test_update_thrust_cpp backend/update_thrust.cpp LIBS geovoronoi::thrust_cpp)
endif()
# Shape functions after a change (shape_update.hpp) on the same policies, fewer cases.
if(TARGET geovoronoi::thrust_omp AND GEOVORONOI_TEST_HOST_SUITES)
  geovoronoi_add_test(test_shape_update_thrust_omp backend/shape_update_thrust.cpp LIBS geovoronoi::thrust_omp)
  target_compile_definitions(test_shape_update_thrust_omp PRIVATE GEOVORONOI_TEST_UPDATE_OMP=1)
endif()
if(TARGET geovoronoi::thrust_cpp AND GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS)
  geovoronoi_add_test(test_shape_update_thrust_cpp backend/shape_update_thrust.cpp LIBS geovoronoi::thrust_cpp)
endif()

# Shape functions after a change (shape_update.hpp) on a Thrust policy (OpenMP), fewer cases than seq:
# the rows are recomputed through the policy's host loops and solves. (The diagram's update itself is
# one host algorithm whatever the policy, tested with seq in tests/update.test.cpp; each Thrust
# system's full solve with parents is the backend suite's.)
if(TARGET geovoronoi::thrust_omp AND GEOVORONOI_TEST_HOST_SUITES)
  geovoronoi_add_test(test_shape_update_thrust_omp backend/shape_update_thrust.cpp LIBS geovoronoi::thrust_omp)
endif()

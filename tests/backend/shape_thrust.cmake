# The shape-function suite on the Thrust backend (OMP system), compared with seq bit for bit.
if(TARGET geovoronoi::thrust_omp AND GEOVORONOI_TEST_HOST_SUITES)
  geovoronoi_add_test(test_shape_thrust_omp backend/shape_thrust_omp.cpp LIBS geovoronoi::thrust_omp)
endif()

if(TARGET geovoronoi::thrust_omp)
  geovoronoi_add_bench(bench_shape_thrust_omp ${CMAKE_CURRENT_LIST_DIR}/thrust_omp.cpp LIBS geovoronoi::thrust_omp)
endif()

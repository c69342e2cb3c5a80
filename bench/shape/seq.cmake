geovoronoi_add_bench(bench_shape_seq ${CMAKE_CURRENT_LIST_DIR}/seq.cpp)

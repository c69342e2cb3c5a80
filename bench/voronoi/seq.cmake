# Sequential backend benchmark: bench_voronoi_seq (see bench/common.hpp for the case names).
geovoronoi_add_bench(bench_voronoi_seq ${CMAKE_CURRENT_LIST_DIR}/seq.cpp)

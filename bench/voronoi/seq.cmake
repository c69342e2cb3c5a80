# Sequential backend benchmark: bench_voronoi_seq (see bench/common.hpp for the case names).
geovoronoi_add_bench(bench_voronoi_seq $<TARGET_OBJECTS:bench_voronoi_main> $<TARGET_OBJECTS:bench_voronoi_seq_cases>)

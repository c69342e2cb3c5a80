# SOFA's std::set Dijkstra as the `sofa_set` baseline: bench_voronoi_sofa_set on its own, and
# bench_voronoi_cpu, which registers seq and sofa_set together so speed-ups come from one run.
geovoronoi_add_bench(bench_voronoi_sofa_set $<TARGET_OBJECTS:bench_voronoi_main>
                     $<TARGET_OBJECTS:bench_voronoi_sofa_set_cases>)

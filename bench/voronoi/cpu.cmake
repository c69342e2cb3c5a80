# bench_voronoi_cpu: the seq and sofa_set cases in one executable, so speed-ups come from one run.
geovoronoi_add_bench(bench_voronoi_cpu $<TARGET_OBJECTS:bench_voronoi_main> $<TARGET_OBJECTS:bench_voronoi_seq_cases>
                     $<TARGET_OBJECTS:bench_voronoi_sofa_set_cases>)
# one-off check (not timed): SOFA's set Dijkstra and the seq backend give bitwise-equal distances
if(GEOVORONOI_BUILD_TESTS)
  add_test(NAME bench_sofa_set_matches_seq COMMAND bench_voronoi_cpu --checks_only)
  set_tests_properties(bench_sofa_set_matches_seq PROPERTIES LABELS "bench" TIMEOUT 120)
endif()

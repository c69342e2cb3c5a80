# bench_voronoi_cpu: the seq and sofa_set cases in one executable (bench/voronoi/cpu.cpp holds main()).
geovoronoi_add_bench(bench_voronoi_cpu ${CMAKE_CURRENT_LIST_DIR}/cpu.cpp ${CMAKE_CURRENT_LIST_DIR}/seq.cpp
                     ${CMAKE_CURRENT_LIST_DIR}/sofa_set.cpp)
target_compile_definitions(bench_voronoi_cpu PRIVATE GEOVORONOI_BENCH_COMBINED)
# one-off check (not timed): SOFA's set Dijkstra and the seq backend give bitwise-equal distances
if(GEOVORONOI_BUILD_TESTS)
  add_test(NAME bench_sofa_set_matches_seq COMMAND bench_voronoi_cpu --checks_only)
  set_tests_properties(bench_sofa_set_matches_seq PROPERTIES LABELS "bench" TIMEOUT 120)
endif()

# Branching grids: bench_branching (seq, and thrust_omp in the same executable when it is built, so
# that ratios come from one run).
if(TARGET geovoronoi::thrust_omp)
  geovoronoi_add_bench(bench_branching ${CMAKE_CURRENT_LIST_DIR}/seq.cpp ${CMAKE_CURRENT_LIST_DIR}/thrust_omp.cpp
                       LIBS geovoronoi::thrust_omp)
  target_compile_definitions(bench_branching PRIVATE GEOVORONOI_BENCH_COMBINED)
else()
  geovoronoi_add_bench(bench_branching ${CMAKE_CURRENT_LIST_DIR}/seq.cpp)
endif()

# Thrust backend benchmarks. bench_voronoi_thrust: thrust_omp (and thrust_tbb) cases plus the seq cases (seq.cpp linked
# in) so that ratios come from one run. bench_voronoi_thrust_cuda: thrust_cuda cases plus seq (nvcc).
if(TARGET geovoronoi::thrust_omp)
  geovoronoi_add_bench(bench_voronoi_thrust ${CMAKE_CURRENT_LIST_DIR}/thrust.cpp ${CMAKE_CURRENT_LIST_DIR}/seq.cpp
                       LIBS geovoronoi::thrust_omp)
  target_compile_definitions(bench_voronoi_thrust PRIVATE GEOVORONOI_BENCH_COMBINED GEOVORONOI_BENCH_THRUST_OMP)
  if(TARGET geovoronoi::thrust_tbb)
    target_link_libraries(bench_voronoi_thrust PRIVATE TBB::tbb)
    target_compile_definitions(bench_voronoi_thrust PRIVATE GEOVORONOI_BENCH_THRUST_TBB)
  endif()
endif()
if(TARGET geovoronoi::thrust_cuda)
  set(_gv_cu ${CMAKE_CURRENT_BINARY_DIR}/thrust_cuda_bench.cu)
  file(CONFIGURE OUTPUT ${_gv_cu} CONTENT "#include \"${CMAKE_CURRENT_LIST_DIR}/thrust.cpp\"\n")
  geovoronoi_add_bench(bench_voronoi_thrust_cuda ${_gv_cu} $<TARGET_OBJECTS:bench_voronoi_seq_cases>
                       LIBS geovoronoi::thrust_cuda CUDA::cudart)
  target_compile_definitions(bench_voronoi_thrust_cuda PRIVATE GEOVORONOI_BENCH_COMBINED)
  set_target_properties(bench_voronoi_thrust_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
endif()

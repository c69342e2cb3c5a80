# CUDA kernel backend benchmark: bench_voronoi_cuda (nvcc; cases described in cuda.cu), and
# bench_voronoi_gpu_cpu: the same cases with the same-run seq and sofa_set references. The CUDA cases
# are compiled once for both.
if(GEOVORONOI_HAVE_CUDA)
  geovoronoi_add_bench_objects(bench_voronoi_cuda_cases ${CMAKE_CURRENT_LIST_DIR}/cuda.cu LIBS geovoronoi::cuda)
  set_target_properties(bench_voronoi_cuda_cases PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  target_compile_options(bench_voronoi_cuda_cases PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow>
                         $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
  geovoronoi_add_bench(bench_voronoi_cuda $<TARGET_OBJECTS:bench_voronoi_main> $<TARGET_OBJECTS:bench_voronoi_cuda_cases>
                       LIBS geovoronoi::cuda)
  set_target_properties(bench_voronoi_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}"
                        LINKER_LANGUAGE CUDA)
  geovoronoi_add_bench(bench_voronoi_gpu_cpu $<TARGET_OBJECTS:bench_voronoi_main> $<TARGET_OBJECTS:bench_voronoi_seq_cases>
                       $<TARGET_OBJECTS:bench_voronoi_sofa_set_cases> $<TARGET_OBJECTS:bench_voronoi_cuda_cases>
                       LIBS geovoronoi::cuda)
  set_target_properties(bench_voronoi_gpu_cpu PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}"
                        LINKER_LANGUAGE CUDA)
endif()

# CUDA kernel backend benchmark: bench_voronoi_cuda (nvcc; cases described in cuda.cu).
if(GEOVORONOI_HAVE_CUDA)
  geovoronoi_add_bench(bench_voronoi_cuda ${CMAKE_CURRENT_LIST_DIR}/cuda.cu LIBS geovoronoi::cuda)
  set_target_properties(bench_voronoi_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  target_compile_options(bench_voronoi_cuda PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow>
                         $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
  # the CUDA cases together with the same-run seq and sofa_set references (main() from cpu.cpp)
  geovoronoi_add_bench(bench_voronoi_gpu_cpu ${CMAKE_CURRENT_LIST_DIR}/cpu.cpp ${CMAKE_CURRENT_LIST_DIR}/seq.cpp
                       ${CMAKE_CURRENT_LIST_DIR}/sofa_set.cpp ${CMAKE_CURRENT_LIST_DIR}/cuda.cu LIBS geovoronoi::cuda)
  target_compile_definitions(bench_voronoi_gpu_cpu PRIVATE GEOVORONOI_BENCH_COMBINED)
  set_target_properties(bench_voronoi_gpu_cpu PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  target_compile_options(bench_voronoi_gpu_cpu PRIVATE $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow>
                         $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
endif()

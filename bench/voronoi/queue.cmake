geovoronoi_add_bench(bench_queue_ablation ${CMAKE_CURRENT_LIST_DIR}/queue.cpp)

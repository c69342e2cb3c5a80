# The sequential backend's sparse searches with pages of 16 to 128 voxels: bench_seq_sparse.
geovoronoi_add_bench(bench_seq_sparse ${CMAKE_CURRENT_LIST_DIR}/seq_sparse.cpp)
add_test(NAME bench_seq_sparse_page_sizes_agree COMMAND bench_seq_sparse --checks_only)

# The sequential backend's sparse searches, paged scratch vs hash map: bench_seq_sparse.
geovoronoi_add_bench(bench_seq_sparse ${CMAKE_CURRENT_LIST_DIR}/seq_sparse.cpp)
add_test(NAME bench_seq_sparse_paged_equals_hash COMMAND bench_seq_sparse --checks_only)

# The sequential backend's sparse searches on larger grids: paged scratch against an oracle, workspace reuse.
if(GEOVORONOI_TEST_HOST_SUITES)
  geovoronoi_add_test(test_backend_seq_sparse ${CMAKE_CURRENT_LIST_DIR}/seq_sparse.cpp)
endif()

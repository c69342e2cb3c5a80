# The Voronoi cases of each CPU backend, compiled once (object libraries, no main()) and linked into
# every executable that registers them; cpu.cpp holds the one main(). (Hooks are read in name order:
# this file comes first.)
geovoronoi_add_bench_objects(bench_voronoi_seq_cases ${CMAKE_CURRENT_LIST_DIR}/seq.cpp)
geovoronoi_add_bench_objects(bench_voronoi_sofa_set_cases ${CMAKE_CURRENT_LIST_DIR}/sofa_set.cpp)
add_library(bench_voronoi_main OBJECT ${CMAKE_CURRENT_LIST_DIR}/cpu.cpp)
target_include_directories(bench_voronoi_main PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
target_link_libraries(bench_voronoi_main PRIVATE benchmark::benchmark geovoronoi::geovoronoi geovoronoi_dev_options)

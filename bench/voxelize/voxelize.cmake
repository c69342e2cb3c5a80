# Mesh voxelizer: the row sweep on ~100k-triangle meshes onto 256^3, and a per-voxel ray-casting
# baseline (see voxelize.cpp).
geovoronoi_add_bench(bench_voxelize ${CMAKE_CURRENT_LIST_DIR}/voxelize.cpp)

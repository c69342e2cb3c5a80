// A user's program on geovoronoi::cuda: built (compiled by nvcc and linked) by the consumer tests;
// run only where a CUDA device exists, where it must give the sequential backend's diagram.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/cuda.cuh>

#include <cstdio>
#include <vector>

int main() {
  namespace gv = geovoronoi;
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) {
    std::printf("consumer (CUDA): no device, built only\n");
    return 77;
  }
  const gv::grid<3> g({9, 7, 5});
  const std::vector<float> stiffness(static_cast<std::size_t>(g.size()), 2.0f);
  const std::vector<gv::coord<3>> seeds{{0, 0, 0}, {8, 6, 4}};
  const auto a = gv::voronoi(gv::seq, g, stiffness, seeds, gv::uniform{}, gv::connectivity<6>{});
  const auto b = gv::voronoi(gv::cuda::par, g, stiffness, seeds, gv::uniform{}, gv::connectivity<6>{});
  const bool ok = a.distance.values() == b.distance.values() && a.label.values() == b.label.values();
  std::printf("consumer (CUDA): %s\n", ok ? "same as seq" : "DIFFERS from seq");
  return ok ? 0 : 1;
}

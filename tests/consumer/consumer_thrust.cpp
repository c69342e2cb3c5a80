// A user's program on a geovoronoi::thrust_<system> target (built once per system by consumer.cmake):
// the Thrust backend on that system must give the sequential backend's diagram bit for bit.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <cstdio>
#include <vector>

int main() {
  namespace gv = geovoronoi;
  const gv::grid<3> g({9, 7, 5}, {1.0, 0.5, 2.0});
  std::vector<float> stiffness(static_cast<std::size_t>(g.size()));
  for (std::size_t i = 0; i < stiffness.size(); ++i) stiffness[i] = 1.0f + float(i % 7);
  const std::vector<gv::coord<3>> seeds{{0, 0, 0}, {8, 6, 4}, {4, 3, 2}};
  const auto a = gv::voronoi(gv::seq, g, stiffness, seeds, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto b = gv::voronoi(gv::thrust::par, g, stiffness, seeds, gv::min_stiffness{}, gv::connectivity<26>{});
  const bool ok = a.distance.values() == b.distance.values() && a.label.values() == b.label.values();
  std::printf("consumer (Thrust, device system %d): %s\n", THRUST_DEVICE_SYSTEM, ok ? "same as seq" : "DIFFERS from seq");
  return ok ? 0 : 1;
}

// A user's program: compute a small diagram and check one value, exiting non-zero on failure.
#include <geovoronoi.hpp>

#include <cstdio>
#include <vector>

int main() {
  namespace gv = geovoronoi;
  const gv::grid<3> g({8, 8, 8});
  const std::vector<float> stiffness(static_cast<std::size_t>(g.size()), 1.0f);
  const auto d = gv::voronoi(gv::seq, g, stiffness, std::vector<gv::coord<3>>{{0, 0, 0}, {7, 7, 7}},
                             gv::uniform{}, gv::connectivity<6>{});
  const bool ok = d.distance({3, 0, 0}) == 3.0f && d.label({1, 1, 1}) == 0 && d.label({6, 6, 6}) == 1;
  std::printf("consumer: %s\n", ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}

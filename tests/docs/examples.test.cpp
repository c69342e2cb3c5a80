// The code samples of docs/, compiled and checked, so the documentation cannot rot silently.
#include <doctest/doctest.h>
#include <geovoronoi.hpp>

#include <cmath>

namespace {
// docs/policies.md, "Writing your own metric"
struct harmonic_stiffness {
  float rigid = 1.0e6f;
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T bu, T bv) const noexcept {
    return length * ((T(1) / bu + T(1) / bv) * T(0.5));
  }
  template <class T>
  GEOVORONOI_HOST_DEVICE static bool inside(T b) noexcept {
    return b > T(0) && b < T(1.0e6);
  }
};
}  // namespace

TEST_CASE("docs/policies.md: a user-defined metric") {
  namespace gv = geovoronoi;
  const gv::grid<3> g({32, 32, 32}, {0.5, 0.5, 1.0});
  auto stiffness = gv::phantom::gradient(g, 1.0f, 10.0f);
  const auto p = gv::make_problem(g, stiffness, harmonic_stiffness{}, gv::connectivity<18>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<3>>{{0, 0, 0}, {31, 31, 31}});
  CHECK(d.label({1, 1, 1}) == 0);
  CHECK(d.label({30, 30, 30}) == 1);
  // one face step along x from the seed: 0.5 * (1/b0 + 1/b1) / 2 * 0.5 (spacing), evaluated the same way
  const float b0 = stiffness({0, 0, 0}), b1 = stiffness({1, 0, 0});
  CHECK(d.distance({1, 0, 0}) == 0.5f * ((1.0f / b0 + 1.0f / b1) * 0.5f));
  // a rigid inclusion is an obstacle
  stiffness({5, 5, 5}) = 2.0e6f;
  const auto p2 = gv::make_problem(g, stiffness, harmonic_stiffness{}, gv::connectivity<18>{});
  const auto d2 = gv::voronoi(gv::seq, p2, std::vector<gv::coord<3>>{{0, 0, 0}});
  CHECK(d2.label({5, 5, 5}) == gv::no_label);
  CHECK(std::isinf(d2.distance({5, 5, 5})));
}

TEST_CASE("README: usage example") {
  namespace gv = geovoronoi;
  // --- README begin
  gv::grid<3> g({64, 48, 32}, {0.5, 0.5, 1.0});             // voxels, spacing (mm)
  auto stiffness = gv::phantom::steak(g);                   // or your own image / std::vector<float>
  auto problem = gv::make_problem(g, stiffness, gv::min_stiffness{}, gv::connectivity<26>{});
  auto nodes = gv::phantom::spread_seeds(stiffness, 8);     // voxel coordinates of the nodes
  auto diagram = gv::voronoi(gv::seq, problem, nodes);
  float d = diagram.distance({10, 20, 5});                  // geodesic distance to the nearest node
  int owner = diagram.label({10, 20, 5});                   // its index in `nodes`, -1 outside
  // --- README end
  CHECK(nodes.size() == 8);
  if (stiffness({10, 20, 5}) > 0) {
    CHECK(owner >= 0);
    CHECK(std::isfinite(d));
  } else {
    CHECK(owner == gv::no_label);
  }
  for (std::size_t i = 0; i < nodes.size(); ++i) CHECK(diagram.label(nodes[i]) == int(i));
}

TEST_CASE("docs/api.md: grid and orientation") {
  namespace gv = geovoronoi;
  const gv::index_t nx = 4, ny = 5, nz = 6;
  const double sx = 0.5, sy = 2.0, sz = 3.0, ox = 10.0, oy = 20.0, oz = 30.0;
  gv::grid<3> r({nx, ny, nz}, {sx, sy, sz}, {ox, oy, oz}, {0, -1, 0,  1, 0, 0,  0, 0, 1});
  // index x runs along world +y, index y along world -x
  CHECK(r.world({1, 0, 0}) == gv::point<3>{ox, oy + sx, oz});
  CHECK(r.world({0, 1, 0}) == gv::point<3>{ox - sy, oy, oz});
  CHECK(r.nearest_voxel({ox - sy, oy + sx, oz + sz}) == gv::coord<3>{1, 1, 1});
  CHECK_THROWS_AS(gv::grid<3>({nx, ny, nz}, {sx, sy, sz}, {ox, oy, oz}, {1, 0, 0, 1, 0, 0, 0, 0, 1}),
                  std::invalid_argument);
}

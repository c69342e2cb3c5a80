// Tests of geovoronoi/grid.hpp: validation (extents, spacing, origin, 64-bit overflow), the linear
// index layout (x fastest), index/coords and world/nearest_voxel round trips, contains, size,
// voxel_volume and equality.

#include <doctest/doctest.h>

#include <geovoronoi/grid.hpp>

#include "support/core_helpers.hpp"

#include <cmath>
#include <random>
#include <type_traits>

namespace {
namespace gv = geovoronoi;
using gvcore::inf_v;
using gvcore::nan_v;

static_assert(std::is_trivially_copyable_v<gv::grid<2>>, "grid<2> must be trivially copyable");
static_assert(std::is_trivially_copyable_v<gv::grid<3>>, "grid<3> must be trivially copyable");
static_assert(std::is_same_v<gv::coord<3>, std::array<gv::index_t, 3>>);
static_assert(std::is_same_v<gv::point<2>, std::array<double, 2>>);
static_assert(sizeof(gv::index_t) == 8 && std::is_signed_v<gv::index_t>);

TEST_CASE("grid: zero or negative extents are rejected, naming the axis") {
  GV_CHECK_INVALID(gv::grid<2>({0, 4}), "extent", "x");
  GV_CHECK_INVALID(gv::grid<2>({4, -1}), "extent", "y", "-1");
  GV_CHECK_INVALID(gv::grid<3>({4, 4, 0}), "extent", "z");
  GV_CHECK_INVALID(gv::grid<3>({-5, 4, 4}), "extent", "x");
  CHECK_NOTHROW(gv::grid<3>({1, 1, 1}));
}

TEST_CASE("grid: non-finite or non-positive spacing is rejected, naming the axis") {
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {0.0, 1.0}), "spacing", "x");
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1.0, -0.0}), "spacing", "y");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1.0, 1.0, -2.0}), "spacing", "z");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {nan_v<double>, 1.0, 1.0}), "spacing", "x");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1.0, inf_v<double>, 1.0}), "spacing", "y");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1.0, 1.0, -inf_v<double>}), "spacing", "z");
  CHECK_NOTHROW(gv::grid<3>({2, 2, 2}, {1e-300, 1.0, 3.5}));
}

TEST_CASE("grid: a non-finite origin is rejected") {
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1.0, 1.0}, {nan_v<double>, 0.0}), "origin", "x");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1.0, 1.0, 1.0}, {0.0, 0.0, inf_v<double>}), "origin", "z");
  CHECK_NOTHROW(gv::grid<3>({2, 2, 2}, {1.0, 1.0, 1.0}, {-1e9, 0.0, 3.0}));
}

TEST_CASE("grid: extents whose voxel count overflows 64 bits are rejected") {
  const gv::index_t big = gv::index_t(1) << 32;
  GV_CHECK_INVALID(gv::grid<3>({big, big, big}), "overflow");
  GV_CHECK_INVALID(gv::grid<2>({big, big}), "overflow");  // 2^64
  GV_CHECK_INVALID(gv::grid<3>({std::numeric_limits<gv::index_t>::max(), 2, 1}), "overflow");
  GV_CHECK_INVALID(gv::grid<3>({3, gv::index_t(1) << 62, 1}), "overflow");
  GV_CHECK_INVALID(gv::grid<3>({1, 1 << 22, gv::index_t(1) << 41}), "overflow");  // overflows at the last axis
}

TEST_CASE("grid: the largest representable voxel counts are accepted") {
  const gv::grid<2> a({gv::index_t(1) << 31, gv::index_t(1) << 31});  // 2^62
  CHECK(a.size() == gv::index_t(1) << 62);
  const gv::grid<3> b({std::numeric_limits<gv::index_t>::max(), 1, 1});
  CHECK(b.size() == std::numeric_limits<gv::index_t>::max());
  // 2^63 itself does not fit
  GV_CHECK_INVALID(gv::grid<2>({gv::index_t(1) << 31, gv::index_t(1) << 32}), "overflow");
}

TEST_CASE("grid: accessors, size and voxel volume") {
  const gv::grid<3> g({7, 5, 3}, {0.5, 2.0, 1.5}, {1.0, -2.0, 0.25});
  CHECK(g.size() == 105);
  CHECK(g.extent(0) == 7);
  CHECK(g.extent(1) == 5);
  CHECK(g.extent(2) == 3);
  CHECK(g.extents() == gv::coord<3>{7, 5, 3});
  CHECK(g.spacing(1) == 2.0);
  CHECK(g.spacing() == gv::point<3>{0.5, 2.0, 1.5});
  CHECK(g.origin() == gv::point<3>{1.0, -2.0, 0.25});
  CHECK(g.voxel_volume() == 1.5);
  CHECK(gv::grid<2>({3, 4}, {0.25, 3.0}).voxel_volume() == 0.75);
  CHECK(gv::grid<2>({3, 4}).voxel_volume() == 1.0);
  CHECK(gv::grid<2>({3, 4}).spacing() == gv::point<2>{1.0, 1.0});
  CHECK(gv::grid<2>({3, 4}).origin() == gv::point<2>{0.0, 0.0});
  CHECK(gv::grid<3>().size() == 0);
  CHECK(gv::grid<3>::dim == 3);
}

TEST_CASE("grid: x varies fastest") {
  const gv::grid<3> g({4, 3, 2});
  CHECK(g.index({0, 0, 0}) == 0);
  CHECK(g.index({1, 0, 0}) == 1);
  CHECK(g.index({0, 1, 0}) == 4);
  CHECK(g.index({0, 0, 1}) == 12);
  CHECK(g.index({3, 2, 1}) == 23);
  CHECK(g.coords(13) == gv::coord<3>{1, 0, 1});
  const gv::grid<2> h({5, 3});
  CHECK(h.index({4, 2}) == 14);
  CHECK(h.index({2, 1}) == 7);
  CHECK(h.coords(7) == gv::coord<2>{2, 1});
}

template <int Dim>
void index_round_trip(std::uint64_t seed, bool anisotropic) {
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<gv::index_t> ext(1, 3000);
  std::uniform_real_distribution<double> sp(0.01, 10.0), org(-100, 100);
  for (int t = 0; t < 50; ++t) {
    gv::coord<Dim> e{};
    gv::point<Dim> s{}, o{};
    for (int a = 0; a < Dim; ++a) {
      e[a] = ext(rng);
      s[a] = anisotropic ? sp(rng) : 1.0;
      o[a] = org(rng);
    }
    const gv::grid<Dim> g(e, s, o);
    gv::index_t expect_size = 1;
    for (int a = 0; a < Dim; ++a) expect_size *= e[a];
    CHECK(g.size() == expect_size);
    for (int k = 0; k < 50; ++k) {
      gv::coord<Dim> c{};
      for (int a = 0; a < Dim; ++a) c[a] = gv::index_t(rng() % std::uint64_t(e[a]));
      REQUIRE(g.contains(c));
      // the layout formula v = x + nx*(y + ny*z), written out here independently
      gv::index_t v = c[0] + e[0] * c[1];
      if constexpr (Dim == 3) v += e[0] * e[1] * c[2];
      CHECK(g.index(c) == v);
      CHECK(g.coords(v) == c);
      // world position: origin + c * spacing, and back
      const auto w = g.world(c);
      for (int a = 0; a < Dim; ++a) CHECK(w[a] == o[a] + double(c[a]) * s[a]);
      CHECK(g.nearest_voxel(w) == c);
      // a point within 0.45 voxel of the centre also maps back
      auto q = w;
      for (int a = 0; a < Dim; ++a) q[a] += (double(rng() % 91) / 100.0 - 0.45) * s[a];
      CHECK(g.nearest_voxel(q) == c);
    }
    // every linear index round-trips on small grids
    if (g.size() < 2000)
      for (gv::index_t v = 0; v < g.size(); ++v) CHECK(g.index(g.coords(v)) == v);
  }
}

TEST_CASE("grid: index/coords and world/nearest_voxel round trips, 2D and 3D, anisotropic") {
  index_round_trip<2>(1, false);
  index_round_trip<2>(2, true);
  index_round_trip<3>(3, false);
  index_round_trip<3>(4, true);
}

TEST_CASE("grid: contains") {
  const gv::grid<3> g({3, 4, 5});
  CHECK(g.contains({0, 0, 0}));
  CHECK(g.contains({2, 3, 4}));
  CHECK_FALSE(g.contains({3, 0, 0}));
  CHECK_FALSE(g.contains({0, 4, 0}));
  CHECK_FALSE(g.contains({0, 0, 5}));
  CHECK_FALSE(g.contains({-1, 0, 0}));
  CHECK_FALSE(g.contains({0, -1, 0}));
  CHECK_FALSE(g.contains({0, 0, -1}));
  CHECK_FALSE(g.contains({std::numeric_limits<gv::index_t>::min(), 0, 0}));
  const gv::grid<2> h({1, 1});
  CHECK(h.contains({0, 0}));
  CHECK_FALSE(h.contains({1, 0}));
  CHECK_FALSE(gv::grid<2>().contains({0, 0}));
}

TEST_CASE("grid: checked_nearest_voxel names the world point as given when its voxel is not in the grid") {
  const gv::grid<3> g({4, 5, 6}, {2.0, 0.5, 1.0}, {-1.0, 3.0, 0.0});
  CHECK(g.checked_nearest_voxel({1.0, 3.5, 5.0}) == gv::coord<3>{1, 1, 5});
  CHECK(g.checked_nearest_voxel({-2.0, 2.75, -0.5}) == gv::coord<3>{0, 0, 0});  // halves up, still inside
  auto message = [&](const gv::point<3>& p) {
    try {
      (void)g.checked_nearest_voxel(p);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("(no exception)");
  };
  // far outside: the point as given, never a clamped voxel such as (-1, 0, 0)
  std::string m = message({1e30, 3.0, 0.0});
  INFO(m);
  CHECK(m.find("world point (1e+30, 3, 0)") != std::string::npos);
  CHECK(m.find("outside the grid") != std::string::npos);
  CHECK(m.find("index 5e+29 along x") != std::string::npos);
  CHECK(m.find("(-1") == std::string::npos);
  m = message({0.0, 3.0, 1e300});
  CHECK(m.find("world point (0, 3, 1e+300)") != std::string::npos);
  CHECK(m.find("along z") != std::string::npos);
  m = message({nan_v<double>, 3.0, 0.0});
  CHECK(m.find("world point (nan, 3, 0)") != std::string::npos);
  CHECK(m.find("not a finite") != std::string::npos);
  m = message({0.0, -inf_v<double>, 0.0});
  CHECK(m.find("world point (0, -inf, 0)") != std::string::npos);
  // just outside: the voxel it would be, and the grid's range
  m = message({7.5, 3.0, 0.0});
  CHECK(m.find("world point (7.5, 3, 0)") != std::string::npos);
  CHECK(m.find("index 4 along x") != std::string::npos);
  CHECK(m.find("0 to 3") != std::string::npos);
  m = message({0.1, 3.0, 0.0});  // inside: no message
  CHECK(m == "(no exception)");
}

TEST_CASE("grid: nearest_voxel rounds halves up and flags non-finite points as outside") {
  const gv::grid<2> g({4, 4}, {2.0, 0.5}, {-1.0, 3.0});
  CHECK(g.nearest_voxel({0.0, 3.25}) == gv::coord<2>{1, 1});    // both exactly halfway
  CHECK(g.nearest_voxel({-2.0, 2.75}) == gv::coord<2>{0, 0});   // halfway below voxel 0
  CHECK(g.nearest_voxel({-2.01, 2.74}) == gv::coord<2>{-1, -1});
  CHECK(g.nearest_voxel({100.0, 3.0}) == gv::coord<2>{51, 0});  // outside, but still the nearest centre
  CHECK_FALSE(g.contains(g.nearest_voxel({nan_v<double>, 3.0})));
  CHECK_FALSE(g.contains(g.nearest_voxel({inf_v<double>, 3.0})));
  CHECK_FALSE(g.contains(g.nearest_voxel({-inf_v<double>, 3.0})));
  CHECK_FALSE(g.contains(g.nearest_voxel({0.0, 1e300})));
}

TEST_CASE("grid: equality compares extents, spacing and origin") {
  const gv::grid<3> a({3, 4, 5}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.0});
  CHECK(a == gv::grid<3>({3, 4, 5}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.0}));
  CHECK_FALSE(a != gv::grid<3>({3, 4, 5}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.0}));
  CHECK(a != gv::grid<3>({3, 4, 6}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.0}));
  CHECK(a != gv::grid<3>({3, 4, 5}, {1.0, 2.0, 3.5}, {0.0, 1.0, 2.0}));
  CHECK(a != gv::grid<3>({3, 4, 5}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.5}));
  CHECK(a != gv::grid<3>({5, 4, 3}, {1.0, 2.0, 3.0}, {0.0, 1.0, 2.0}));
  CHECK_FALSE(a == gv::grid<3>());
  const gv::grid<3> copy = a;
  CHECK(copy == a);
}

TEST_CASE("grid: to_string formats coordinates") {
  CHECK(gv::to_string<3>({1, -2, 30}) == "(1, -2, 30)");
  CHECK(gv::to_string<2>({0, 7}) == "(0, 7)");
}

}  // namespace

// ---- direction (orientation) -------------------------------------------------------------------

TEST_CASE("grid: the direction defaults to the identity and takes part in equality") {
  const gv::grid<3> g({4, 5, 6}, {1.0, 2.0, 3.0});
  CHECK(g.direction() == gv::direction_matrix<3>{1, 0, 0, 0, 1, 0, 0, 0, 1});
  CHECK(gv::grid<2>().direction() == gv::direction_matrix<2>{1, 0, 0, 1});
  const gv::grid<3> r({4, 5, 6}, {1.0, 2.0, 3.0}, {}, {0, -1, 0, 1, 0, 0, 0, 0, 1});
  CHECK(r.direction(0, 1) == -1.0);
  CHECK(r.direction(1, 0) == 1.0);
  CHECK(g != r);
  CHECK(r == gv::grid<3>({4, 5, 6}, {1.0, 2.0, 3.0}, {}, {0, -1, 0, 1, 0, 0, 0, 0, 1}));
}

TEST_CASE("grid: world <-> voxel with a 90 degree rotation about z") {
  // index axis x points along world +y, index axis y along world -x (column c = axis c's direction)
  const gv::grid<3> g({4, 5, 6}, {0.5, 2.0, 3.0}, {10.0, 20.0, 30.0}, {0, -1, 0, 1, 0, 0, 0, 0, 1});
  CHECK(g.world({0, 0, 0}) == gv::point<3>{10.0, 20.0, 30.0});
  CHECK(g.world({2, 0, 0}) == gv::point<3>{10.0, 21.0, 30.0});   // 2 * 0.5 along +y
  CHECK(g.world({0, 3, 0}) == gv::point<3>{4.0, 20.0, 30.0});    // 3 * 2.0 along -x
  CHECK(g.world({1, 1, 1}) == gv::point<3>{8.0, 20.5, 33.0});
  CHECK(g.nearest_voxel({10.0, 21.0, 30.0}) == gv::coord<3>{2, 0, 0});
  CHECK(g.nearest_voxel({4.0, 20.0, 30.0}) == gv::coord<3>{0, 3, 0});
  CHECK(g.nearest_voxel({8.1, 20.6, 33.4}) == gv::coord<3>{1, 1, 1});
  // the identity's answer would be a different (outside) voxel
  CHECK_FALSE(g.contains(gv::grid<3>({4, 5, 6}, {0.5, 2.0, 3.0}, {10.0, 20.0, 30.0}).nearest_voxel({4.0, 20.0, 30.0})));
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(g.nearest_voxel(g.world(g.coords(v))) == g.coords(v));

  const gv::grid<2> h({3, 7}, {1.0, 1.0}, {0.0, 0.0}, {0, 1, -1, 0});  // x -> -y, y -> +x
  CHECK(h.world({2, 5}) == gv::point<2>{5.0, -2.0});
  CHECK(h.nearest_voxel({5.2, -1.7}) == gv::coord<2>{2, 5});
}

TEST_CASE("grid: an oblique rotation round-trips every voxel centre") {
  const double c = std::cos(0.3), s = std::sin(0.3);
  const gv::grid<3> g({5, 4, 3}, {0.7, 1.3, 2.1}, {-3.0, 1.5, 0.25}, {c, -s, 0, s, c, 0, 0, 0, 1});
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(g.nearest_voxel(g.world(g.coords(v))) == g.coords(v));
}

TEST_CASE("grid: singular, non-orthonormal or non-finite directions are rejected, naming the matrix") {
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1, 1, 1}, {}, {1, 0, 0, 0, 1, 0, 0, 0, 0}), "direction matrix", "singular",
                   "[1 0 0; 0 1 0; 0 0 0]");
  GV_CHECK_INVALID(gv::grid<3>({2, 2, 2}, {1, 1, 1}, {}, {1, 0, 0, 1, 0, 0, 0, 0, 1}), "direction matrix", "singular");
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1, 1}, {}, {2, 0, 0, 2}), "direction matrix", "not orthonormal", "[2 0; 0 2]");
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1, 1}, {}, {1, 0.1, 0, 1}), "not orthonormal");
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1, 1}, {}, {1, 0, 0, 1 + 1e-5}), "not orthonormal");
  GV_CHECK_INVALID(gv::grid<2>({2, 2}, {1, 1}, {}, {nan_v<double>, 0, 0, 1}), "direction matrix", "not finite");
  CHECK_NOTHROW(gv::grid<2>({2, 2}, {1, 1}, {}, {1, 0, 0, 1 + 1e-7}));  // within the tolerance
  CHECK_NOTHROW(gv::grid<2>({2, 2}, {1, 1}, {}, {1, 0, 0, -1}));        // a reflection is fine
  CHECK_NOTHROW(gv::grid<3>({2, 2, 2}, {1, 1, 1}, {}, {0, 0, 1, 1, 0, 0, 0, 1, 0}));
}

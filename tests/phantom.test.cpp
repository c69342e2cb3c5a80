// Tests of geovoronoi/phantom.hpp: constant and gradient fields, the steak phantom's tissues, and
// the deterministic seed pickers.

#include <doctest/doctest.h>

#include <geovoronoi/phantom.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace ph = geovoronoi::phantom;

TEST_CASE("phantom: constant") {
  const gv::grid<3> g({5, 4, 3});
  const auto a = ph::constant(g);
  CHECK(a.geometry() == g);
  CHECK(a.size() == 60);
  CHECK(std::all_of(a.begin(), a.end(), [](float x) { return x == 1.0f; }));
  const auto b = ph::constant(gv::grid<2>({3, 3}), 2.5f);
  CHECK(std::all_of(b.begin(), b.end(), [](float x) { return x == 2.5f; }));
}

TEST_CASE("phantom: gradient runs from 1 to 10 along x and is constant across") {
  const gv::grid<3> g({10, 4, 3}, {0.5, 1.0, 2.0});
  const auto f = ph::gradient(g);
  REQUIRE(f.geometry() == g);
  for (gv::index_t z = 0; z < 3; ++z)
    for (gv::index_t y = 0; y < 4; ++y) {
      CHECK(f({0, y, z}) == 1.0f);
      CHECK(f({9, y, z}) == 10.0f);
      for (gv::index_t x = 0; x < 10; ++x) {
        CHECK(f({x, y, z}) == doctest::Approx(1.0 + double(x)).epsilon(1e-6));  // step 9/9 = 1 per voxel
        if (x > 0) CHECK(f({x, y, z}) > f({x - 1, y, z}));
      }
    }
  const auto h = ph::gradient(gv::grid<2>({5, 2}), 2.0f, 4.0f);
  CHECK(h({0, 1}) == 2.0f);
  CHECK(h({2, 0}) == 3.0f);
  CHECK(h({4, 1}) == 4.0f);
  // a single column is the low value, not a division by zero
  const auto one = ph::gradient(gv::grid<3>({1, 3, 3}));
  CHECK(std::all_of(one.begin(), one.end(), [](float x) { return x == 1.0f; }));
}

TEST_CASE("phantom: the steak has background, meat, fat and bone in sensible proportions") {
  const gv::grid<3> g({64, 48, 16});
  const ph::steak_moduli m;
  const auto f = ph::steak(g);
  REQUIRE(f.geometry() == g);
  double n[4] = {0, 0, 0, 0};
  for (float x : f) {
    if (x == 0.0f)
      n[0]++;
    else if (x == m.meat)
      n[1]++;
    else if (x == m.fat)
      n[2]++;
    else if (x == m.bone)
      n[3]++;
    else
      FAIL_CHECK("unexpected value " << x);
  }
  for (double& x : n) x /= double(g.size());
  INFO("background " << n[0] << " meat " << n[1] << " fat " << n[2] << " bone " << n[3]);
  CHECK(n[0] > 0.2);
  CHECK(n[0] < 0.55);   // the outline fills most of the box
  CHECK(n[1] > 0.3);    // meat dominates the domain
  CHECK(n[1] > n[2]);
  CHECK(n[2] > 0.05);   // a fat rim and marbling
  CHECK(n[2] > n[3]);
  CHECK(n[3] > 0.01);   // the T-bone
  CHECK(n[3] < 0.15);
  // the box's corners are background, the centre is inside
  CHECK(f({0, 0, 0}) == 0.0f);
  CHECK(f({63, 47, 15}) == 0.0f);
  CHECK(f({32, 24, 8}) > 0.0f);
  // the moduli match SOFA's transfer function
  CHECK(m.meat == 2.0e4f);
  CHECK(m.fat == 5.0e3f);
  CHECK(m.bone == 1.5e10f);
  // custom moduli are used as given
  const auto c = ph::steak(gv::grid<3>({32, 24, 4}), ph::steak_moduli{1.0f, 2.0f, 3.0f});
  std::set<float> values(c.begin(), c.end());
  CHECK(values == std::set<float>{0.0f, 1.0f, 2.0f, 3.0f});
}

template <int Dim, class Seeds>
void check_seed_list(const gv::image<float, Dim>& f, const Seeds& s, std::size_t expected) {
  CHECK(s.size() == expected);
  std::set<gv::index_t> seen;
  for (const auto& c : s) {
    REQUIRE(f.geometry().contains(c));
    CHECK(f(c) > 0.0f);
    seen.insert(f.geometry().index(c));
  }
  CHECK(seen.size() == s.size());
}

TEST_CASE("phantom: spread_seeds returns distinct, in-domain, well spread voxels deterministically") {
  const auto steak = ph::steak(gv::grid<3>({48, 36, 12}));
  for (int count : {1, 10, 100}) {
    const auto s = ph::spread_seeds(steak, count);
    check_seed_list(steak, s, std::size_t(count));
    CHECK(ph::spread_seeds(steak, count) == s);
  }
  // farthest-point sampling: the first seeds are far apart
  const auto square = ph::constant(gv::grid<2>({21, 21}));
  const auto s4 = ph::spread_seeds(square, 4);
  check_seed_list(square, s4, 4);
  double closest = 1e9;
  for (std::size_t i = 0; i < s4.size(); ++i)
    for (std::size_t j = i + 1; j < s4.size(); ++j)
      closest = std::min(closest, std::hypot(double(s4[i][0] - s4[j][0]), double(s4[i][1] - s4[j][1])));
  CHECK(closest >= 10.0);
  CHECK(s4[0] == gv::coord<2>{10, 10});  // starts at the centre
  // more seeds than domain voxels: every domain voxel once
  auto tiny = ph::constant(gv::grid<2>({3, 2}));
  tiny[4] = 0.0f;
  check_seed_list(tiny, ph::spread_seeds(tiny, 50), 5);
  // nothing to pick
  CHECK(ph::spread_seeds(tiny, 0).empty());
  CHECK(ph::spread_seeds(ph::constant(gv::grid<2>({3, 3}), 0.0f), 3).empty());
}

TEST_CASE("phantom: random_seeds returns distinct in-domain voxels, deterministic in the salt") {
  const auto steak = ph::steak(gv::grid<3>({48, 36, 12}));
  const auto a = ph::random_seeds(steak, 50, 1);
  check_seed_list(steak, a, 50);
  CHECK(ph::random_seeds(steak, 50, 1) == a);
  CHECK(ph::random_seeds(steak, 50, 2) != a);
  auto tiny = ph::constant(gv::grid<2>({3, 2}));
  tiny[0] = -1.0f;
  check_seed_list(tiny, ph::random_seeds(tiny, 9, 7), 5);
}

TEST_CASE("phantom: mri_like_grid has the pelvis MRI's proportions and anisotropic spacing") {
  const auto g = ph::mri_like_grid();
  CHECK(g.extent(0) == 221);
  CHECK(g.extent(1) == 271);
  CHECK(g.extent(2) == 69);
  CHECK(g.spacing(0) == 0.9);
  CHECK(g.spacing(1) == 0.9);
  CHECK(g.spacing(2) == 2.5);
  const auto h = ph::mri_like_grid(64);
  CHECK(h.extent(0) == 64);
  CHECK(h.extent(1) == 78);  // 64 * 271 / 221 = 78.48, rounded
  CHECK(h.extent(2) == 20);
  CHECK(ph::mri_like_grid(0).size() == 1);
}

TEST_CASE("phantom: mri_like is a masked, noisy body whose values span three decades, deterministically") {
  const auto g = ph::mri_like_grid(64);
  const auto f = ph::mri_like(g);
  REQUIRE(f.geometry() == g);
  std::vector<float> in;
  for (float x : f) {
    REQUIRE(std::isfinite(x));
    REQUIRE(x >= 0.0f);
    if (x > 0.0f) in.push_back(x);
  }
  const double inside = double(in.size()) / double(g.size());
  INFO("inside fraction " << inside);
  CHECK(inside > 0.3);  // an irregular body with a masked background around it
  CHECK(inside < 0.7);
  std::sort(in.begin(), in.end());
  const float lo = in.front(), hi = in.back(), median = in[in.size() / 2];
  INFO("min " << lo << " median " << median << " max " << hi);
  CHECK(hi / lo > 1000.0f);  // several decades: gas and cortical bone against fat and fluid
  CHECK(median > 100.0f);    // the bulk is soft tissue
  CHECK(median < 700.0f);
  CHECK(in[in.size() / 100] < 20.0f);  // dark tissues are not a handful of voxels
  // noisy: almost no two neighbouring inside voxels are equal, and many values are distinct
  gv::index_t equal = 0, pairs = 0;
  for (gv::index_t v = 0; v + 1 < g.size(); ++v)
    if (f[v] > 0 && f[v + 1] > 0) ++pairs, equal += f[v] == f[v + 1];
  CHECK(pairs > 1000);
  CHECK(double(equal) < 0.01 * double(pairs));
  std::set<float> distinct(in.begin(), in.end());
  CHECK(distinct.size() > in.size() / 2);
  // the box's corners are background, the centre is inside
  CHECK(f({0, 0, 0}) == 0.0f);
  CHECK(f({63, 77, 19}) == 0.0f);
  CHECK(f({32, 39, 10}) > 0.0f);
  // deterministic; the salt changes the noise, not the body
  const auto again = ph::mri_like(g);
  CHECK(std::equal(f.begin(), f.end(), again.begin()));
  const auto other = ph::mri_like(g, 99);
  gv::index_t differ = 0;
  for (gv::index_t v = 0; v < g.size(); ++v) {
    CHECK((f[v] > 0) == (other[v] > 0));
    differ += f[v] != other[v];
  }
  CHECK(differ > gv::index_t(in.size() / 2));
  // without noise a region is smooth (only the bias field varies); with it, neighbours differ
  const auto clean = ph::mri_like(g, 17, 0.0);
  auto close_pairs = [&](const gv::image<float, 3>& img) {
    gv::index_t close = 0, all = 0;
    for (gv::index_t v = 0; v + 1 < g.size(); ++v)
      if (img[v] > 0 && img[v + 1] > 0) {
        ++all;
        close += std::abs(img[v] - img[v + 1]) < 0.02f * img[v];
      }
    return double(close) / double(all);
  };
  CHECK(close_pairs(clean) > 0.75);  // the rest are tissue boundaries
  CHECK(close_pairs(f) < 0.25);
  CHECK_THROWS_AS(ph::mri_like(g, 1, -0.1), std::invalid_argument);
  CHECK_THROWS_AS(ph::mri_like(g, 1, 0.5), std::invalid_argument);
}

}  // namespace

TEST_CASE("phantom: two_material_beam is soft in the first half of z, stiff in the second") {
  const gv::grid<3> g({4, 3, 10});
  const auto f = gv::phantom::two_material_beam(g, 2.0f, 7.0f);
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(f[v] == (g.coords(v)[2] < 5 ? 2.0f : 7.0f));
  const gv::grid<2> g2({3, 5});
  const auto f2 = gv::phantom::two_material_beam(g2);
  CHECK(f2[g2.index({0, 1})] == 1.0e4f);
  CHECK(f2[g2.index({2, 2})] == 1.0e5f);
}

TEST_CASE("phantom: fingers_meshes voxelize to exactly the fingers image, on plain and rotated grids") {
  namespace gv = geovoronoi;
  const double c = std::cos(0.3), s = std::sin(0.3);
  const gv::direction_matrix<3> rot{c, -s, 0.0, s, c, 0.0, 0.0, 0.0, 1.0};
  for (const auto& g : {gv::grid<3>({23, 17, 5}), gv::grid<3>({31, 20, 4}, {0.5, 0.7, 2.5}, {-3.0, 12.0, 1.0}, rot)}) {
    for (const int count : {1, 3, 5}) {
      const auto want = gv::phantom::fingers(g, count, 1, 7.0f);
      const auto parts = gv::phantom::fingers_meshes(g, count, 1, 7.0f);
      CHECK(parts.size() == std::size_t(count) + 1);
      const auto got = gv::voxelize<float>(parts, g);
      REQUIRE(got.stiffness.size() == want.size());
      gv::index_t differ = 0;
      for (gv::index_t v = 0; v < want.size(); ++v) differ += got.stiffness[v] != want[v];
      CHECK(differ == 0);
      // with two fingers or more the gaps stay empty: the image is not all material
      if (count > 1) CHECK(std::count(want.begin(), want.end(), 0.0f) > 0);
    }
  }
  CHECK_THROWS_AS(gv::phantom::fingers_meshes(gv::grid<3>({4, 4, 4}), 3, 1), std::invalid_argument);
}

// cut_from_mesh.hpp: exact predicates on touching cases, the bounding-box path against a brute force
// over every edge, planes, sweeps, rotated grids, 2D polylines.
#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/obj.hpp>
#include <geovoronoi/io/stl.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <random>

namespace gv = geovoronoi;
using gv::detail::lattice2;
using gv::detail::lattice3;

namespace {

constexpr std::int64_t L = std::int64_t(1) << gv::detail::lattice_bits;  // lattice steps per voxel

/// Every edge tested against every triangle.
template <int N>
gv::cut_set<3> brute_force(const gv::grid<3>& g, const gv::triangle_mesh& m) {
  const auto pts = gv::detail::snap_all<3>(g, m.vertices, "test");
  constexpr auto offs = gv::connectivity<N>::offsets();
  gv::cut_set<3> out(g, gv::connectivity<N>{});
  gv::cut_builder<3> b(g, gv::connectivity<N>{});
  for (gv::index_t u = 0; u < g.size(); ++u)
    for (int d = N / 2; d < N; ++d) {
      const auto c = g.coords(u);
      const gv::coord<3> v{c[0] + offs[d][0], c[1] + offs[d][1], c[2] + offs[d][2]};
      if (!g.contains(v)) continue;
      const lattice3 p{c[0] * L, c[1] * L, c[2] * L}, q{v[0] * L, v[1] * L, v[2] * L};
      for (const auto& t : m.triangles) {
        if (gv::detail::degenerate(pts[t[0]], pts[t[1]], pts[t[2]])) continue;
        if (gv::detail::segment_meets_triangle(p, q, pts[t[0]], pts[t[1]], pts[t[2]])) {
          b.insert(u, d);
          break;
        }
      }
    }
  return b.build();
}

template <int N>
gv::cut_set<2> brute_force_2d(const gv::grid<2>& g, const std::vector<std::vector<gv::point<2>>>& lines) {
  constexpr auto offs = gv::connectivity<N>::offsets();
  gv::cut_builder<2> b(g, gv::connectivity<N>{});
  for (const auto& line : lines) {
    const auto pts = gv::detail::snap_all<2>(g, line, "test");
    for (gv::index_t u = 0; u < g.size(); ++u)
      for (int d = N / 2; d < N; ++d) {
        const auto c = g.coords(u);
        const gv::coord<2> v{c[0] + offs[d][0], c[1] + offs[d][1]};
        if (!g.contains(v)) continue;
        const lattice2 p{c[0] * L, c[1] * L}, q{v[0] * L, v[1] * L};
        for (std::size_t s = 0; s + 1 < pts.size() || s == 0; ++s) {
          const auto& a = pts[s];
          const auto& e = pts[std::min(s + 1, pts.size() - 1)];
          if (gv::detail::segments_meet(p, q, a, e)) b.insert(u, d);
          if (s + 1 >= pts.size()) break;
        }
      }
  }
  return b.build();
}

/// A quad in the plane x = x0 covering y, z in [lo, hi], as two triangles.
gv::triangle_mesh plane_x(double x0, double lo, double hi) {
  gv::triangle_mesh m;
  m.vertices = {{x0, lo, lo}, {x0, hi, lo}, {x0, hi, hi}, {x0, lo, hi}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return m;
}

/// Number of edges of grid g under connectivity<N> with one end at x = 2 and the other at x = 3.
template <int N>
std::size_t edges_between_x2_x3(const gv::grid<3>& g) {
  constexpr auto offs = gv::connectivity<N>::offsets();
  std::size_t n = 0;
  for (gv::index_t u = 0; u < g.size(); ++u)
    for (int d = N / 2; d < N; ++d) {
      const auto c = g.coords(u);
      const gv::coord<3> v{c[0] + offs[d][0], c[1] + offs[d][1], c[2] + offs[d][2]};
      if (g.contains(v) && std::min(c[0], v[0]) == 2 && std::max(c[0], v[0]) == 3) ++n;
    }
  return n;
}

}  // namespace

TEST_CASE("exact predicates: segment against a triangle, touching cases") {
  using gv::detail::segment_meets_triangle;
  // triangle in the plane x = 5 (lattice units), corners (5,0,0), (5,10,0), (5,0,10)
  const lattice3 a{5, 0, 0}, b{5, 10, 0}, c{5, 0, 10};
  auto hits = [&](lattice3 p, lattice3 q) {
    const bool r = segment_meets_triangle(p, q, a, b, c);
    CHECK(r == segment_meets_triangle(q, p, a, b, c));  // the segment has no direction
    CHECK(r == segment_meets_triangle(p, q, b, c, a));  // nor the triangle an orientation
    CHECK(r == segment_meets_triangle(p, q, c, b, a));
    return r;
  };
  SUBCASE("crossing the interior") { CHECK(hits({0, 2, 2}, {10, 2, 2})); }
  SUBCASE("through an edge") {
    CHECK(hits({0, 5, 5}, {10, 5, 5}));   // hypotenuse y + z = 10
    CHECK(hits({0, 3, 0}, {10, 3, 0}));   // edge z = 0
  }
  SUBCASE("through a vertex") {
    CHECK(hits({0, 10, 0}, {10, 10, 0}));
    CHECK(hits({4, -1, -1}, {6, 1, 1}));  // through (5, 0, 0) diagonally
  }
  SUBCASE("an endpoint on the triangle") {
    CHECK(hits({5, 2, 2}, {10, 2, 2}));   // interior
    CHECK(hits({5, 5, 5}, {9, 9, 9}));    // on the hypotenuse
    CHECK(hits({5, 0, 10}, {0, 0, 10}));  // on a vertex
    CHECK_FALSE(hits({5, 6, 6}, {9, 6, 6}));  // on the plane, outside the triangle
  }
  SUBCASE("lying in the plane") {
    CHECK(hits({5, 1, 1}, {5, 2, 2}));     // inside
    CHECK(hits({5, -5, 3}, {5, 20, 3}));   // across, both ends outside
    CHECK(hits({5, 10, 0}, {5, 20, 0}));   // touching a vertex
    CHECK(hits({5, 5, 5}, {5, 9, 9}));     // touching the hypotenuse from outside
    CHECK(hits({5, -3, 0}, {5, 3, 0}));    // overlapping an edge
    CHECK_FALSE(hits({5, 6, 6}, {5, 9, 9}));
    CHECK_FALSE(hits({5, -1, -1}, {5, -5, 20}));
  }
  SUBCASE("missing by one lattice step") {
    CHECK_FALSE(hits({0, 2, 2}, {4, 2, 2}));          // stops one step short of the plane
    CHECK_FALSE(hits({0, 5, 6}, {10, 5, 6}));          // one step beyond the hypotenuse
    CHECK_FALSE(hits({0, -1, 3}, {10, -1, 3}));        // one step beside the edge y = 0
    CHECK_FALSE(hits({0, 11, 0}, {10, 11, 0}));        // one step beyond the vertex
    CHECK_FALSE(hits({5, 6, 5}, {5, 7, 7}));           // in the plane, one step away
  }
  SUBCASE("large coordinates stay exact") {
    // near the lattice limit, where doubles cannot represent the products: a triangle whose
    // hypotenuse passes through (2^39 + 1, 2^39 + 1), probed exactly on it and one step off
    const std::int64_t big = std::int64_t(1) << 38;
    const lattice3 A{big, 0, 0}, B{big, 2 * big + 2, 0}, C{big, 0, 2 * big + 2};
    CHECK(segment_meets_triangle({0, big + 1, big + 1}, {2 * big, big + 1, big + 1}, A, B, C));
    CHECK_FALSE(segment_meets_triangle({0, big + 1, big + 2}, {2 * big, big + 1, big + 2}, A, B, C));
    CHECK(gv::detail::orient3d({0, 0, 0}, {big, 1, 0}, {1, big, 0}, {0, 0, 1}) == 1);
    CHECK(gv::detail::orient3d({-big, -big, -big}, {big, big - 1, big}, {big, big, big}, {big - 1, big, big}) != 0);
  }
}

TEST_CASE("exact predicates: 2D segments") {
  using gv::detail::segments_meet;
  CHECK(segments_meet({0, 0}, {4, 4}, {0, 4}, {4, 0}));      // crossing
  CHECK(segments_meet({0, 0}, {4, 4}, {4, 4}, {8, 0}));      // sharing an endpoint
  CHECK(segments_meet({0, 0}, {4, 0}, {2, 0}, {2, 5}));      // T junction
  CHECK(segments_meet({0, 0}, {4, 0}, {3, 0}, {9, 0}));      // collinear overlap
  CHECK(segments_meet({0, 0}, {4, 0}, {2, 0}, {2, 0}));      // a point on the segment
  CHECK_FALSE(segments_meet({0, 0}, {4, 0}, {5, 0}, {9, 0}));  // collinear, one step apart
  CHECK_FALSE(segments_meet({0, 0}, {4, 0}, {0, 1}, {4, 1}));  // parallel
  CHECK_FALSE(segments_meet({0, 0}, {4, 0}, {2, 1}, {2, 5}));  // stops one step short
}

TEST_CASE("snapping: the one rounding is to the 2^-16 voxel lattice, half up") {
  std::int64_t s;
  CHECK(gv::detail::snap(2.5, s));
  CHECK(s == 5 * L / 2);
  CHECK(gv::detail::snap(std::nextafter(2.5, 3.0), s));  // one ulp off: the same lattice point,
  CHECK(s == 5 * L / 2);                                   // so it still touches (documented)
  CHECK(gv::detail::snap(2.5 + 1.0 / double(L), s));
  CHECK(s == 5 * L / 2 + 1);
  CHECK(gv::detail::snap(0.5 / double(L), s));  // a half step rounds up
  CHECK(s == 1);
  CHECK(gv::detail::snap(-0.5 / double(L), s));
  CHECK(s == 0);
  CHECK_FALSE(gv::detail::snap(1e300, s));
  CHECK_FALSE(gv::detail::snap(std::nan(""), s));
}

TEST_CASE("cut_from_mesh: the plane x = 2.5 on a 6 x 6 x 6 grid") {
  const gv::grid<3> g({6, 6, 6});
  const auto m = plane_x(2.5, -1.0, 6.0);
  SUBCASE("6-connectivity: the 36 x-edges between x = 2 and x = 3") {
    const auto cuts = gv::cut_from_mesh(g, gv::connectivity<6>{}, m);
    CHECK(cuts.size() == 36);
    for (gv::index_t y = 0; y < 6; ++y)
      for (gv::index_t z = 0; z < 6; ++z) CHECK(cuts.cut(g.index({2, y, z}), 3));
    CHECK(cuts == brute_force<6>(g, m));
  }
  SUBCASE("18- and 26-connectivity: every edge crossing the plane, and only those") {
    const auto c18 = gv::cut_from_mesh(g, gv::connectivity<18>{}, m);
    CHECK(c18.size() == edges_between_x2_x3<18>(g));
    CHECK(c18 == brute_force<18>(g, m));
    const auto c26 = gv::cut_from_mesh(g, gv::connectivity<26>{}, m);
    CHECK(c26.size() == edges_between_x2_x3<26>(g));
    CHECK(c26.size() == 36 * 9 - 2 * 6 * 3 * 2 + 4);  // 9 per voxel at x = 2, less those leaving y/z faces
    CHECK(c26 == brute_force<26>(g, m));
  }
  SUBCASE("a plane through voxel centres cuts every edge touching it") {
    const auto m2 = plane_x(2.0, -1.0, 6.0);
    const auto cuts = gv::cut_from_mesh(g, gv::connectivity<6>{}, m2);
    // x-edges 1-2 and 2-3 (touching at an end), and every y- and z-edge inside the plane
    CHECK(cuts.size() == 36 + 36 + 2 * 30);
    CHECK(cuts == brute_force<6>(g, m2));
    // one ulp off the centres snaps onto them (the documented single rounding); one lattice step
    // off is off: only the x-edges between 2 and 3 remain
    CHECK(gv::cut_from_mesh(g, gv::connectivity<6>{}, plane_x(std::nextafter(2.0, 3.0), -1.0, 6.0)) == cuts);
    CHECK(gv::cut_from_mesh(g, gv::connectivity<6>{}, plane_x(2.0 + 1.0 / double(L), -1.0, 6.0)).size() == 36);
    CHECK(gv::cut_from_mesh(g, gv::connectivity<6>{}, plane_x(2.0 - 1.0 / double(L), -1.0, 6.0)).size() == 36);
  }
  SUBCASE("a triangle edge lying on a row of voxel centres cuts the edges along it") {
    gv::triangle_mesh t;  // in the plane z = 2, its edge y = 2 from x = 0.5 to 4.5
    t.vertices = {{0.5, 2.0, 2.0}, {4.5, 2.0, 2.0}, {2.5, 4.5, 2.0}};
    t.triangles = {{0, 1, 2}};
    const auto c = gv::cut_from_mesh(g, gv::connectivity<6>{}, t);
    CHECK(c.cut(g.index({1, 2, 2}), 3));   // x-edge (1,2,2)-(2,2,2), on the triangle's edge
    CHECK(c.cut(g.index({2, 2, 2}), 5));   // z-edge from a centre on the triangle's edge
    CHECK(c.cut(g.index({2, 2, 1}), 5));   // z-edge ending there
    CHECK(c.cut(g.index({0, 2, 2}), 3));   // x-edge overlapping the triangle's edge on [0.5, 1]
    CHECK_FALSE(c.cut(g.index({0, 2, 1}), 5));  // z-edge at x = 0, beside the triangle
    CHECK(c == brute_force<6>(g, t));
  }
}

TEST_CASE("cut_from_mesh: random meshes, the bounding-box path equals the brute force") {
  std::mt19937 rng(2024);
  const gv::grid<3> g({7, 6, 5});
  for (int trial = 0; trial < 60; ++trial) {
    gv::triangle_mesh m;
    const int nt = 1 + int(rng() % 6);
    // coordinates on a quarter-voxel grid, so vertices, edges and faces often pass exactly through
    // voxel centres and grid edges (the touching cases)
    std::uniform_int_distribution<int> q(-6, 32);
    for (int t = 0; t < nt; ++t) {
      for (int k = 0; k < 3; ++k) m.vertices.push_back({q(rng) / 4.0, q(rng) / 4.0 * 0.8, q(rng) / 4.0 * 0.6});
      const auto b = std::uint32_t(3 * t);
      m.triangles.push_back({b, b + 1, b + 2});
    }
    CAPTURE(trial);
    CHECK(gv::cut_from_mesh(g, gv::connectivity<6>{}, m) == brute_force<6>(g, m));
    CHECK(gv::cut_from_mesh(g, gv::connectivity<18>{}, m) == brute_force<18>(g, m));
    CHECK(gv::cut_from_mesh(g, gv::connectivity<26>{}, m) == brute_force<26>(g, m));
  }
}

TEST_CASE("cut_from_mesh: a large oblique triangle visits a slab, not its bounding box") {
  const gv::grid<3> g({40, 40, 40});
  gv::triangle_mesh m;
  m.vertices = {{-0.3, 0.2, 1.1}, {39.6, 3.3, 20.2}, {5.1, 39.4, 38.7}};
  m.triangles = {{0, 1, 2}};
  gv::cut_stats st;
  const auto cuts = gv::cut_from_mesh(g, gv::connectivity<26>{}, m, &st);
  CHECK(st.voxels_visited <= 8 * 40 * 40);  // the box holds 64000 voxels
  CHECK(cuts.size() > 1000);
  CHECK(cuts == brute_force<26>(g, m));
  std::mt19937 rng(31);
  std::uniform_real_distribution<double> q(-3.0, 15.0);
  const gv::grid<3> h({12, 11, 10});
  for (int trial = 0; trial < 30; ++trial) {
    gv::triangle_mesh r;
    for (int k = 0; k < 6; ++k) r.vertices.push_back({q(rng), q(rng), q(rng)});
    r.triangles = {{0, 1, 2}, {3, 4, 5}, {0, 4, 2}};
    CAPTURE(trial);
    CHECK(gv::cut_from_mesh(h, gv::connectivity<26>{}, r) == brute_force<26>(h, r));
    CHECK(gv::cut_from_mesh(h, gv::connectivity<6>{}, r) == brute_force<6>(h, r));
  }
}

TEST_CASE("cut_from_mesh: a rotated, shifted, anisotropic grid cuts the same edges as its index space") {
  // the mesh is made in index space, on the lattice, then moved to world coordinates through the
  // grid's transform; the rounding of that round trip is far below half a lattice step
  const double c = std::cos(0.3), s = std::sin(0.3);
  const gv::grid<3> rotated({6, 5, 4}, {0.7, 1.3, 0.9}, {10.0, -4.0, 2.5}, {c, -s, 0, s, c, 0, 0, 0, 1});
  const gv::grid<3> plain({6, 5, 4});
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> q(-4, 28);
  for (int trial = 0; trial < 20; ++trial) {
    gv::triangle_mesh index_mesh, world_mesh;
    for (int t = 0; t < 4; ++t) {
      for (int k = 0; k < 3; ++k) {
        const std::array<double, 3> u{q(rng) / 4.0, q(rng) / 5.0, q(rng) / 6.0};
        std::array<double, 3> lat{};  // moved onto the lattice, so the round trip cannot change it
        for (int a = 0; a < 3; ++a) lat[a] = std::round(u[a] * double(L)) / double(L);
        index_mesh.vertices.push_back(lat);
        std::array<double, 3> w{};
        for (int r = 0; r < 3; ++r) {
          w[r] = rotated.origin()[r];
          for (int a = 0; a < 3; ++a) w[r] += rotated.direction(r, a) * lat[a] * rotated.spacing(a);
        }
        world_mesh.vertices.push_back(w);
      }
      const auto b = std::uint32_t(3 * t);
      index_mesh.triangles.push_back({b, b + 1, b + 2});
      world_mesh.triangles.push_back({b, b + 1, b + 2});
    }
    const auto want = gv::cut_from_mesh(plain, gv::connectivity<26>{}, index_mesh);
    const auto got = gv::cut_from_mesh(rotated, gv::connectivity<26>{}, world_mesh);
    CHECK(got.entries() == want.entries());
    CHECK(got.geometry() == rotated);
  }
}

TEST_CASE("cut_from_mesh: degenerate triangles, statistics and bad input") {
  const gv::grid<3> g({4, 4, 4});
  gv::triangle_mesh m = plane_x(1.5, -1, 5);
  m.vertices.push_back({0, 0, 0});
  m.vertices.push_back({1, 1, 1});
  m.vertices.push_back({2, 2, 2});  // collinear with the two before
  m.triangles.push_back({4, 5, 6});
  gv::cut_stats st;
  const auto cuts = gv::cut_from_mesh(g, gv::connectivity<6>{}, m, &st);
  CHECK(st.primitives == 2);
  CHECK(st.degenerate == 1);
  CHECK(st.edges_tested > 0);
  CHECK(cuts.size() == 16);

  SUBCASE("bounding-box cost: a small triangle tests only the edges near it") {
    const gv::grid<3> big({200, 200, 200});
    gv::triangle_mesh t;
    t.vertices = {{100.2, 100.2, 100.5}, {101.7, 100.3, 100.5}, {100.4, 101.8, 100.5}};
    t.triangles = {{0, 1, 2}};
    gv::cut_stats s;
    const auto c = gv::cut_from_mesh(big, gv::connectivity<26>{}, t, &s);
    CHECK(s.edges_tested < 500);
    CHECK(c.size() > 0);
  }
  SUBCASE("a triangle outside the grid cuts nothing") {
    const auto c = gv::cut_from_mesh(g, gv::connectivity<26>{}, plane_x(9.5, -1, 5));
    CHECK(c.empty());
  }
  SUBCASE("errors") {
    gv::triangle_mesh bad = plane_x(1.5, -1, 5);
    bad.vertices[2][1] = std::nan("");
    CHECK_THROWS_WITH_AS(gv::cut_from_mesh(g, gv::connectivity<6>{}, bad), doctest::Contains("vertex 2"),
                         std::invalid_argument);
    bad = plane_x(1.5, -1, 5);
    bad.vertices[1][0] = 1e9;
    CHECK_THROWS_WITH_AS(gv::cut_from_mesh(g, gv::connectivity<6>{}, bad), doctest::Contains("2^24"),
                         std::invalid_argument);
    bad = plane_x(1.5, -1, 5);
    bad.triangles[1][2] = 7;
    CHECK_THROWS_WITH_AS(gv::cut_from_mesh(g, gv::connectivity<6>{}, bad), doctest::Contains("triangle 1"),
                         std::invalid_argument);
  }
}

TEST_CASE("cut_from_blade_sweep: a blade swept through x = 2.5 cuts like the plane") {
  const gv::grid<3> g({6, 6, 6});
  std::vector<std::vector<gv::point<3>>> sweep;
  for (double z : {-1.0, 1.25, 3.5, 6.0}) sweep.push_back({{2.5, -1.0, z}, {2.5, 2.0, z}, {2.5, 6.0, z}});
  gv::cut_stats st;
  const auto cuts = gv::cut_from_blade_sweep(g, gv::connectivity<26>{}, sweep, &st);
  CHECK(cuts == gv::cut_from_mesh(g, gv::connectivity<26>{}, plane_x(2.5, -1.0, 6.0)));
  CHECK(st.primitives == 3 * 2 * 2);

  SUBCASE("a blade that stops halfway") {
    std::vector<std::vector<gv::point<3>>> half{{{2.5, -1.0, -1.0}, {2.5, 6.0, -1.0}},
                                                {{2.5, -1.0, 2.5}, {2.5, 6.0, 2.5}}};
    const auto c = gv::cut_from_blade_sweep(g, gv::connectivity<6>{}, half);
    CHECK(c.size() == 6 * 3);  // the x-edges at z = 0, 1, 2
    CHECK(c.cut(g.index({2, 4, 2}), 3));
    CHECK_FALSE(c.cut(g.index({2, 4, 3}), 3));
  }
  SUBCASE("a blade that does not move cuts nothing") {
    std::vector<std::vector<gv::point<3>>> still{{{2.5, 0, 0}, {2.5, 5, 5}}, {{2.5, 0, 0}, {2.5, 5, 5}}};
    gv::cut_stats s;
    CHECK(gv::cut_from_blade_sweep(g, gv::connectivity<6>{}, still, &s).empty());
    CHECK(s.degenerate == 2);
  }
  SUBCASE("errors") {
    CHECK_THROWS_AS(gv::cut_from_blade_sweep(g, gv::connectivity<6>{}, {{{0, 0, 0}, {1, 1, 1}}}), std::invalid_argument);
    CHECK_THROWS_AS(gv::cut_from_blade_sweep(g, gv::connectivity<6>{}, {{{0, 0, 0}}, {{1, 1, 1}}}),
                    std::invalid_argument);
    CHECK_THROWS_WITH_AS(
        gv::cut_from_blade_sweep(g, gv::connectivity<6>{}, {{{0, 0, 0}, {1, 1, 1}}, {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}}}),
        doctest::Contains("position 1"), std::invalid_argument);
  }
}

TEST_CASE("cut_from_polylines: 2D cuts, exact, against the brute force") {
  const gv::grid<2> g({6, 6});
  const std::vector<gv::point<2>> line{{2.5, -1.0}, {2.5, 7.0}};
  const auto c4 = gv::cut_from_polyline(g, gv::connectivity<4>{}, line);
  CHECK(c4.size() == 6);
  for (gv::index_t y = 0; y < 6; ++y) CHECK(c4.cut(g.index({3, y}), 1));  // (-1, 0) from x = 3
  const auto c8 = gv::cut_from_polyline(g, gv::connectivity<8>{}, line);
  CHECK(c8.size() == 6 + 2 * 5);
  CHECK(c8 == brute_force_2d<8>(g, {line}));

  std::mt19937 rng(5);
  std::uniform_int_distribution<int> q(-4, 26);
  for (int trial = 0; trial < 100; ++trial) {
    std::vector<std::vector<gv::point<2>>> lines;
    for (int k = 0; k < 1 + int(rng() % 3); ++k) {
      std::vector<gv::point<2>> l;
      for (int i = 0; i < 1 + int(rng() % 4); ++i) l.push_back({q(rng) / 4.0, q(rng) / 4.0});
      lines.push_back(l);
    }
    CAPTURE(trial);
    CHECK(gv::cut_from_polylines(g, gv::connectivity<4>{}, lines) == brute_force_2d<4>(g, lines));
    CHECK(gv::cut_from_polylines(g, gv::connectivity<8>{}, lines) == brute_force_2d<8>(g, lines));
  }
  CHECK_THROWS_AS(gv::cut_from_polyline(g, gv::connectivity<4>{}, {{0.0, std::nan("")}}), std::invalid_argument);

  // a long diagonal visits a band along it, not its bounding box
  const gv::grid<2> big({300, 300});
  const std::vector<gv::point<2>> diag{{0.3, 1.1}, {297.6, 280.2}};
  gv::cut_stats st;
  const auto cd = gv::cut_from_polyline(big, gv::connectivity<8>{}, diag, &st);
  CHECK(st.voxels_visited <= 7 * 300);  // the box holds 90000
  CHECK(cd == brute_force_2d<8>(big, {diag}));
  std::uniform_real_distribution<double> r(-3.0, 20.0);
  const gv::grid<2> h({17, 15});
  for (int trial = 0; trial < 100; ++trial) {
    const std::vector<std::vector<gv::point<2>>> l{{{r(rng), r(rng)}, {r(rng), r(rng)}, {r(rng), r(rng)}}};
    CAPTURE(trial);
    CHECK(gv::cut_from_polylines(h, gv::connectivity<8>{}, l) == brute_force_2d<8>(h, l));
    CHECK(gv::cut_from_polylines(h, gv::connectivity<4>{}, l) == brute_force_2d<4>(h, l));
  }
}

TEST_CASE("cut_from_mesh: from an OBJ and an STL file's bytes") {
  const gv::grid<3> g({6, 6, 6});
  const std::string obj = "v 2.5 -1 -1\nv 2.5 6 -1\nv 2.5 6 6\nv 2.5 -1 6\nf 1 2 3 4\n";
  const auto m = gv::io::parse_obj("plane.obj", std::vector<unsigned char>(obj.begin(), obj.end()));
  CHECK(gv::cut_from_mesh(g, gv::connectivity<26>{}, m) == gv::cut_from_mesh(g, gv::connectivity<26>{}, plane_x(2.5, -1, 6)));
  const std::string stl = "solid p\nfacet normal 1 0 0\nouter loop\nvertex 2.5 -1 -1\nvertex 2.5 6 -1\nvertex 2.5 6 6\n"
                          "vertex 2.5 -1 6\nendloop\nendfacet\nendsolid p\n";
  const auto s = gv::io::parse_stl("plane.stl", std::vector<unsigned char>(stl.begin(), stl.end()));
  CHECK(gv::cut_from_mesh(g, gv::connectivity<6>{}, s).size() == 36);
}

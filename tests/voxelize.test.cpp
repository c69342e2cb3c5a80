// voxelize.hpp: against an independent ray-casting oracle (double precision, several random
// directions, majority vote, voxels within 1e-6 of the surface skipped), the tie rule on faces
// through voxel centres, the checks' error text, the winding rule against a brute-force solid-angle
// sum, overlap rules, fractions, surface voxels, invariance; and the mesh phantoms and mesh writers.
#include <geovoronoi/io/obj.hpp>
#include <geovoronoi/io/stl.hpp>
#include <geovoronoi/phantom.hpp>
#include <geovoronoi/voxelize.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

namespace gv = geovoronoi;
using gv::triangle_mesh;
using V3 = std::array<double, 3>;

namespace {

V3 sub(const V3& a, const V3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) { return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}; }
double dot(const V3& a, const V3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Distance from p to the closed triangle abc (Ericson, Real-Time Collision Detection 5.1.5).
double distance(const V3& p, const V3& a, const V3& b, const V3& c) {
  const V3 ab = sub(b, a), ac = sub(c, a), ap = sub(p, a);
  auto len = [&](const V3& q) { return std::sqrt(dot(sub(p, q), sub(p, q))); };
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return len(a);
  const V3 bp = sub(p, b);
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return len(b);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return len({a[0] + v * ab[0], a[1] + v * ab[1], a[2] + v * ab[2]});
  }
  const V3 cp = sub(p, c);
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return len(c);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return len({a[0] + w * ac[0], a[1] + w * ac[1], a[2] + w * ac[2]});
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return len({b[0] + w * (c[0] - b[0]), b[1] + w * (c[1] - b[1]), b[2] + w * (c[2] - b[2])});
  }
  const double den = 1.0 / (va + vb + vc), v = vb * den, w = vc * den;
  return len({a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w, a[2] + ab[2] * v + ac[2] * w});
}

/// Signed crossings of the ray p + t d (t > 0) with the mesh (Moller-Trumbore), +1 where the
/// triangle's normal points along d.
int ray_count(const triangle_mesh& m, const V3& p, const V3& d) {
  int n = 0;
  for (const auto& t : m.triangles) {
    const V3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
    const V3 e1 = sub(b, a), e2 = sub(c, a), h = cross(d, e2);
    const double det = dot(e1, h);
    if (det == 0) continue;
    const V3 s = sub(p, a);
    const double u = dot(s, h) / det;
    if (u < 0 || u > 1) continue;
    const V3 q = cross(s, e1);
    const double v = dot(d, q) / det;
    if (v < 0 || u + v > 1) continue;
    if (dot(e2, q) / det <= 0) continue;
    n += dot(cross(e1, e2), d) > 0 ? 1 : -1;
  }
  return n;
}

/// The oracle: 1 inside, 0 outside, -1 within 1e-6 (world units) of the surface (not judged).
/// Inside = the signed count is non-zero along a majority of three random directions.
std::vector<int> oracle(const triangle_mesh& m, const gv::grid<3>& g) {
  std::mt19937 rng(7);
  std::normal_distribution<double> nd;
  std::vector<V3> dirs(3);
  for (auto& d : dirs) d = {nd(rng), nd(rng), nd(rng)};
  std::vector<int> out(static_cast<std::size_t>(g.size()));
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const V3 p = g.world(g.coords(v));
    double dmin = 1e300;
    for (const auto& t : m.triangles)
      dmin = std::min(dmin, distance(p, m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]]));
    if (dmin < 1e-6) {
      out[std::size_t(v)] = -1;
      continue;
    }
    int votes = 0;
    for (const auto& d : dirs) votes += ray_count(m, p, d) != 0;
    out[std::size_t(v)] = votes >= 2;
  }
  return out;
}

/// Brute-force generalized winding number at p.
double winding(const triangle_mesh& m, const V3& p) {
  double s = 0;
  for (const auto& t : m.triangles) {
    const V3 a = sub(m.vertices[t[0]], p), b = sub(m.vertices[t[1]], p), c = sub(m.vertices[t[2]], p);
    const double la = std::sqrt(dot(a, a)), lb = std::sqrt(dot(b, b)), lc = std::sqrt(dot(c, c));
    s += 2 * std::atan2(dot(a, cross(b, c)), la * lb * lc + dot(a, b) * lc + dot(a, c) * lb + dot(b, c) * la);
  }
  return s / (4 * 3.14159265358979323846);
}

gv::voxelize_part part(triangle_mesh m, double value = 1.0, gv::label_t label = 0, std::string name = {}) {
  gv::voxelize_part p;
  p.mesh = std::move(m);
  p.value = value;
  p.label = label;
  p.name = std::move(name);
  return p;
}

/// Compares voxelize's inside-ness (label != 0) with the oracle where it is sure; returns the number
/// of voxels judged.
gv::index_t check_against_oracle(const triangle_mesh& m, const gv::grid<3>& g, gv::inside_rule rule = gv::inside_rule::closed) {
  gv::voxelize_options o;
  o.rule = rule;
  const auto v = gv::voxelize<float>({part(m)}, g, o);
  const auto want = oracle(m, g);
  gv::index_t judged = 0, wrong = 0;
  for (gv::index_t i = 0; i < g.size(); ++i) {
    if (want[std::size_t(i)] < 0) continue;
    ++judged;
    if ((v.label[i] != 0) != (want[std::size_t(i)] == 1)) ++wrong;
  }
  CHECK(wrong == 0);
  return judged;
}

std::size_t count_label(const gv::image<gv::label_t, 3>& l, gv::label_t x) {
  return static_cast<std::size_t>(std::count(l.begin(), l.end(), x));
}

triangle_mesh merge(const triangle_mesh& a, const triangle_mesh& b) {
  triangle_mesh m = a;
  const auto off = static_cast<std::uint32_t>(m.vertices.size());
  m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
  for (auto t : b.triangles) m.triangles.push_back({t[0] + off, t[1] + off, t[2] + off});
  return m;
}

triangle_mesh flipped(triangle_mesh m) {
  for (auto& t : m.triangles) std::swap(t[1], t[2]);
  return m;
}

std::string error_of(const std::vector<gv::voxelize_part>& parts, const gv::grid<3>& g, gv::voxelize_options o = {}) {
  try {
    (void)gv::voxelize<float>(parts, g, o);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

bool has(const std::string& s, const std::string& what) {
  const bool ok = s.find(what) != std::string::npos;
  if (!ok) MESSAGE("message: " << s << "   (looking for: " << what << ")");
  return ok;
}

const gv::grid<3> unit10({10, 10, 10});

}  // namespace

TEST_CASE("voxelize: box voxel counts, and faces through voxel centres (the half-open tie rule)") {
  auto v = gv::voxelize<float>({part(gv::phantom::box_mesh({1.5, 1.5, 1.5}, {5.5, 4.5, 3.5}), 7.0)}, unit10);
  CHECK(count_label(v.label, 1) == 4 * 3 * 2);
  CHECK(v.stats.inside_voxels == 24);
  CHECK(v.stats.triangles == 12);
  CHECK(v.stiffness({2, 2, 2}) == 7.0f);
  CHECK(v.stiffness({1, 2, 2}) == 0.0f);
  CHECK(v.stats.mesh_volume == doctest::Approx(24.0));
  // every face on voxel centres: lower faces keep their centres, upper faces do not
  v = gv::voxelize<float>({part(gv::phantom::box_mesh({2, 2, 2}, {5, 5, 5}))}, unit10);
  CHECK(count_label(v.label, 1) == 27);
  CHECK(v.label({2, 2, 2}) == 1);
  CHECK(v.label({4, 4, 4}) == 1);
  CHECK(v.label({5, 4, 4}) == 0);
  CHECK(v.label({4, 5, 4}) == 0);
  CHECK(v.label({4, 4, 5}) == 0);
  // a box whose edges and corners lie on rows
  v = gv::voxelize<float>({part(gv::phantom::box_mesh({-1, -1, -1}, {20, 20, 20}))}, unit10);
  CHECK(count_label(v.label, 1) == 1000);
}

TEST_CASE("voxelize: two meshes sharing a face claim each centre on it exactly once") {
  gv::voxelize_options o;
  o.overlap = gv::overlap_rule::error;
  for (int axis = 0; axis < 3; ++axis) {
    gv::point<3> lo{2, 2, 2}, mid{5, 5, 5}, hi{8, 8, 8}, a_hi{5, 5, 5}, b_lo{2, 2, 2};
    for (int k = 0; k < 3; ++k) {
      a_hi[k] = k == axis ? mid[k] : hi[k];
      b_lo[k] = k == axis ? mid[k] : lo[k];
    }
    const auto v = gv::voxelize<float>({part(gv::phantom::box_mesh(lo, a_hi)), part(gv::phantom::box_mesh(b_lo, hi))}, unit10, o);
    // centres in [2, 8) along each axis, each given to exactly one of the two
    CHECK(count_label(v.label, 1) + count_label(v.label, 2) == 6 * 6 * 6);
    CHECK(count_label(v.label, 1) == 3 * 6 * 6);
    gv::coord<3> on{5, 5, 5};
    CHECK(v.label(on) == 2);
  }
  // a shared face that is a diagonal plane through centres: a cube split into two prisms
  triangle_mesh a, b;
  a.vertices = b.vertices = {{1, 1, 1}, {7, 1, 1}, {1, 7, 1}, {1, 1, 7}, {7, 1, 7}, {1, 7, 7}, {7, 7, 1}, {7, 7, 7}};
  // prism A: x + y <= 8 (vertices 0 1 2 / 3 4 5), prism B: x + y >= 8 (1 6 2 / 4 7 5)
  a.triangles = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {0, 3, 5}, {0, 5, 2}, {1, 2, 5}, {1, 5, 4}};
  b.triangles = {{1, 2, 6}, {4, 7, 5}, {1, 6, 7}, {1, 7, 4}, {6, 2, 5}, {6, 5, 7}, {2, 1, 4}, {2, 4, 5}};
  const auto v = gv::voxelize<float>({part(a), part(b)}, unit10, o);
  int on_face = 0;
  for (gv::index_t z = 1; z < 7; ++z)
    for (gv::index_t y = 1; y < 7; ++y)
      for (gv::index_t x = 1; x < 7; ++x) {
        CHECK(v.label({x, y, z}) != 0);
        if (x + y == 8) ++on_face;
      }
  CHECK(on_face > 0);
  CHECK(count_label(v.label, 1) + count_label(v.label, 2) == 216);
}

TEST_CASE("voxelize: spheres and tori against the ray-casting oracle at several resolutions") {
  for (int n : {12, 17, 23}) {
    const gv::grid<3> g({n, n, n}, {20.0 / n, 20.0 / n, 20.0 / n}, {-10 + 10.0 / n, -10 + 10.0 / n, -10 + 10.0 / n});
    CHECK(check_against_oracle(gv::phantom::ellipsoid_mesh({0.3, -0.2, 0.1}, {8, 6.5, 5}, 2), g) > 0);
    CHECK(check_against_oracle(gv::phantom::torus_mesh({0.1, 0.2, -0.3}, 6, 2.5, 24, 12), g) > 0);
  }
}

TEST_CASE("voxelize: nested shells keep the cavity outside; parts closer than a voxel stay apart; thin plates") {
  const auto outer = gv::phantom::ellipsoid_mesh({5, 5, 5}, {4.3, 4.1, 4.2}, 2);
  const auto inner = flipped(gv::phantom::ellipsoid_mesh({5, 5, 5}, {2.2, 2.1, 2.3}, 2));
  const auto shell = merge(outer, inner);
  CHECK(check_against_oracle(shell, unit10) > 500);
  const auto v = gv::voxelize<float>({part(shell)}, unit10);
  CHECK(v.label({5, 5, 5}) == 0);
  CHECK(v.label({5, 5, 8}) == 1);
  CHECK(v.stats.mesh_volume == doctest::Approx(4.0 / 3 * 3.14159 * (4.3 * 4.1 * 4.2 - 2.2 * 2.1 * 2.3)).epsilon(0.1));

  // 0.2 voxel apart: each keeps its own voxels
  const auto two = gv::voxelize<float>({part(gv::phantom::box_mesh({1.2, 1.2, 1.2}, {4.4, 3.5, 3.5}), 1, 5),
                                        part(gv::phantom::box_mesh({4.6, 1.2, 1.2}, {8.5, 3.5, 3.5}), 2, 9)},
                                       unit10);
  CHECK(count_label(two.label, 5) == 3 * 2 * 2);
  CHECK(count_label(two.label, 9) == 4 * 2 * 2);
  // a plate thinner than a voxel holding a layer of centres, and one holding none
  const auto plate = gv::voxelize<float>({part(gv::phantom::box_mesh({0.5, 0.5, 2.9}, {8.5, 8.5, 3.1}))}, unit10);
  CHECK(count_label(plate.label, 1) == 64);
  const auto none = gv::voxelize<float>({part(gv::phantom::box_mesh({0.5, 0.5, 3.2}, {8.5, 8.5, 3.4}))}, unit10);
  CHECK(count_label(none.label, 1) == 0);
}

TEST_CASE("voxelize: rotated grids, principal axes, volume") {
  const double c = std::cos(0.5), s = std::sin(0.5);
  const gv::grid<3> rot({16, 14, 12}, {0.8, 0.9, 1.1}, {-6, -5, -6}, {c, -s, 0, s, c, 0, 0, 0, 1});
  CHECK(check_against_oracle(gv::phantom::torus_mesh({0, 0, 0}, 5, 2, 20, 10), rot) > 1000);

  // a long box turned about z and x: the first principal axis follows its long side
  auto box = gv::phantom::box_mesh({-8, -2, -1}, {8, 2, 1});
  const double cb = std::cos(0.7), sb = std::sin(0.7);
  for (auto& p : box.vertices) p = {cb * p[0] - sb * p[1], sb * p[0] + cb * p[1], p[2]};
  gv::voxelize_options o;
  o.voxel_size = {0.25, 0.25, 0.25};
  o.principal_axes = true;
  const auto g = gv::voxelize_grid({part(box)}, o);
  CHECK(std::abs(g.direction(0, 0) * cb + g.direction(1, 0) * sb) == doctest::Approx(1.0));
  CHECK(std::abs(g.direction(2, 2)) == doctest::Approx(1.0));
  const double det = g.direction(0, 0) * (g.direction(1, 1) * g.direction(2, 2) - g.direction(2, 1) * g.direction(1, 2)) -
                     g.direction(0, 1) * (g.direction(1, 0) * g.direction(2, 2) - g.direction(2, 0) * g.direction(1, 2)) +
                     g.direction(0, 2) * (g.direction(1, 0) * g.direction(2, 1) - g.direction(2, 0) * g.direction(1, 1));
  CHECK(det == doctest::Approx(1.0));
  // aligned with the box, the grid is about 16 x 4 x 2 / 0.25^3 voxels and the box fills it
  CHECK(g.size() <= 65 * 17 * 9);
  const auto v = gv::voxelize<float>({part(box)}, o);
  CHECK(double(v.stats.inside_voxels) * g.voxel_volume() == doctest::Approx(128.0).epsilon(0.03));

  // a sphere's inside volume against its mesh volume (stated tolerance: 2% at radius 12 voxels)
  gv::voxelize_options so;
  so.voxel_size = {1, 1, 1};
  so.pad = 1;
  const auto sphere = gv::voxelize<float>({part(gv::phantom::ellipsoid_mesh({0.3, 0.1, 0.2}, {12, 12, 12}, 4))}, so);
  CHECK(double(sphere.stats.inside_voxels) == doctest::Approx(sphere.stats.mesh_volume).epsilon(0.02));
}

TEST_CASE("voxelize: the grid options") {
  const auto box = gv::phantom::box_mesh({0.2, 0.3, 0.4}, {4.1, 2.05, 1.0});
  gv::voxelize_options o;
  o.voxel_size = {0.5, 0.5, 0.5};
  o.pad = 2;
  auto g = gv::voxelize_grid({part(box)}, o);
  for (int a = 0; a < 3; ++a) {
    CHECK(std::fmod(g.origin()[a], 0.5) == 0.0);  // snapped
    CHECK(g.origin()[a] - 0.25 + 2 * 0.5 <= std::array<double, 3>{0.2, 0.3, 0.4}[a]);
    CHECK(g.origin()[a] + (double(g.extent(a)) - 2 - 0.5) * 0.5 >= std::array<double, 3>{4.1, 2.05, 1.0}[a]);
  }
  o = {};
  o.voxels = {39, 7, 6};
  g = gv::voxelize_grid({part(box)}, o);
  CHECK(g.extent(0) == 39);
  CHECK(g.spacing(0) == doctest::Approx(0.1));
  CHECK(g.origin()[0] == doctest::Approx(0.25));
  auto err = [&](gv::voxelize_options x) {
    try {
      (void)gv::voxelize_grid({part(box)}, x);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  CHECK(has(err({}), "neither voxel_size nor voxels"));
  o = {};
  o.voxel_size = {1, 1, 1};
  o.voxels = {2, 2, 2};
  CHECK(has(err(o), "both voxel_size and voxels"));
  o.voxels = {0, 0, 0};
  o.voxel_size = {1, -1, 1};
  CHECK(has(err(o), "voxel_size along y is -1"));
  o.voxel_size = {1e-5, 1e-5, 1e-5};
  CHECK(has(err(o), "more than 2^31"));
  CHECK(has(error_of({}, unit10), "no parts"));
  o = {};
  o.fraction_samples = 17;
  CHECK(has(error_of({part(box)}, unit10, o), "fraction_samples is 17"));
}

TEST_CASE("voxelize: invariance under triangle order, vertex rotation and thread count") {
  const auto base = merge(gv::phantom::torus_mesh({5, 5, 5}, 3.4, 1.3, 17, 9),
                          gv::phantom::ellipsoid_mesh({5.1, 4.9, 5.2}, {0.9, 0.8, 0.7}, 1));
  const gv::grid<3> g({21, 20, 19}, {0.5, 0.5, 0.5}, {0, 0, 0});
  gv::voxelize_options o;
  o.fraction_samples = 2;
  o.threads = 1;
  const auto ref = gv::voxelize<double>({part(base, 3.0)}, g, o);
  CHECK(ref.stats.inside_voxels > 100);
  auto shuffled = base;
  std::mt19937 rng(3);
  std::shuffle(shuffled.triangles.begin(), shuffled.triangles.end(), rng);
  for (std::size_t i = 0; i < shuffled.triangles.size(); ++i) {
    auto& t = shuffled.triangles[i];
    std::rotate(t.begin(), t.begin() + std::ptrdiff_t(i % 3), t.end());
  }
  for (unsigned threads : {1u, 2u, 3u, 7u}) {
    o.threads = threads;
    const auto v = gv::voxelize<double>({part(shuffled, 3.0)}, g, o);
    CHECK(v.label.values() == ref.label.values());
    CHECK(v.stiffness.values() == ref.stiffness.values());
    CHECK(v.fraction.values() == ref.fraction.values());
    CHECK(v.stats.crossings == ref.stats.crossings);
  }
}

TEST_CASE("voxelize: errors of inside_rule::closed name the part, the edge and the triangles") {
  const auto box = gv::phantom::box_mesh({2, 2, 2}, {6, 6, 6});
  auto open = box;
  open.triangles.pop_back();
  std::string e = error_of({part(open, 1, 0, "lid.stl")}, unit10);
  CHECK(has(e, "part 0 (\"lid.stl\")"));
  CHECK(has(e, "not closed"));
  CHECK(has(e, "from vertex 1 (6, 2, 2) to vertex 5 (6, 2, 6) belongs to triangle 4 only"));
  CHECK(has(e, "inside_rule::winding"));

  e = error_of({part(box), part(flipped(box))}, unit10);
  CHECK(has(e, "part 1 encloses a negative volume"));
  CHECK(has(e, "inside out"));

  auto one_flipped = box;
  std::swap(one_flipped.triangles[4][1], one_flipped.triangles[4][2]);
  e = error_of({part(one_flipped)}, unit10);
  CHECK(has(e, "not consistently oriented"));
  CHECK(has(e, "triangles 1 and 4 run along the edge from vertex 0 (2, 2, 2) to vertex 1 (6, 2, 2)"));

  auto fin = box;  // a third triangle on the edge from corner 0 to corner 1
  fin.vertices.push_back({4, 0, 0});
  fin.triangles.push_back({0, 1, 8});
  fin.triangles.push_back({1, 0, 8});
  e = error_of({part(fin)}, unit10);
  CHECK(has(e, "not manifold"));
  CHECK(has(e, "shared by 4 triangles"));

  const auto crossing = merge(box, gv::phantom::box_mesh({4.5, 3, 3}, {8, 5, 5}));
  e = error_of({part(crossing)}, unit10);
  CHECK(has(e, "intersect"));
  CHECK(has(e, "triangles "));
  CHECK(has(e, "self-intersections"));
  // the same two boxes as a soup are fine for the winding rule
  gv::voxelize_options w;
  w.rule = gv::inside_rule::winding;
  CHECK(error_of({part(crossing)}, unit10, w) == "no error");

  CHECK(has(error_of({part(triangle_mesh{})}, unit10), "has no triangles"));
  triangle_mesh flat;
  flat.vertices = {{1, 1, 1}, {2, 2, 2}, {3, 3, 3}};
  flat.triangles = {{0, 1, 2}, {2, 1, 0}};
  CHECK(has(error_of({part(flat)}, unit10), "all 2 triangles have zero area"));
  auto far = box;
  far.vertices[3] = {1e30, 0, 0};
  CHECK(has(error_of({part(far)}, unit10), "2^24 voxels"));
  auto bad = box;
  bad.triangles[2][1] = 99;
  CHECK(has(error_of({part(bad)}, unit10), "triangle 2 refers to vertex 99"));
}

TEST_CASE("voxelize: the winding rule fills an open sphere and follows the solid-angle sum") {
  auto sphere = gv::phantom::ellipsoid_mesh({5, 5, 5}, {3.7, 3.6, 3.9}, 2);
  const auto full = gv::voxelize<float>({part(sphere)}, unit10);
  sphere.triangles.erase(sphere.triangles.begin() + 17);
  CHECK(has(error_of({part(sphere)}, unit10), "not closed"));
  gv::voxelize_options o;
  o.rule = gv::inside_rule::winding;
  const auto v = gv::voxelize<float>({part(sphere)}, unit10, o);
  CHECK(v.label.values() == full.label.values());
  // half a sphere: the winding number varies continuously; compare with brute force away from 1/2
  auto half = gv::phantom::ellipsoid_mesh({5, 5, 5}, {3.7, 3.6, 3.9}, 2);
  std::vector<std::array<std::uint32_t, 3>> keep;
  for (const auto& t : half.triangles)
    if (half.vertices[t[0]][2] + half.vertices[t[1]][2] + half.vertices[t[2]][2] < 3 * 5.6) keep.push_back(t);
  half.triangles = keep;
  const auto hv = gv::voxelize<float>({part(half)}, unit10, o);
  int judged = 0, wrong = 0;
  for (gv::index_t i = 0; i < unit10.size(); ++i) {
    const double w = winding(half, unit10.world(unit10.coords(i)));
    if (std::abs(w - 0.5) < 0.05) continue;
    ++judged;
    if ((hv.label[i] != 0) != (w >= 0.5)) ++wrong;
  }
  CHECK(judged > 900);
  CHECK(wrong == 0);
  // a closed mesh under the winding rule: exactly the closed rule
  const auto tor = gv::phantom::torus_mesh({5, 5, 5}, 3, 1.4, 19, 11);
  CHECK(gv::voxelize<float>({part(tor)}, unit10, o).label.values() == gv::voxelize<float>({part(tor)}, unit10).label.values());
}

TEST_CASE("voxelize: overlap rules") {
  const auto a = part(gv::phantom::box_mesh({1.5, 1.5, 1.5}, {5.5, 5.5, 5.5}), 3.0, 0, "a");
  const auto b = part(gv::phantom::box_mesh({3.5, 3.5, 3.5}, {7.5, 7.5, 7.5}), 5.0, 0, "b");
  gv::voxelize_options o;
  o.outside_value = -1;
  auto at = [&](gv::overlap_rule r) {
    o.overlap = r;
    const auto v = gv::voxelize<float>({a, b}, unit10, o);
    CHECK(v.stiffness({1, 1, 1}) == -1.0f);
    CHECK(v.label({2, 2, 2}) == 1);
    CHECK(v.label({7, 7, 7}) == 2);
    return v.label({4, 4, 4});
  };
  CHECK(at(gv::overlap_rule::last_wins) == 2);
  CHECK(at(gv::overlap_rule::first_wins) == 1);
  CHECK(at(gv::overlap_rule::max_value) == 2);
  CHECK(at(gv::overlap_rule::min_value) == 1);
  o.overlap = gv::overlap_rule::error;
  const std::string e = error_of({a, b}, unit10, o);
  CHECK(has(e, "part 0 (\"a\") and part 1 (\"b\") overlap"));
  CHECK(has(e, "voxel (4, 4, 4)"));
}

TEST_CASE("voxelize: fraction and surface voxels") {
  const auto tor = gv::phantom::torus_mesh({5, 5, 5}, 3, 1.4, 30, 16);
  gv::voxelize_options o;
  o.fraction_samples = 1;
  auto v = gv::voxelize<float>({part(tor)}, unit10, o);
  for (gv::index_t i = 0; i < unit10.size(); ++i) CHECK(v.fraction[i] == (v.label[i] != 0 ? 1.0f : 0.0f));
  o.fraction_samples = 4;
  v = gv::voxelize<float>({part(tor)}, unit10, o);
  double sum = 0;
  bool partial = false;
  for (float f : v.fraction) {
    CHECK(f >= 0.0f);
    CHECK(f <= 1.0f);
    sum += f;
    partial = partial || (f > 0 && f < 1);
  }
  CHECK(partial);
  CHECK(sum == doctest::Approx(v.stats.mesh_volume).epsilon(0.02));

  o.fraction_samples = 0;
  o.surface_inside = true;
  const auto s = gv::voxelize<float>({part(tor)}, unit10, o);
  const auto plain = gv::voxelize<float>({part(tor)}, unit10);
  std::size_t more = 0;
  for (gv::index_t i = 0; i < unit10.size(); ++i) {
    if (plain.label[i]) CHECK(s.label[i] != 0);
    more += s.label[i] && !plain.label[i];
  }
  CHECK(more > 0);
  // the voxels of a box's faces: a box from 2.5 to 5.5 meets the cubes of voxels 2..6 (touching counts)
  const auto sb = gv::voxelize<float>({part(gv::phantom::box_mesh({2.5, 2.5, 2.5}, {5.5, 5.5, 5.5}))}, unit10, o);
  CHECK(count_label(sb.label, 1) == 5 * 5 * 5);
  const auto sc = gv::voxelize<float>({part(gv::phantom::box_mesh({2.6, 2.6, 2.6}, {5.4, 5.4, 5.4}))}, unit10, o);
  CHECK(count_label(sc.label, 1) == 3 * 3 * 3);  // voxels 3..5: the cube of 2 ends at 2.5
}

TEST_CASE("phantom meshes and the mesh writers") {
  CHECK(gv::phantom::box_mesh({0, 0, 0}, {1, 2, 3}).triangles.size() == 12);
  const auto e = gv::phantom::ellipsoid_mesh({1, 2, 3}, {4, 5, 6}, 3);
  CHECK(e.triangles.size() == 20 * 64);
  const auto t = gv::phantom::torus_mesh({0, 0, 0}, 10, 3, 40, 20);
  CHECK(t.triangles.size() == 1600);
  gv::voxelize_options o;
  o.voxel_size = {1, 1, 1};
  auto v = gv::voxelize<float>({part(e)}, o);  // closed and outward, or the checks throw
  CHECK(v.stats.mesh_volume == doctest::Approx(4.0 / 3 * 3.14159265 * 120).epsilon(0.02));
  v = gv::voxelize<float>({part(t)}, o);
  CHECK(v.stats.mesh_volume == doctest::Approx(2 * 3.14159265 * 3.14159265 * 10 * 9).epsilon(0.03));
  o.voxel_size = {2, 2, 2};
  const auto limb = gv::voxelize<float>(gv::phantom::limb(), o);
  CHECK(limb.stiffness.geometry().extent(0) >= 60);
  CHECK(count_label(limb.label, 1) > 0);
  CHECK(count_label(limb.label, 2) > 0);
  CHECK(limb.stiffness(limb.label.geometry().nearest_voxel({0, 0, 0})) == 1.5e10f);

  const std::string stl = "voxelize_test_mesh.stl", obj = "voxelize_test_mesh.obj";
  gv::io::write_stl(stl, t);
  const auto rs = gv::io::read_stl(stl);
  CHECK(rs.triangles.size() == t.triangles.size());
  gv::io::write_obj(obj, t);
  const auto ro = gv::io::read_obj(obj);
  CHECK(ro.vertices == t.vertices);
  CHECK(ro.triangles == t.triangles);
  std::remove(stl.c_str());
  std::remove(obj.c_str());
  CHECK_THROWS_AS(gv::io::write_stl("/nonexistent-folder/x.stl", t), gv::io::io_error);
}

#pragma once
// Snapping a part to the lattice and the checks of inside_rule::closed: edges paired in opposite
// directions, a positive enclosed volume, no two triangles meeting other than along their shared
// edge or vertex (exact predicates).

#include <geovoronoi/detail/voxelize/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

namespace geovoronoi::detail::vox {

/// Snaps @p mesh onto grid @p g: vertices (merged when they land on the same lattice point) and the
/// triangles that keep a non-zero area. @p who prefixes errors ("geovoronoi::voxelize: part 1").
inline snapped_part snap_part(const grid<3>& g, const triangle_mesh& mesh, const std::string& who) {
  snapped_part sp;
  sp.pts = snap_all<3>(g, mesh.vertices, who.c_str());
  const std::size_t nv = sp.pts.size();
  std::vector<std::uint32_t> by(nv);
  std::iota(by.begin(), by.end(), std::uint32_t(0));
  std::sort(by.begin(), by.end(), [&](std::uint32_t x, std::uint32_t y) {
    return sp.pts[x] < sp.pts[y] || (sp.pts[x] == sp.pts[y] && x < y);
  });
  sp.canon.resize(nv);
  for (std::size_t i = 0; i < nv; ++i)
    sp.canon[by[i]] = (i > 0 && sp.pts[by[i]] == sp.pts[by[i - 1]]) ? sp.canon[by[i - 1]] : by[i];
  sp.tris.reserve(mesh.triangles.size());
  // signed volume in world units, about the first vertex (smaller terms, less cancellation)
  const auto& o = mesh.vertices.empty() ? std::array<double, 3>{0, 0, 0} : mesh.vertices[0];
  double vol = 0.0;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] >= nv)
        throw std::invalid_argument(who + ": triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(tri[k]) + " of " + std::to_string(nv));
    lattice_triangle lt;
    for (int i = 0; i < 3; ++i) {
      lt.v[i] = sp.pts[tri[i]];
      lt.id[i] = sp.canon[tri[i]];
    }
    if (degenerate(lt.v[0], lt.v[1], lt.v[2])) {
      ++sp.degenerate;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      lt.n[k] = normal_component(lt.v[0], lt.v[1], lt.v[2], k);
      lt.lo[k] = std::min({lt.v[0][k], lt.v[1][k], lt.v[2][k]});
      lt.hi[k] = std::max({lt.v[0][k], lt.v[1][k], lt.v[2][k]});
    }
    lt.index = static_cast<std::uint32_t>(t);
    sp.tris.push_back(lt);
    const auto &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    const double ax = a[0] - o[0], ay = a[1] - o[1], az = a[2] - o[2];
    const double bx = b[0] - o[0], by_ = b[1] - o[1], bz = b[2] - o[2];
    const double cx = c[0] - o[0], cy = c[1] - o[1], cz = c[2] - o[2];
    vol += ax * (by_ * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by_ * cx);
  }
  sp.volume = vol / 6.0;
  if (mesh.triangles.empty()) throw std::invalid_argument(who + " has no triangles");
  if (sp.tris.empty())
    throw std::invalid_argument(who + ": all " + std::to_string(mesh.triangles.size()) +
                                " triangles have zero area on the lattice of 2^-16 voxel (degenerate mesh)");
  return sp;
}

/// Why the part's edges are not paired (empty when every undirected edge, between merged vertices,
/// is used by exactly two triangles in opposite directions).
inline std::string edge_problem(const triangle_mesh& mesh, const snapped_part& sp) {
  struct half_edge {
    std::uint32_t lo, hi, tri;
    int dir;
  };
  std::vector<half_edge> es;
  es.reserve(sp.tris.size() * 3);
  for (const auto& t : sp.tris)
    for (int e = 0; e < 3; ++e) {
      const std::uint32_t u = t.id[e], v = t.id[(e + 1) % 3];
      es.push_back({std::min(u, v), std::max(u, v), t.index, u < v ? 1 : -1});
    }
  std::sort(es.begin(), es.end(), [](const half_edge& x, const half_edge& y) {
    return std::tie(x.lo, x.hi, x.tri, x.dir) < std::tie(y.lo, y.hi, y.tri, y.dir);
  });
  auto edge = [&](const half_edge& e) {
    return "the edge from vertex " + std::to_string(e.lo) + " " + point_text(mesh.vertices[e.lo]) + " to vertex " +
           std::to_string(e.hi) + " " + point_text(mesh.vertices[e.hi]);
  };
  for (std::size_t i = 0; i < es.size();) {
    std::size_t j = i;
    while (j < es.size() && es[j].lo == es[i].lo && es[j].hi == es[i].hi) ++j;
    const std::size_t n = j - i;
    if (n == 1)
      return "the mesh is not closed: " + edge(es[i]) + " belongs to triangle " + std::to_string(es[i].tri) +
             " only (an open edge)";
    if (n > 2) {
      std::string list;
      for (std::size_t k = i; k < j && k < i + 6; ++k) list += (k > i ? ", " : "") + std::to_string(es[k].tri);
      if (n > 6) list += ", ...";
      return "the mesh is not manifold: " + edge(es[i]) + " is shared by " + std::to_string(n) + " triangles (" + list +
             ")";
    }
    if (es[i].dir == es[i + 1].dir)
      return "the mesh is not consistently oriented: triangles " + std::to_string(es[i].tri) + " and " +
             std::to_string(es[i + 1].tri) + " run along " + edge(es[i]) +
             " in the same direction (one of them is flipped)";
    i = j;
  }
  return {};
}

/// True when closed triangles @p x and @p y (no shared vertex) meet.
inline bool triangles_meet(const lattice_triangle& x, const lattice_triangle& y) noexcept {
  auto one_side = [](const lattice_triangle& p, const lattice_triangle& q) {
    const int s0 = orient3d(p.v[0], p.v[1], p.v[2], q.v[0]), s1 = orient3d(p.v[0], p.v[1], p.v[2], q.v[1]),
              s2 = orient3d(p.v[0], p.v[1], p.v[2], q.v[2]);
    return (s0 > 0 && s1 > 0 && s2 > 0) || (s0 < 0 && s1 < 0 && s2 < 0);
  };
  if (one_side(x, y) || one_side(y, x)) return false;
  for (int e = 0; e < 3; ++e) {
    if (segment_meets_triangle(y.v[e], y.v[(e + 1) % 3], x.v[0], x.v[1], x.v[2])) return true;
    if (segment_meets_triangle(x.v[e], x.v[(e + 1) % 3], y.v[0], y.v[1], y.v[2])) return true;
  }
  return false;
}

/// How @p x and @p y meet beyond what they share (empty when they do not).
inline std::string pair_problem(const lattice_triangle& x, const lattice_triangle& y) {
  int shared = 0, xs[3], ys[3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (x.id[i] == y.id[j]) {
        xs[shared] = i;
        ys[shared] = j;
        ++shared;
      }
  if (shared == 0) return triangles_meet(x, y) ? "intersect" : "";
  if (shared == 1) {
    // the intersection, a convex set holding the shared vertex, reaches past it only through an
    // edge opposite the shared vertex meeting the other triangle
    const int i = xs[0], j = ys[0];
    if (segment_meets_triangle(x.v[(i + 1) % 3], x.v[(i + 2) % 3], y.v[0], y.v[1], y.v[2]) ||
        segment_meets_triangle(y.v[(j + 1) % 3], y.v[(j + 2) % 3], x.v[0], x.v[1], x.v[2]))
      return "intersect (beyond their shared vertex " + std::to_string(x.id[i]) + ")";
    return "";
  }
  if (shared >= 3) return "use the same three vertices";
  // a shared edge: they meet beyond it only when coplanar and on the same side of it
  const int xa = 3 - xs[0] - xs[1], ya = 3 - ys[0] - ys[1];
  const lattice3 &u = x.v[xs[0]], &v = x.v[xs[1]], &a = x.v[xa], &b = y.v[ya];
  if (orient3d(u, v, a, b) != 0) return "";
  auto mag = [](int128_t z) { return z < 0 ? -z : z; };
  const int drop = (mag(x.n[0]) >= mag(x.n[1]) && mag(x.n[0]) >= mag(x.n[2])) ? 0 : (mag(x.n[1]) >= mag(x.n[2]) ? 1 : 2);
  const int p = drop == 0 ? 1 : 0, q = drop == 2 ? 1 : 2;
  const int oa = orient2d({u[p], u[q]}, {v[p], v[q]}, {a[p], a[q]});
  const int ob = orient2d({u[p], u[q]}, {v[p], v[q]}, {b[p], b[q]});
  if (oa * ob > 0) return "overlap (folded onto each other across their shared edge)";
  return "";
}

/**
 * The first pair of triangles (smallest pair of mesh indices) that meet other than along a shared
 * edge or vertex, as "triangles I and J intersect ...", or empty. Triangles are bucketed in a
 * uniform grid over the part's lattice bounds; a pair is tested once, in the first cell both cover.
 */
inline std::string self_intersection(const snapped_part& sp) {
  const auto& T = sp.tris;
  const std::size_t n = T.size();
  if (n < 2) return {};
  std::int64_t lo[3], hi[3];
  double mean = 0.0;
  for (int k = 0; k < 3; ++k) {
    lo[k] = T[0].lo[k];
    hi[k] = T[0].hi[k];
  }
  for (const auto& t : T) {
    double ext = 0.0;
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], t.lo[k]);
      hi[k] = std::max(hi[k], t.hi[k]);
      ext = std::max(ext, double(t.hi[k] - t.lo[k]));
    }
    mean += ext;
  }
  mean /= double(n);
  // cells about twice the mean triangle size, at most 2^10 per axis and about 8 n in all
  std::int64_t cell = std::max<std::int64_t>(1, static_cast<std::int64_t>(2.0 * mean));
  std::int64_t res[3];
  for (;;) {
    double total = 1.0;
    for (int k = 0; k < 3; ++k) {
      res[k] = (hi[k] - lo[k]) / cell + 1;
      total *= double(res[k]);
    }
    if (total <= 8.0 * double(n) + 64.0 && res[0] <= 1024 && res[1] <= 1024 && res[2] <= 1024) break;
    cell *= 2;
  }
  std::vector<std::pair<std::uint64_t, std::uint32_t>> entries;
  auto cell_of = [&](std::int64_t x, int k) { return (x - lo[k]) / cell; };
  for (std::uint32_t t = 0; t < n; ++t) {
    const auto& tr = T[t];
    for (std::int64_t z = cell_of(tr.lo[2], 2); z <= cell_of(tr.hi[2], 2); ++z)
      for (std::int64_t y = cell_of(tr.lo[1], 1); y <= cell_of(tr.hi[1], 1); ++y)
        for (std::int64_t x = cell_of(tr.lo[0], 0); x <= cell_of(tr.hi[0], 0); ++x)
          entries.push_back({std::uint64_t((z * res[1] + y) * res[0] + x), t});
  }
  std::sort(entries.begin(), entries.end());
  std::uint32_t best_a = 0, best_b = 0;
  std::string best;
  for (std::size_t i = 0; i < entries.size();) {
    std::size_t j = i;
    while (j < entries.size() && entries[j].first == entries[i].first) ++j;
    const std::uint64_t key = entries[i].first;
    for (std::size_t p = i; p < j; ++p)
      for (std::size_t q = p + 1; q < j; ++q) {
        const auto &x = T[entries[p].second], &y = T[entries[q].second];
        bool apart = false;
        std::int64_t first[3];
        for (int k = 0; k < 3; ++k) {
          if (x.hi[k] < y.lo[k] || y.hi[k] < x.lo[k]) apart = true;
          first[k] = cell_of(std::max(x.lo[k], y.lo[k]), k);
        }
        if (apart) continue;
        if (std::uint64_t((first[2] * res[1] + first[1]) * res[0] + first[0]) != key) continue;  // tested elsewhere
        std::uint32_t a = x.index, b = y.index;
        if (a > b) std::swap(a, b);
        if (!best.empty() && std::make_pair(a, b) >= std::make_pair(best_a, best_b)) continue;
        const std::string why = pair_problem(x, y);
        if (!why.empty()) {
          best = why;
          best_a = a;
          best_b = b;
        }
      }
    i = j;
  }
  if (best.empty()) return {};
  return "triangles " + std::to_string(best_a) + " and " + std::to_string(best_b) + " " + best;
}

}  // namespace geovoronoi::detail::vox

#pragma once
/// @file cut_from_mesh.hpp
/// @brief Builds a cut_set from geometry in world coordinates: a triangle mesh (3D), a blade swept
///        over time (3D) or polylines (2D), with exact intersection tests.
///
/// **The rule.** Grid edge (u, v) is cut when the closed segment between the two voxel centres
/// shares at least one point with a closed triangle (3D) or a closed polyline segment (2D).
/// Touching counts: a segment through a triangle's edge or vertex, a voxel centre lying on a
/// triangle, a segment lying in a triangle's plane and overlapping it all cut the edge.
///
/// **Exactness.** Each vertex is moved once into the grid's continuous index space
/// (D^T (p - origin) / spacing per axis, skipping zero entries of D as grid::nearest_voxel does,
/// so an axis-aligned grid with unit spacing and zero origin transforms exactly) and snapped to the
/// lattice of 2^-16 voxel: floor(x * 2^16 + 0.5). That rounding is the only one; every test after it
/// is exact integer arithmetic (detail/exact.hpp), so the result never depends on the order of
/// operations, the compiler or the platform. Voxel centres are lattice points. Vertices must lie
/// within 2^24 voxels of voxel 0 along each index axis (lattice coordinates up to 2^40 keep the
/// 128-bit predicates exact). Triangles that collapse to a line or a point on the lattice are
/// skipped and counted in cut_stats::degenerate (such a set has no area; it could only touch edges
/// at isolated points). In 2D a zero-length segment is kept: it cuts the edges through its point.
///
/// **Cost.** For each triangle only the edges leaving voxels in its index-space bounding box,
/// grown by one voxel, can be cut. Within that box the voxels are walked in columns along the axis
/// where the triangle's normal is largest, and only the (at most 9) voxels of each column within 3.5
/// voxels of the plane are visited, so the work is proportional to the area of the box's
/// projection, not its volume. Edges whose ends lie strictly on one side of the plane (exact
/// orient3d) are rejected before the full segment/triangle test.

#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/exact.hpp>
#include <geovoronoi/detail/lattice.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/mesh.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

/// What a cut construction looked at.
struct cut_stats {
  std::size_t primitives = 0;   ///< triangles (segments in 2D) that were used
  std::size_t degenerate = 0;   ///< triangles skipped because they collapse to a line on the lattice (3D only)
  std::size_t voxels_visited = 0; ///< voxels whose forward edges were examined
  std::size_t edges_tested = 0; ///< exact segment tests performed
};

namespace detail {

/// The voxel box [lo, hi] (clamped to the grid) whose edges can meet a primitive with lattice
/// bounding box [mn, mx]; false when it misses the grid.
template <int Dim>
bool edge_box(const grid<Dim>& g, const std::array<std::int64_t, Dim>& mn, const std::array<std::int64_t, Dim>& mx,
              std::array<index_t, Dim>& lo, std::array<index_t, Dim>& hi) noexcept {
  for (int a = 0; a < Dim; ++a) {
    lo[a] = std::max<index_t>(lattice_ceil(mn[a]) - 1, 0);
    hi[a] = std::min<index_t>(lattice_floor(mx[a]) + 1, g.extent(a) - 1);
    if (lo[a] > hi[a]) return false;
  }
  return true;
}

/// Forward directions of connectivity<N> and their offsets.
template <int N>
struct forward_stencil {
  static constexpr int count = N / 2;
  std::array<std::array<int, 3>, N / 2> off{};
  forward_stencil() {
    constexpr auto o = connectivity<N>::offsets();
    for (int f = 0; f < count; ++f)
      for (int a = 0; a < connectivity<N>::dim; ++a) off[f][a] = o[N / 2 + f][a];
  }
};

}  // namespace detail

/**
 * @brief The cut of grid @p g under connectivity<N> by the triangles of @p mesh (world coordinates).
 *
 * See this file's notes for the rule (closed segment meets closed triangle), the single rounding
 * and the cost.
 * @param stats if not null, receives what was examined.
 * @throws std::invalid_argument for a vertex that is not finite or lies more than 2^24 voxels from
 *         the grid, a triangle index out of range, or a grid longer than 2^24 voxels along an axis.
 *
 * @code
 * auto mesh = geovoronoi::io::read_mesh("scalpel.stl");
 * geovoronoi::cut_set<3> cuts = geovoronoi::cut_from_mesh(g, geovoronoi::connectivity<26>{}, mesh);
 * @endcode
 */
template <int N>
cut_set<3> cut_from_mesh(const grid<3>& g, connectivity<N> conn, const triangle_mesh& mesh, cut_stats* stats = nullptr) {
  static_assert(connectivity<N>::dim == 3, "geovoronoi::cut_from_mesh: needs a 3D connectivity (6, 18 or 26)");
  const char* who = "geovoronoi::cut_from_mesh";
  detail::check_lattice_grid(g, who);
  const auto pts = detail::snap_all<3>(g, mesh.vertices, who);
  const detail::forward_stencil<N> fw;
  constexpr std::int64_t one = std::int64_t(1) << detail::lattice_bits;
  cut_builder<3> out(g, conn);
  cut_stats st;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] >= pts.size())
        throw std::invalid_argument(std::string(who) + ": triangle " + std::to_string(t) + " refers to vertex " +
                                    std::to_string(tri[k]) + " of " + std::to_string(pts.size()));
    const detail::lattice3 &a = pts[tri[0]], &b = pts[tri[1]], &c = pts[tri[2]];
    if (detail::degenerate(a, b, c)) {
      ++st.degenerate;
      continue;
    }
    ++st.primitives;
    std::array<std::int64_t, 3> mn, mx;
    for (int k = 0; k < 3; ++k) {
      mn[k] = std::min({a[k], b[k], c[k]});
      mx[k] = std::max({a[k], b[k], c[k]});
    }
    std::array<index_t, 3> lo, hi;
    if (!detail::edge_box<3>(g, mn, mx, lo, hi)) continue;
    // walk the box in columns along the axis w where the normal is largest: the plane moves by at
    // most one voxel along w per voxel step across, so an edge whose ends are not strictly on one
    // side of it starts within 3 voxels of the plane's crossing of its column
    const detail::int128_t n[3] = {detail::normal_component(a, b, c, 0), detail::normal_component(a, b, c, 1),
                                   detail::normal_component(a, b, c, 2)};
    auto mag = [](detail::int128_t x) { return x < 0 ? -x : x; };
    const int w = (mag(n[0]) >= mag(n[1]) && mag(n[0]) >= mag(n[2])) ? 0 : (mag(n[1]) >= mag(n[2]) ? 1 : 2);
    const int i_ax = w == 0 ? 1 : 0, j_ax = w == 2 ? 1 : 2;
    const double ri = static_cast<double>(n[i_ax]) / static_cast<double>(n[w]);
    const double rj = static_cast<double>(n[j_ax]) / static_cast<double>(n[w]);
    for (index_t i = lo[i_ax]; i <= hi[i_ax]; ++i)
      for (index_t j = lo[j_ax]; j <= hi[j_ax]; ++j) {
        // where the plane crosses this column, in voxels (rounding here only widens a margin)
        const double cross = (static_cast<double>(a[w]) - ri * static_cast<double>(i * one - a[i_ax]) -
                              rj * static_cast<double>(j * one - a[j_ax])) / static_cast<double>(one);
        const double from = std::max(static_cast<double>(lo[w]), std::floor(cross - 3.5));
        const double to = std::min(static_cast<double>(hi[w]), std::ceil(cross + 3.5));
        if (from > to) continue;
        for (index_t k = static_cast<index_t>(from); k <= static_cast<index_t>(to); ++k) {
          coord<3> u{};
          u[i_ax] = i;
          u[j_ax] = j;
          u[w] = k;
          ++st.voxels_visited;
          const detail::lattice3 pu{u[0] * one, u[1] * one, u[2] * one};
          const int su = detail::orient3d(a, b, c, pu);
          cut_mask_t mask = 0;
          for (int f = 0; f < fw.count; ++f) {
            const coord<3> v{u[0] + fw.off[f][0], u[1] + fw.off[f][1], u[2] + fw.off[f][2]};
            if (!g.contains(v)) continue;
            const detail::lattice3 pv{v[0] * one, v[1] * one, v[2] * one};
            if (su * detail::orient3d(a, b, c, pv) > 0) continue;
            ++st.edges_tested;
            if (detail::segment_meets_triangle(pu, pv, a, b, c)) mask |= cut_mask_t(1) << f;
          }
          if (mask) out.insert_unchecked(g.index(u), mask);
        }
      }
  }
  if (stats) *stats = st;
  return out.build();
}

/**
 * @brief The cut made by a blade swept over time: @p positions[t] is the blade (a polyline of
 *        world points) at step t; between steps t and t + 1, segment i sweeps the quad
 *        (P[t][i], P[t][i+1], P[t+1][i+1], P[t+1][i]), split along its diagonal P[t][i]-P[t+1][i+1]
 *        into two triangles. The union of those triangles cuts as in cut_from_mesh().
 * @throws std::invalid_argument when fewer than two steps are given, a step has fewer than two
 *         points, or the steps differ in point count; and as cut_from_mesh().
 */
template <int N>
cut_set<3> cut_from_blade_sweep(const grid<3>& g, connectivity<N> conn,
                                const std::vector<std::vector<point<3>>>& positions, cut_stats* stats = nullptr) {
  const char* who = "geovoronoi::cut_from_blade_sweep";
  if (positions.size() < 2)
    throw std::invalid_argument(std::string(who) + ": a sweep needs at least two blade positions, got " +
                                std::to_string(positions.size()));
  const std::size_t m = positions[0].size();
  if (m < 2) throw std::invalid_argument(std::string(who) + ": the blade needs at least two points");
  triangle_mesh mesh;
  for (std::size_t t = 0; t < positions.size(); ++t) {
    if (positions[t].size() != m)
      throw std::invalid_argument(std::string(who) + ": blade position " + std::to_string(t) + " has " +
                                  std::to_string(positions[t].size()) + " points, position 0 has " + std::to_string(m));
    for (const auto& p : positions[t]) mesh.vertices.push_back(p);
  }
  if (mesh.vertices.size() > 0xFFFFFFFFu) throw std::invalid_argument(std::string(who) + ": too many blade points");
  for (std::size_t t = 0; t + 1 < positions.size(); ++t)
    for (std::size_t i = 0; i + 1 < m; ++i) {
      const auto p00 = std::uint32_t(t * m + i), p01 = std::uint32_t(t * m + i + 1);
      const auto p10 = std::uint32_t((t + 1) * m + i), p11 = std::uint32_t((t + 1) * m + i + 1);
      mesh.triangles.push_back({p00, p01, p11});
      mesh.triangles.push_back({p00, p11, p10});
    }
  return cut_from_mesh(g, conn, mesh, stats);
}

/**
 * @brief The cut of 2D grid @p g under connectivity<N> (4 or 8) by polylines in world coordinates:
 *        an edge is cut when its closed segment meets a closed polyline segment (touching counts;
 *        exact orient2d on the same lattice as cut_from_mesh()). A polyline of one point cuts the
 *        edges through that point.
 * @throws std::invalid_argument for a point that is not finite or lies more than 2^24 voxels away.
 */
template <int N>
cut_set<2> cut_from_polylines(const grid<2>& g, connectivity<N> conn, const std::vector<std::vector<point<2>>>& lines,
                              cut_stats* stats = nullptr) {
  static_assert(connectivity<N>::dim == 2, "geovoronoi::cut_from_polylines: needs a 2D connectivity (4 or 8)");
  const char* who = "geovoronoi::cut_from_polylines";
  detail::check_lattice_grid(g, who);
  const detail::forward_stencil<N> fw;
  constexpr std::int64_t one = std::int64_t(1) << detail::lattice_bits;
  cut_builder<2> out(g, conn);
  cut_stats st;
  for (const auto& line : lines) {
    const auto pts = detail::snap_all<2>(g, line, who);
    for (std::size_t s = 0; s < pts.size(); ++s) {
      if (s + 1 == pts.size() && pts.size() > 1) break;
      const detail::lattice2 a = pts[s], b = pts[std::min(s + 1, pts.size() - 1)];
      ++st.primitives;
      std::array<std::int64_t, 2> mn{std::min(a[0], b[0]), std::min(a[1], b[1])};
      std::array<std::int64_t, 2> mx{std::max(a[0], b[0]), std::max(a[1], b[1])};
      std::array<index_t, 2> lo, hi;
      if (!detail::edge_box<2>(g, mn, mx, lo, hi)) continue;
      // as in 3D: columns along the axis w where the segment's normal is largest, visiting only the
      // voxels within 2.5 of the line's crossing (a zero-length segment keeps its whole, tiny box)
      const std::int64_t nx = a[1] - b[1], ny = b[0] - a[0];
      const int w = std::abs(nx) >= std::abs(ny) ? 0 : 1, i_ax = 1 - w;
      const double ri = (nx == 0 && ny == 0) ? 0.0 : static_cast<double>(w == 0 ? ny : nx) / static_cast<double>(w == 0 ? nx : ny);
      for (index_t i = lo[i_ax]; i <= hi[i_ax]; ++i) {
        double from = static_cast<double>(lo[w]), to = static_cast<double>(hi[w]);
        if (nx != 0 || ny != 0) {
          const double cross = (static_cast<double>(a[w]) - ri * static_cast<double>(i * one - a[i_ax])) / static_cast<double>(one);
          from = std::max(from, std::floor(cross - 2.5));
          to = std::min(to, std::ceil(cross + 2.5));
        }
        for (index_t k = static_cast<index_t>(from); from <= to && k <= static_cast<index_t>(to); ++k) {
          coord<2> u{};
          u[i_ax] = i;
          u[w] = k;
          ++st.voxels_visited;
          const detail::lattice2 pu{u[0] * one, u[1] * one};
          cut_mask_t mask = 0;
          for (int f = 0; f < fw.count; ++f) {
            const index_t vx = u[0] + fw.off[f][0], vy = u[1] + fw.off[f][1];
            if (vx < 0 || vy < 0 || vx >= g.extent(0) || vy >= g.extent(1)) continue;
            ++st.edges_tested;
            if (detail::segments_meet(pu, {vx * one, vy * one}, a, b)) mask |= cut_mask_t(1) << f;
          }
          if (mask) out.insert_unchecked(g.index(u), mask);
        }
      }
    }
  }
  if (stats) *stats = st;
  return out.build();
}

/// One polyline (see cut_from_polylines()).
template <int N>
cut_set<2> cut_from_polyline(const grid<2>& g, connectivity<N> conn, const std::vector<point<2>>& line,
                             cut_stats* stats = nullptr) {
  return cut_from_polylines(g, conn, std::vector<std::vector<point<2>>>{line}, stats);
}

}  // namespace geovoronoi

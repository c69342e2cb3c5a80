#pragma once
/// @file detail/exact.hpp
/// @brief Exact geometric predicates on an integer lattice: orientation tests and closed
///        segment/segment and segment/triangle intersection, in 128-bit integer arithmetic.
///
/// Coordinates are integers of magnitude at most lattice_limit (2^40). A difference is then below
/// 2^41, a 2 x 2 minor below 2^83 and a 3 x 3 determinant below 3 * 2^124 < 2^126: every value fits
/// a signed 128-bit integer, so every predicate below is exact.

#include <geovoronoi/config.hpp>

#include <array>
#include <cstdint>

namespace geovoronoi::detail {

__extension__ typedef __int128 int128_t;

/// Lattice points: integer coordinates, |x| <= lattice_limit.
using lattice3 = std::array<std::int64_t, 3>;
using lattice2 = std::array<std::int64_t, 2>;

/// Largest coordinate magnitude the predicates accept.
inline constexpr std::int64_t lattice_limit = std::int64_t(1) << 40;

inline int sign(int128_t x) noexcept { return (x > 0) - (x < 0); }

/// Sign of the signed area of (a, b, c): > 0 counter-clockwise.
inline int orient2d(const lattice2& a, const lattice2& b, const lattice2& c) noexcept {
  const int128_t abx = b[0] - a[0], aby = b[1] - a[1], acx = c[0] - a[0], acy = c[1] - a[1];
  return sign(abx * acy - aby * acx);
}

/// Sign of det[b - a, c - a, d - a] (the signed volume of tetrahedron a b c d, times 6).
inline int orient3d(const lattice3& a, const lattice3& b, const lattice3& c, const lattice3& d) noexcept {
  const int128_t bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
  const int128_t cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
  const std::int64_t dx = d[0] - a[0], dy = d[1] - a[1], dz = d[2] - a[2];
  const int128_t m0 = by * cz - bz * cy, m1 = bz * cx - bx * cz, m2 = bx * cy - by * cx;  // b x c
  return sign(m0 * dx + m1 * dy + m2 * dz);
}

/// True when point p lies on the closed segment [a, b], given that a, b, p are collinear.
inline bool on_collinear_segment(const lattice2& a, const lattice2& b, const lattice2& p) noexcept {
  for (int i = 0; i < 2; ++i) {
    const std::int64_t lo = a[i] < b[i] ? a[i] : b[i], hi = a[i] < b[i] ? b[i] : a[i];
    if (p[i] < lo || p[i] > hi) return false;
  }
  return true;
}

/// Closed segments [a, b] and [c, d] share at least one point (touching and overlapping count).
inline bool segments_meet(const lattice2& a, const lattice2& b, const lattice2& c, const lattice2& d) noexcept {
  const int o1 = orient2d(a, b, c), o2 = orient2d(a, b, d), o3 = orient2d(c, d, a), o4 = orient2d(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  if (o1 == 0 && on_collinear_segment(a, b, c)) return true;
  if (o2 == 0 && on_collinear_segment(a, b, d)) return true;
  if (o3 == 0 && on_collinear_segment(c, d, a)) return true;
  if (o4 == 0 && on_collinear_segment(c, d, b)) return true;
  return false;
}

/// Closed triangle (a, b, c) (non-degenerate) contains point p.
inline bool triangle_contains(const lattice2& a, const lattice2& b, const lattice2& c, const lattice2& p) noexcept {
  const int o1 = orient2d(a, b, p), o2 = orient2d(b, c, p), o3 = orient2d(c, a, p);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

/// True when the three points are collinear (the triangle has zero area).
inline bool degenerate(const lattice3& a, const lattice3& b, const lattice3& c) noexcept {
  const int128_t bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
  const int128_t cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
  return cy * bz - cz * by == 0 && cz * bx - cx * bz == 0 && cx * by - cy * bx == 0;
}

/// Component @p k of the (unnormalised) normal (b - a) x (c - a).
inline int128_t normal_component(const lattice3& a, const lattice3& b, const lattice3& c, int k) noexcept {
  const int i = (k + 1) % 3, j = (k + 2) % 3;
  return int128_t(b[i] - a[i]) * (c[j] - a[j]) - int128_t(b[j] - a[j]) * (c[i] - a[i]);
}

/**
 * @brief The closed segment [p, q] meets the closed triangle (a, b, c): touching a vertex or an
 *        edge counts, and so does any overlap when the segment lies in the triangle's plane.
 * @pre the triangle is not degenerate.
 */
inline bool segment_meets_triangle(const lattice3& p, const lattice3& q, const lattice3& a, const lattice3& b,
                                   const lattice3& c) noexcept {
  const int sp = orient3d(a, b, c, p), sq = orient3d(a, b, c, q);
  if (sp * sq > 0) return false;  // both strictly on one side
  if (sp == 0 && sq == 0) {
    // coplanar: drop the axis along which the normal is largest, where the projection keeps the area
    const int128_t bx = b[0] - a[0], by = b[1] - a[1], bz = b[2] - a[2];
    const int128_t cx = c[0] - a[0], cy = c[1] - a[1], cz = c[2] - a[2];
    int128_t n[3] = {cy * bz - cz * by, cz * bx - cx * bz, cx * by - cy * bx};
    for (auto& x : n) x = x < 0 ? -x : x;
    const int drop = (n[0] >= n[1] && n[0] >= n[2]) ? 0 : (n[1] >= n[2] ? 1 : 2);
    const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
    const lattice2 p2{p[i], p[j]}, q2{q[i], q[j]}, a2{a[i], a[j]}, b2{b[i], b[j]}, c2{c[i], c[j]};
    return triangle_contains(a2, b2, c2, p2) || triangle_contains(a2, b2, c2, q2) || segments_meet(p2, q2, a2, b2) ||
           segments_meet(p2, q2, b2, c2) || segments_meet(p2, q2, c2, a2);
  }
  // the segment crosses or touches the plane at one point; it lies in the closed triangle when the
  // line p q passes on the same side of (or through) all three edges
  const int o1 = orient3d(p, q, a, b), o2 = orient3d(p, q, b, c), o3 = orient3d(p, q, c, a);
  return (o1 >= 0 && o2 >= 0 && o3 >= 0) || (o1 <= 0 && o2 <= 0 && o3 <= 0);
}

}  // namespace geovoronoi::detail

#pragma once
// Translation-invariant problems: the fast exact path of the shape functions.
//
// When every voxel is inside the domain and every edge of a given direction has the same weight (a
// uniform metric, or any metric on a constant field), the geodesic distance between two voxels
// depends only on the absolute offset between them:
//
//     d(q, v) = L(|v - q|),   L(o) = d(corner, corner + o),
//
// bitwise, with L computed by ONE backend solve from voxel 0. Why this holds exactly in floating point:
// a backend's distance is the least fixed point of d(v) = min_u fl(d(u) + w(u, v)), which equals the
// minimum over paths of the left-to-right rounded sum of the path's weights (fl(x + w) is monotone in
// x). Clamp every point of any lattice path from q to v into the box spanned by q and v: each step
// keeps or zeroes each of its components, so it becomes a stencil step of weight <= the original (we
// check that dropping components never increases a weight) or vanishes, and the rounded sum can only
// decrease (fl(x + w) >= x for w >= 0). So the minimum over all paths is reached inside that box, which
// lies in the grid; and a box's paths map onto the corner box's by reflections, which keep every weight
// (also checked). L is therefore also monotone along each axis, which bounds balls by boxes.
//
// With L, a query's new cell C_q = {v : L(|v - q|) < d(v)} needs no search at all: the cell is closed
// under shortest-path predecessors of q, so it is 26-connected around q, and a box whose outer shell
// holds no cell voxel contains the whole cell. Per query we grow such a box, then scan it.

#include <geovoronoi/detail/dispatch.hpp>
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/metric.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::shape {

/// Same bits (a constant field must be constant bit for bit: -0 and +0 may weigh differently).
template <class T>
bool same_bits(T a, T b) noexcept {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

/**
 * Whether problem @p p is translation invariant in the sense above: every voxel inside the domain;
 * the metric ignores the field (uniform) or the field is one value; the weights of the stencil are
 * non-negative, equal under reflections and never increased by zeroing some of a step's components.
 */
template <class P>
bool translation_invariant(const P& p) {
  using T = typename P::value_type;
  using M = typename P::metric_type;
  // a cut breaks the translation invariance (a ball's shape depends on where the cut is)
  if constexpr (P::has_cuts) return false;
  const index_t n = p.geometry.size();
  if (n == 0) return false;
  const T f0 = p.field[0];
  constexpr bool field_free = std::is_same_v<M, geovoronoi::uniform>;
  for (index_t v = 0; v < n; ++v) {
    const T f = p.field[v];
    if (!detail::inside<M>(f)) return false;
    if (!field_free && !same_bits(f, f0)) return false;
  }
  constexpr int N = P::neighbours;
  T w[N];
  for (int k = 0; k < N; ++k) {
    w[k] = search::edge_weight(p.metric, p.edges.length[k], f0, f0);
    if (!(w[k] >= T(0)) || !(w[k] < std::numeric_limits<T>::infinity())) return false;
  }
  for (int k = 0; k < N; ++k) {
    const auto& a = p.edges.offset[k];
    // every reflection of step k, and every step with a subset of its components, is in the stencil
    // with a weight equal (reflection) or not larger (subset)
    for (int mask = 1; mask < 8; ++mask) {  // components kept
      for (int flip = 0; flip < 8; ++flip) {
        int b[3];
        bool zero = true;
        for (int c = 0; c < 3; ++c) {
          b[c] = (mask >> c & 1) ? ((flip >> c & 1) ? -a[c] : a[c]) : 0;
          zero = zero && b[c] == 0;
        }
        if (zero) continue;
        int j = -1;
        for (int m = 0; m < N && j < 0; ++m)
          if (p.edges.offset[m][0] == b[0] && p.edges.offset[m][1] == b[1] && p.edges.offset[m][2] == b[2]) j = m;
        if (j < 0) return false;
        const bool reflection = (b[0] != 0) == (a[0] != 0) && (b[1] != 0) == (a[1] != 0) && (b[2] != 0) == (a[2] != 0);
        if (reflection ? !same_bits(w[j], w[k]) : !(w[j] <= w[k])) return false;
      }
    }
  }
  return true;
}

/// A box of voxels, inclusive bounds per axis (unused axes of a 2D grid are [0, 0]).
struct box {
  index_t lo[3], hi[3];
  index_t size() const noexcept { return (hi[0] - lo[0] + 1) * (hi[1] - lo[1] + 1) * (hi[2] - lo[2] + 1); }
};

/**
 * The distance table L of a translation-invariant problem and the per-query scans built on it.
 * Read-only after construction; every scan takes its scratch from the caller, so one table serves
 * concurrent queries.
 */
template <class P>
class offset_table {
 public:
  using T = typename P::value_type;

  /// Computes L with one backend solve from voxel 0 (the policy does the search).
  template <class Policy>
  offset_table(const Policy& policy, const P& p) : p_(p) {
    for (int a = 0; a < 3; ++a) ext_[a] = a < P::dim ? p.geometry.extent(a) : 1;
    auto d = dispatch::solve(policy, p, std::vector<source<T>>{{index_t(0), T(0), label_t(0)}},
                             std::numeric_limits<T>::infinity(), false);
    table_ = std::move(d.distance.values());
  }

  const P& problem() const noexcept { return p_; }
  index_t extent(int a) const noexcept { return ext_[a]; }

  /// d(q, v) for voxel coordinates c (of v) and qc (of q).
  T distance(const index_t* c, const index_t* qc) const noexcept {
    return table_[std::size_t(dabs(c[0] - qc[0]) + ext_[0] * (dabs(c[1] - qc[1]) + ext_[1] * dabs(c[2] - qc[2])))];
  }

  /// The voxel coordinates of linear index v, unused axes 0.
  void coords(index_t v, index_t* c) const noexcept {
    c[0] = v % ext_[0];
    v /= ext_[0];
    c[1] = v % ext_[1];
    c[2] = v / ext_[1];
  }

  /// The table row of offsets (., |y - qy|, |z - qz|).
  const T* row(index_t y, index_t z, const index_t* qc) const noexcept {
    return table_.data() + std::size_t(ext_[0] * (dabs(y - qc[1]) + ext_[1] * dabs(z - qc[2])));
  }

  /**
   * Visits every voxel v of @p b (clipped to the grid) in increasing linear index with
   * f(v, x-coordinate, d(q, v)); f returns false to stop. Returns false if stopped.
   */
  template <class F>
  bool scan(const box& b, const index_t* qc, F&& f) const {
    for (index_t z = b.lo[2]; z <= b.hi[2]; ++z)
      for (index_t y = b.lo[1]; y <= b.hi[1]; ++y) {
        const T* row = this->row(y, z, qc);
        const index_t base = ext_[0] * (y + ext_[1] * z);
        for (index_t x = b.lo[0]; x <= b.hi[0]; ++x)
          if (!f(base + x, x, row[dabs(x - qc[0])])) return false;
      }
    return true;
  }

  /**
   * The smallest box around q (voxel coordinates qc) outside of which no voxel satisfies member(v, dq)
   * — given that the member set is closed under shortest-path predecessors of q (a new cell, a ball).
   * The box grows one slab at a time while the slab just outside a face (widened by one voxel on the
   * other axes, so that the whole outer shell is covered) holds a member.
   */
  template <class Member>
  box grow(const index_t* qc, Member&& member) const {
    box b{{qc[0], qc[1], qc[2]}, {qc[0], qc[1], qc[2]}};
    auto hit = [&](index_t v, index_t, T dq) { return !member(v, dq); };  // stop at the first member
    for (bool changed = true; changed;) {
      changed = false;
      for (int a = 0; a < P::dim; ++a)
        for (int dir = -1; dir <= 1; dir += 2)
          for (;;) {
            const index_t at = dir < 0 ? b.lo[a] - 1 : b.hi[a] + 1;
            if (at < 0 || at >= ext_[a]) break;
            box s;
            for (int c = 0; c < 3; ++c) {
              s.lo[c] = std::max<index_t>(0, b.lo[c] - 1);
              s.hi[c] = std::min<index_t>(ext_[c] - 1, b.hi[c] + 1);
            }
            s.lo[a] = s.hi[a] = at;
            if (scan(s, qc, hit)) break;  // no member on this slab
            (dir < 0 ? b.lo[a] : b.hi[a]) = at;
            changed = true;
          }
    }
    return b;
  }

  /// The voxels at distance < radius from voxel q, sorted, labelled 0: what bounded_solve returns for
  /// the single source q, without a search.
  sparse_solution<T> ball(index_t q, T radius) const {
    index_t qc[3];
    coords(q, qc);
    sparse_solution<T> r;
    scan(ball_box(qc, radius), qc, [&](index_t v, index_t, T dq) {
      if (dq < radius) {
        r.voxel.push_back(v);
        r.distance.push_back(dq);
        r.label.push_back(0);
      }
      return true;
    });
    return r;
  }

  /// The box bounding the ball d(q, v) < radius (L grows along every axis).
  box ball_box(const index_t* qc, T radius) const {
    box b;
    for (int a = 0; a < 3; ++a) {
      b.lo[a] = b.hi[a] = qc[a];
      if (a >= P::dim) continue;
      const index_t stride = a == 0 ? 1 : a == 1 ? ext_[0] : ext_[0] * ext_[1];
      index_t r = 0;
      while (r + 1 < ext_[a] && table_[std::size_t((r + 1) * stride)] < radius) ++r;
      b.lo[a] = std::max<index_t>(0, qc[a] - r);
      b.hi[a] = std::min<index_t>(ext_[a] - 1, qc[a] + r);
    }
    return b;
  }

 private:
  static index_t dabs(index_t x) noexcept { return x < 0 ? -x : x; }
  P p_;
  index_t ext_[3];
  std::vector<T> table_;
};

/**
 * Sibson / Laplace accumulation of one query q from the table, filling @p acc exactly as
 * accumulate_cell() does from a backend's new cell (same sets, same arithmetic). @p mask and @p members
 * are scratch.
 */
/// The members of a new cell during the Laplace pass, as parallel arrays (padded-mask index, voxel,
/// distance from the query); sized up, never down, so a worker allocates once.
template <class T>
struct cell_members {
  std::vector<index_t> i, v;
  std::vector<T> dq;
  void ensure(std::size_t n) {
    if (i.size() < n) i.resize(n), v.resize(n), dq.resize(n);
  }
};

template <class P, class D>
void accumulate_offset(const offset_table<P>& tab, const D& d, const std::vector<face<P::dim>>& faces, bool laplace,
                       index_t q, accumulators& acc, std::vector<unsigned char>& mask,
                       cell_members<typename P::value_type>& members, bool& any_facet) {
  using T = typename P::value_type;
  const P& p = tab.problem();
  const T* dist = d.distance.data();
  const label_t* lab = d.label.data();
  index_t qc[3];
  tab.coords(q, qc);
  const box b = tab.grow(qc, [dist](index_t v, T dq) { return dq < dist[v]; });
  acc.clear();
  any_facet = false;
  const index_t nx = tab.extent(0), ny = tab.extent(1);
  if (!laplace) {
    for (index_t z = b.lo[2]; z <= b.hi[2]; ++z)
      for (index_t y = b.lo[1]; y <= b.hi[1]; ++y) {
        const T* trow = tab.row(y, z, qc);
        const T* drow = dist + nx * (y + ny * z);
        const label_t* lrow = lab + nx * (y + ny * z);
        // the two halves of the row read the table backwards and forwards
        for (index_t x = b.lo[0]; x < qc[0]; ++x)
          if (trow[qc[0] - x] < drow[x] && lrow[x] >= 0) acc.touch(lrow[x]), ++acc.volume[lrow[x]];
        for (index_t x = std::max(b.lo[0], qc[0]); x <= b.hi[0]; ++x)
          if (trow[x - qc[0]] < drow[x] && lrow[x] >= 0) acc.touch(lrow[x]), ++acc.volume[lrow[x]];
      }
    return;
  }
  // Laplace: a membership mask over the box padded by one voxel on every side: 1 member, 0 not a
  // member, 2 outside the grid (never a facet). The box holds the whole cell, so the padding is 0 or 2.
  const index_t px = b.hi[0] - b.lo[0] + 3, py = b.hi[1] - b.lo[1] + 3, pz = b.hi[2] - b.lo[2] + 3;
  const index_t sy = px, sz = px * py;
  mask.assign(std::size_t(px * py * pz), 0);
  for (int a = 0; a < 3; ++a)
    for (int side = 0; side < 2; ++side) {
      if (side == 0 ? b.lo[a] > 0 : b.hi[a] < tab.extent(a) - 1) continue;  // the pad layer is in the grid
      index_t lo[3] = {0, 0, 0}, hi[3] = {px - 1, py - 1, pz - 1};
      lo[a] = hi[a] = side == 0 ? 0 : hi[a];
      for (index_t z = lo[2]; z <= hi[2]; ++z)
        for (index_t y = lo[1]; y <= hi[1]; ++y)
          for (index_t x = lo[0]; x <= hi[0]; ++x) mask[std::size_t(x + sy * y + sz * z)] = 2;
    }
  members.ensure(std::size_t(b.size()));
  index_t* mi = members.i.data();
  index_t* mv = members.v.data();
  T* mdq = members.dq.data();
  std::size_t count = 0;
  for (index_t z = b.lo[2]; z <= b.hi[2]; ++z)
    for (index_t y = b.lo[1]; y <= b.hi[1]; ++y) {
      const T* trow = tab.row(y, z, qc);
      const index_t base = nx * (y + ny * z);
      const index_t mrow = sy * (y - b.lo[1] + 1) + sz * (z - b.lo[2] + 1) + 1 - b.lo[0];
      for (index_t x = b.lo[0]; x <= b.hi[0]; ++x) {
        const T dq = trow[x < qc[0] ? qc[0] - x : x - qc[0]];
        const index_t v = base + x;
        if (!(dq < dist[v])) continue;
        mask[std::size_t(mrow + x)] = 1;
        mi[count] = mrow + x, mv[count] = v, mdq[count] = dq, ++count;
        const label_t o = lab[v];
        if (o >= 0) acc.touch(o), ++acc.volume[o];
      }
    }
  // facet pairs: a member with a 0 face neighbour; faces[j] crosses axis faces[j].axis in faces[j].dir
  const T f0 = p.field[0];
  T cface[6];
  index_t mstep[6];
  const index_t pstride[3] = {1, sy, sz};
  for (std::size_t j = 0; j < faces.size(); ++j) {
    cface[j] = search::edge_weight(p.metric, p.edges.length[faces[j].edge], f0, f0);  // every edge of a direction weighs the same
    mstep[j] = faces[j].dir * pstride[faces[j].axis];
  }
  const unsigned char* m = mask.data();
  for (std::size_t j0 = 0; j0 < count; ++j0) {
    const index_t i = mi[j0];
    if (m[i - 1] && m[i + 1] && m[i - sy] && m[i + sy] && m[i - sz] && m[i + sz]) continue;  // interior
    for (std::size_t j = 0; j < faces.size(); ++j) {
      if (m[i + mstep[j]] != 0) continue;
      const auto& f = faces[j];
      const index_t w = mv[j0] + f.delta;
      const label_t k = lab[w];
      if (k == no_label) continue;
      acc.touch(k);
      ++acc.faces[k][f.axis];
      any_facet = true;
      T h = mdq[j0] + cface[j];
      h = h + dist[w];
      if (double(h) < acc.h[k]) acc.h[k] = double(h);
    }
  }
}

}  // namespace geovoronoi::detail::shape

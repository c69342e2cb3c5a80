#pragma once
// Exact reuse of translation-invariant distance tables on piecewise-constant fields.
//
// Let f be a field value and R_f the voxels inside the domain whose field is f bit for bit. Inside R_f
// every edge weighs what it weighs in the constant-f problem, whose distances are a table of offsets
// L_f (translation_invariant.hpp: one solve, and L_f is non-decreasing in every |component|).
//
// For a query q in R_f, let m = the chessboard (Chebyshev) distance from q to the nearest voxel of B,
// the voxels with a 3^Dim neighbour in the grid of another class (another field value, or outside the
// domain). Then:
//
//  1. Every voxel x in the grid that is not in R_f has Chebyshev(x - q) >= m + 1: the cube of
//     half-width c - 1 around q (c = the distance to the nearest such x) lies in R_f, and x has a
//     neighbour y in that cube at Chebyshev c - 1, which is in B; so m <= c - 1.
//  2. A path from q that leaves R_f steps from some u in R_f to a voxel x outside R_f; x is a stencil
//     neighbour of u (offsets in {-1, 0, 1}), so Chebyshev(u - q) >= m. The path's prefix up to u stays
//     in R_f, so it costs at least L_f(|u - q|) (the invariant lattice's distance, which the table
//     holds), and some component of |u - q| is >= m, so by monotonicity the cost is at least
//     r = min over axes a of L_f(m e_a) (axes whose extent is <= m cannot have such u). Rounded sums
//     never decrease along a path (fl(s + w) >= s for w >= 0), so the whole path costs >= r.
//  3. If L_f(|v - q|) < r, then d_q(v) = L_f(|v - q|) exactly: the table's optimal lattice path to v
//     has every prefix cost < r, so by induction it never reaches a voxel at Chebyshev >= m from q
//     (whose L would be >= r): all its voxels are in the cube of half-width m - 1, which lies in R_f
//     (point 1), so it is a path of the problem and costs L_f(|v - q|); every other path either stays
//     in R_f (cost >= L_f(|v - q|) by the table's optimality) or leaves it (cost >= r > L_f(|v - q|)).
//
// So the ball S = {v : L_f(|v - q|) < r}, which lies in the cube of half-width m - 1, gets its exact
// distances from the table with no search. The search (fused_query.hpp) fills S's cell voxels from
// the table, queues those on S's rim, and continues outside S as before. A shortest path to a cell
// voxel outside S has a last voxel u in S, which is in the cell (a voxel of a shortest path to a cell
// voxel is in the cell) and is queued with its exact distance; fl(a + w) is monotone in a, so the
// continuation reproduces every distance bit for bit. A cell voxel of S whose 3^Dim neighbourhood lies
// in S (tested with L_f(min(|o| + 1, extent - 1)) < r, monotonicity again) needs no queueing.
//
// Tables are built only for values whose region has voxels with m >= 2 (smaller balls hold the query
// alone), at most max_tables of them, each on a box of the grid's spacing just large enough for the
// offsets it is read at (by the clamping argument the distances to offsets inside that box are those
// of the full grid), and only when the constant-f problem passes translation_invariant's checks.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/detail/dispatch.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <vector>

namespace geovoronoi::detail::shape {

template <class P>
class piecewise_tables {
 public:
  using T = typename P::value_type;
  static constexpr int max_tables = 8;

  struct table {
    std::vector<T> L;  // offsets (ox, oy, oz) at ox + e[0] * (oy + e[1] * oz)
    index_t e[3];
  };

  template <class Policy>
  piecewise_tables(const Policy& policy, const P& p) {
    // a cut breaks the constant-region balls (a ball may cross a cut): none with cuts, so empty(); the
    // tables' solves are then not even compiled (they solve P's own type, without cuts)
    if constexpr (P::has_cuts) {
      (void)policy;
      (void)p;
    } else {
      constexpr int Dim = P::dim;
      using M = typename P::metric_type;
      const index_t n = p.geometry.size();
      for (int a = 0; a < 3; ++a) ext_[a] = a < Dim ? p.geometry.extent(a) : 1;
      // classes: inside voxels by field bits; outside voxels share one class
      auto cls = [&](index_t v) -> std::uint64_t {
        const T f = p.field[v];
        if (!detail::inside<M>(f)) return ~std::uint64_t(0);
        std::uint64_t b = 0;
        std::memcpy(&b, &f, sizeof(T));
        return b;
      };
      // chessboard distance to B by a two-pass chamfer over the 3^Dim neighbourhood (exact for this metric)
      constexpr std::uint16_t far = std::numeric_limits<std::uint16_t>::max();
      m_.assign(std::size_t(n), far);
      const index_t sx = 1, sy = ext_[0], sz = ext_[0] * ext_[1];
      const int zr = Dim == 3 ? 1 : 0;
      bool any_b = false;
      for (index_t z = 0; z < ext_[2]; ++z)
        for (index_t y = 0; y < ext_[1]; ++y)
          for (index_t x = 0; x < ext_[0]; ++x) {
            const index_t v = x * sx + y * sy + z * sz;
            const std::uint64_t c = cls(v);
            bool b = false;
            for (int dz = -zr; dz <= zr && !b; ++dz)
              for (int dy = -1; dy <= 1 && !b; ++dy)
                for (int dx = -1; dx <= 1 && !b; ++dx) {
                  const index_t xx = x + dx, yy = y + dy, zz = z + dz;
                  if (xx < 0 || yy < 0 || zz < 0 || xx >= ext_[0] || yy >= ext_[1] || zz >= ext_[2]) continue;
                  b = cls(xx * sx + yy * sy + zz * sz) != c;
                }
            if (b) m_[std::size_t(v)] = 0, any_b = true;
          }
      if (!any_b) return;  // one class: the whole problem is translation-invariant or outside
      for (int pass = 0; pass < 2; ++pass) {
        const int s = pass == 0 ? 1 : -1;
        for (index_t i = 0; i < n; ++i) {
          const index_t v = pass == 0 ? i : n - 1 - i;
          const index_t z = v / sz, y = (v - z * sz) / sy, x = v - z * sz - y * sy;
          std::uint32_t best = m_[std::size_t(v)];
          // the half of the neighbourhood already visited in this pass's order
          for (int dz = -zr; dz <= 0; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                if (dz == 0 && (dy > 0 || (dy == 0 && dx >= 0))) continue;
                const index_t xx = x + s * dx, yy = y + s * dy, zz = z + s * dz;
                if (xx < 0 || yy < 0 || zz < 0 || xx >= ext_[0] || yy >= ext_[1] || zz >= ext_[2]) continue;
                best = std::min<std::uint32_t>(best, std::uint32_t(m_[std::size_t(xx * sx + yy * sy + zz * sz)]) + 1);
              }
          m_[std::size_t(v)] = std::uint16_t(std::min<std::uint32_t>(best, far - 1));
        }
      }
      // the values worth a table: most voxels with m >= 2 first
      struct stat {
        std::size_t count = 0;
        std::uint16_t max_m = 0;
        T value{};
      };
      std::map<std::uint64_t, stat> stats;
      for (index_t v = 0; v < n; ++v) {
        if (m_[std::size_t(v)] < 2) continue;
        const std::uint64_t c = cls(v);
        if (c == ~std::uint64_t(0)) continue;
        auto& s = stats[c];
        ++s.count;
        s.max_m = std::max(s.max_m, m_[std::size_t(v)]);
        s.value = p.field[v];
      }
      std::vector<std::pair<std::uint64_t, stat>> order(stats.begin(), stats.end());
      std::sort(order.begin(), order.end(), [](const auto& a, const auto& b) {
        return a.second.count > b.second.count || (a.second.count == b.second.count && a.first < b.first);
      });
      if (order.size() > std::size_t(max_tables)) order.resize(std::size_t(max_tables));
      for (const auto& [bits, s] : order) {
        coord<Dim> e{};
        index_t te[3] = {1, 1, 1};
        for (int a = 0; a < Dim; ++a) e[a] = te[a] = std::min<index_t>(ext_[a], index_t(s.max_m) + 1);
        point<Dim> sp{};
        for (int a = 0; a < Dim; ++a) sp[a] = p.geometry.spacing(a);
        const grid<Dim> g(e, sp);
        std::vector<T> f(std::size_t(g.size()), s.value);
        const auto pf = make_problem(g, f, p.metric, typename P::connectivity_type{});
        if (!translation_invariant(pf)) continue;
        auto d = dispatch::solve(policy, pf, std::vector<source<T>>{{index_t(0), T(0), label_t(0)}},
                                 std::numeric_limits<T>::infinity(), false);
        table t;
        t.L = std::move(d.distance.values());
        for (int a = 0; a < 3; ++a) t.e[a] = te[a];
        tables_.push_back(std::move(t));
        bits_.push_back(bits);
      }
      if (tables_.empty()) return;
      id_.assign(std::size_t(n), -1);
      for (index_t v = 0; v < n; ++v) {
        if (m_[std::size_t(v)] < 2) continue;
        const std::uint64_t c = cls(v);
        for (std::size_t t = 0; t < bits_.size(); ++t)
          if (bits_[t] == c) id_[std::size_t(v)] = std::int8_t(t);
      }
    }
}

  bool empty() const noexcept { return tables_.empty(); }
  /// The table of voxel v's region if its ball is worth using (m >= 2), else null.
  const table* table_of(index_t v) const noexcept {
    const int t = id_.empty() ? -1 : id_[std::size_t(v)];
    return t < 0 ? nullptr : &tables_[std::size_t(t)];
  }
  /// Chessboard distance from v to the nearest voxel with a neighbour of another class.
  index_t m(index_t v) const noexcept { return m_[std::size_t(v)]; }
  index_t extent(int a) const noexcept { return ext_[a]; }

  /**
   * The exact ball of query q's constant region: calls f(row, x, l, interior) for every voxel (x, y, z)
   * of it, with row = row_of(y, z) (the caller's linear index of voxel (0, y, z)), l its distance
   * from q out of the table, and interior true when its whole neighbourhood lies in the ball too (so
   * l needs no search from it). Returns false, calling nothing, where no ball applies.
   */
  template <class RowOf, class F>
  bool for_each_ball_voxel(index_t q, RowOf&& row_of, F&& f) const {
    const table* t = table_of(q);
    if (!t) return false;
    const index_t mq = m(q);
    index_t qc[3];
    {
      index_t v = q;
      qc[0] = v % ext_[0];
      v /= ext_[0];
      qc[1] = v % ext_[1];
      qc[2] = v / ext_[1];
    }
    const index_t stride[3] = {1, t->e[0], t->e[0] * t->e[1]};
    const T* L = t->L.data();
    T r = std::numeric_limits<T>::infinity();
    for (int a = 0; a < P::dim; ++a)
      if (mq <= ext_[a] - 1) r = std::min(r, L[mq * stride[a]]);
    if (!(T(0) < r) || !(r < std::numeric_limits<T>::infinity())) return false;
    index_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::max<index_t>(0, qc[a] - (mq - 1));
      hi[a] = std::min<index_t>(ext_[a] - 1, qc[a] + (mq - 1));
    }
    for (index_t z = lo[2]; z <= hi[2]; ++z) {
      const index_t oz = z > qc[2] ? z - qc[2] : qc[2] - z;
      const index_t iz = std::min(oz + 1, ext_[2] - 1);
      for (index_t y = lo[1]; y <= hi[1]; ++y) {
        const index_t oy = y > qc[1] ? y - qc[1] : qc[1] - y;
        const index_t iy = std::min(oy + 1, ext_[1] - 1);
        const T* row = L + stride[1] * oy + stride[2] * oz;
        const T* next = L + stride[1] * iy + stride[2] * iz;
        const index_t base = row_of(y, z);
        for (index_t x = lo[0]; x <= hi[0]; ++x) {
          const index_t ox = x > qc[0] ? x - qc[0] : qc[0] - x;
          const T l = row[ox];
          if (!(l < r)) continue;  // outside the ball
          f(base, x, l, next[std::min(ox + 1, ext_[0] - 1)] < r);
        }
      }
    }
    return true;
  }

  std::size_t bytes() const noexcept {
    std::size_t b = m_.capacity() * sizeof(std::uint16_t) + id_.capacity();
    for (const auto& t : tables_) b += t.L.capacity() * sizeof(T);
    return b;
  }

 private:
  index_t ext_[3];
  std::vector<std::uint16_t> m_;
  std::vector<std::int8_t> id_;
  std::vector<table> tables_;
  std::vector<std::uint64_t> bits_;
};

}  // namespace geovoronoi::detail::shape

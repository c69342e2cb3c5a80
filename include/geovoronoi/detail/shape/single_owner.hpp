#pragma once
// Sibson: the queries whose new cell provably steals from their own node only, found without a full
// search (their row is exactly 1 for that node). The argument is in docs/shape-functions.md ("Queries
// whose new cell stays in their own cell"); the comments below name its steps.

#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <queue>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::shape {

/**
 * Which queries' new cells may hold a voxel of another node than their own.
 *
 * Let q have label k and d(q) > 0, and let C_q hold a voxel of another label. Follow the search's
 * parents (in its settling order) from such a voxel back to q: the first voxel v of another label on
 * that chain is in C_q, and so are z_0 = q, ..., z_{m-1}, all of label k. With a_i the search's key of
 * z_i (a float sum, a_{i+1} = fl(a_i + c_i), c_i = c(z_i -> z_{i+1}) >= 0): a_i < d(z_i), and
 * fl(a_{m-1} + c) < d(v).
 *
 * 1. An upper bound U(z) of the key of any chain voxel, from a search backward from the frontiers
 *    (the constructor), in double, rounded up:
 *    * fl(a + c) < d(v) with d(v) a float implies a + c < d(v) (rounding is monotone), so a voxel z of
 *      label k with a neighbour v of another label (edge not cut, d(v) > 0) starts with
 *      U(z) = min(d(z), d(v) - c(z -> v));
 *    * a_{i+1} = fl(a_i + c_i) is at least a_i (monotone) and at least a_i + c_i - e with
 *      e <= min(c_i, 2u a_{i+1} + eta) (u half the epsilon of the distance type, eta its smallest subnormal), so
 *      a_{i+1} < U(z_{i+1}) implies a_i < U(z_{i+1}) - c_i + min(c_i, 2u U(z_{i+1}) + eta), and
 *      a_i < U(z_{i+1}) too: a step back from z to a neighbour w of the same label keeps the least of
 *      d(w), U(z) and that expression (a zero weight adds exactly: U(z)).
 *    Budgets never grow along a step, so the search settles each voxel once (largest first). A query
 *    never reached (U(q) = 0) has no chain: its row is 1 for its node.
 * 2. For a reached query, may_share() runs a float search from q with the search's own arithmetic and
 *    pruning, entering a voxel z of label k only with a key a < U(z) (every chain voxel passes), and
 *    answers yes at the first voxel of another label it would enter (a < d). By induction along the
 *    chain it reaches each chain voxel with the full search's key (it relaxes the same float sums and
 *    never goes below the full search), so it finds v when the chain exists; conversely every key it
 *    holds is a float path sum whose prefixes all passed the cell test, so what it enters is in C_q.
 *    Its answer is therefore exact, and it explores only voxels of C_q from which the frontier can be
 *    reached within the cell. It runs best first (least a - U(z)) and corrects keys that improve, so a
 *    query that does share finds its witness quickly.
 *
 * A negative weight breaks step 1 (a_{i+1} < a_i) and is an error of the search that meets it, so a
 * problem with one between two voxels of the domain gets no filter (negative_weight()): every query is
 * searched, and the search reports it as before.
 */
template <class P>
class single_owner_filter {
 public:
  using T = typename P::value_type;

  /// Scratch of one worker's searches: keys of the grid's size (reset through the touched list).
  struct scratch {
    std::vector<T> key;
    std::vector<index_t> touched;
    std::vector<std::pair<double, index_t>> heap;
    explicit scratch(index_t n) : key(std::size_t(n), std::numeric_limits<T>::infinity()) {}
  };

  single_owner_filter(const P& p, const T* dist, const label_t* lab) : p_(p), walk_(p), dist_(dist), lab_(lab) {
    const index_t n = p.geometry.size();
    constexpr double u = double(std::numeric_limits<T>::epsilon()) / 2;
    constexpr double eta = double(std::numeric_limits<T>::denorm_min());
    // a + b - c + m rounded up: the double operations err by at most 2^-52 of the operands' sum
    auto up = [](double x, double scale) { return x + std::ldexp(scale, -50); };
    if constexpr (!search::never_negative_v<typename P::metric_type>) {
      for (index_t z = 0; z < n && !negative_; ++z)
        if (stealable(z))
          walk_.for_each_neighbour(p, z, [&](int dir, index_t v) {
            if (p.inside(v) && p.weight(z, v, dir) < T(0)) negative_ = true;
          });
      if (negative_) return;
    }
    budget_.assign(std::size_t(n), 0.0);
    frontier_.assign(std::size_t(n), 0);
    std::vector<std::pair<double, index_t>> seeds;
    // 1. the frontier: z of label k, a neighbour v of another label across an edge that is not cut
    for (index_t z = 0; z < n; ++z) {
      if (!stealable(z)) continue;
      const label_t k = lab_[z];
      const double dz = double(dist_[z]);
      double b = 0;
      walk_.for_each_neighbour(p, z, [&](int dir, index_t v) {
        if (lab_[v] == k || !p.inside(v)) return;
        frontier_[std::size_t(z)] = 1;
        if (!stealable(v)) return;
        const T c = p.weight(z, v, dir);
        // a negative or NaN weight: keep the voxel (its search reports or refuses the edge itself)
        const double dv = double(dist_[v]);
        const double left = c >= T(0) ? up(dv - double(c), dv + double(c)) : dz;
        b = std::max(b, std::min(dz, left));
      });
      if (b > 0) {
        budget_[std::size_t(z)] = b;
        seeds.push_back({b, z});
      }
    }
    // 2. inward, within each cell, largest budget first
    std::priority_queue<std::pair<double, index_t>> heap(std::less<std::pair<double, index_t>>(), std::move(seeds));
    while (!heap.empty()) {
      const double b = heap.top().first;
      const index_t z = heap.top().second;
      heap.pop();
      if (b < budget_[std::size_t(z)]) continue;  // stale
      const label_t k = lab_[z];
      const T fz = p.field[z];
      walk_.for_each_neighbour(p, z, [&](int dir, index_t w) {
        if (lab_[w] != k || !stealable(w)) return;
        // the search from q steps w -> z: the weight of that direction
        const T c = search::edge_weight(p.metric, p.edges.length[opposite_direction(dir, P::neighbours)], p.field[w], fz);
        double nb = b;
        if (c > T(0)) {
          const double cd = double(c), m = std::min(cd, 2 * u * b + eta);
          nb = std::min(b, up(b - cd + m, b + cd + m));
        }
        nb = std::min(nb, double(dist_[w]));
        if (nb > budget_[std::size_t(w)]) {
          budget_[std::size_t(w)] = nb;
          heap.push({nb, w});
        }
      });
    }
  }

  /// Whether some edge between two voxels of the domain weighs less than 0 (then nothing is filtered).
  bool negative_weight() const noexcept { return negative_; }
  /// Bytes held (the budgets), and per worker scratch.
  std::size_t bytes() const noexcept { return budget_.capacity() * (sizeof(double) + 1); }
  static std::size_t scratch_bytes(index_t n) noexcept { return std::size_t(n) * (sizeof(T) + 20); }

  /// Whether the backward search reached @p q (U(q) > 0); if not, q's row is 1 for its node.
  bool reached(index_t q) const noexcept { return budget_[std::size_t(q)] > 0; }

  /// What may_share() found.
  enum class verdict { own_only, shares, undecided };

  /**
   * Whether the new cell of query @p q (label k, 0 < d(q) < inf) holds a voxel of another label:
   * own_only when it provably does not (its row is 1 for k), shares when it does, undecided when the
   * search popped @p max_pops voxels without deciding.
   */
  verdict may_share(index_t q, scratch& s, std::size_t max_pops) const {
    if (!reached(q)) return verdict::own_only;
    const label_t k = lab_[q];
    using item = std::pair<double, index_t>;
    auto later = [](const item& a, const item& b) { return a.first > b.first; };
    bool found = false;
    std::size_t pops = 0;
    s.heap.clear();
    s.key[std::size_t(q)] = T(0);
    s.touched.push_back(q);
    s.heap.push_back({-budget_[std::size_t(q)], q});
    while (!s.heap.empty() && !found && pops < max_pops) {
      std::pop_heap(s.heap.begin(), s.heap.end(), later);
      const index_t u = s.heap.back().second;
      const double prio = s.heap.back().first;
      s.heap.pop_back();
      const T a = s.key[std::size_t(u)];
      if (prio != double(a) - budget_[std::size_t(u)]) continue;  // stale: the key improved since
      ++pops;
      walk_.for_each_neighbour(p_, u, [&](int dir, index_t w) {
        if (found || !p_.inside(w)) return;
        const T c = p_.weight(u, w, dir);
        if (!(c >= T(0))) {  // the search would report it: let the search run
          found = true;
          return;
        }
        const T av = search::extend(a, c);
        if (lab_[w] != k) {
          // another node's voxel (or an unreached one) that the search would enter
          if (av < dist_[w]) found = true;
          return;
        }
        if (!(av < dist_[w]) || !(av < s.key[std::size_t(w)]) || !(double(av) < budget_[std::size_t(w)])) return;
        if (!(s.key[std::size_t(w)] < std::numeric_limits<T>::infinity())) s.touched.push_back(w);
        s.key[std::size_t(w)] = av;
        s.heap.push_back({double(av) - budget_[std::size_t(w)], w});
        std::push_heap(s.heap.begin(), s.heap.end(), later);
      });
    }
    const bool exhausted = s.heap.empty();
    for (const index_t v : s.touched) s.key[std::size_t(v)] = std::numeric_limits<T>::infinity();
    s.touched.clear();
    return found ? verdict::shares : exhausted ? verdict::own_only : verdict::undecided;
  }

  /**
   * Bounds for deciding many queries with the library's own search: d(z) at voxels with a neighbour of
   * another label, U(z) rounded up to T at the other voxels that can be in a new cell (0 where no chain
   * passes), d elsewhere. Every bound is at most d(z). A search from q under these bounds enters every
   * chain voxel (a_i < U(z_i)) with its true key and the chain's first foreign voxel v (a bound d(v):
   * v neighbours z_{m-1}); everything it enters is in C_q (its bounds are at most d). So its new cell
   * holds another label than k exactly when the true one does, and when it does not, its row is the
   * true row (1 for k).
   */
  void restricted_bounds(T* out) const {
    const std::size_t n = budget_.size();
    for (std::size_t z = 0; z < n; ++z) {
      if (frontier_[z] || !stealable(index_t(z))) {
        out[z] = dist_[z];
        continue;
      }
      const double b = budget_[z];
      T t = static_cast<T>(b);
      if (double(t) < b) t = std::nextafter(t, std::numeric_limits<T>::infinity());
      out[z] = std::min(t, dist_[z]);
    }
  }

 private:
  // a voxel that can be in some C_q: in the domain, labelled, 0 < d < inf (a node is in no new cell)
  bool stealable(index_t v) const noexcept {
    return lab_[v] != no_label && dist_[v] > T(0) && dist_[v] < std::numeric_limits<T>::infinity() && p_.inside(v);
  }

  const P& p_;
  search::stencil_walker<P::dim> walk_;
  const T* dist_;
  const label_t* lab_;
  std::vector<double> budget_;
  std::vector<unsigned char> frontier_;
  bool negative_ = false;
};

}  // namespace geovoronoi::detail::shape

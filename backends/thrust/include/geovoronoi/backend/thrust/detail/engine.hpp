#pragma once
// The Thrust backend's engine: near-far frontier relaxation with packed (distance, label) keys.
//
// Voxels waiting to be expanded sit either in the near list (inside the current window) or in the far
// pile. A round expands the whole near list in parallel: each expansion pushes candidate keys to its
// neighbours with an atomic min, and a neighbour whose key dropped is queued (near or far by its new
// distance) unless it is queued already. When the near list runs dry, the window moves up: its
// bottom is the smallest far distance, its top theta is set so that the next near list holds about
// `target` voxels but is at most a few edges deep, and a voxel is near only if it is also within a
// few of its own local edge weights of the bottom (admission). Then the far pile is split. With a
// narrow window almost every voxel is expanded once, with its final key (Dijkstra's order, in
// batches); a wide one gives parallelism at the price of re-expansions. The fixed point is the same
// either way (see docs/backend-thrust.md).

#include <geovoronoi/backend/thrust/detail/atomics.hpp>
#include <geovoronoi/backend/thrust/detail/system.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/result.hpp>

#include <thrust/functional.h>
#include <thrust/transform_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace geovoronoi::thrust::detail {

/// The host search core (detail/search/): keys, the stencil walk, the relaxation step.
namespace search = geovoronoi::detail::search;

/// Work counters of one engine run.
struct engine_counts {
  std::uint64_t expansions = 0;  ///< voxels expanded (a voxel expanded twice counts twice)
  std::uint64_t rounds = 0;      ///< parallel expansion rounds
  std::uint64_t splits = 0;      ///< threshold raises (far-pile splits)
  std::uint64_t reached = 0;     ///< voxels with a finite distance (filled by the solve, not the engine)
  std::uint64_t suspects = 0;    ///< voxels marked for the label repair
  std::uint64_t relabelled = 0;  ///< voxels whose label the repair recomputed (suspects and their heirs)
  bool overflowed = false;       ///< a candidate distance was +inf (see geovoronoi/detail/overflow.hpp)
};

/// Reserve @p k slots of a shared list; returns the first.
GEOVORONOI_HOST_DEVICE inline index_t reserve(index_t* count, index_t k) noexcept {
#ifdef __CUDA_ARCH__
  return index_t(atomicAdd(reinterpret_cast<unsigned long long*>(count), static_cast<unsigned long long>(k)));
#else
  return __atomic_fetch_add(count, k, __ATOMIC_RELAXED);
#endif
}

/// Appends a functor's staged voxels to the shared lists, with one reservation each: @p a near ones
/// from the front of @p stage, @p b far ones from its back (@p top entries in all).
GEOVORONOI_HOST_DEVICE inline void flush_stage(const index_t* stage, index_t top, index_t a, index_t b,
                                               index_t* sizes, index_t* near_out, index_t* far_out) noexcept {
  if (a) {
    const index_t at = reserve(sizes, a);
    for (index_t i = 0; i < a; ++i) near_out[at + i] = stage[i];
  }
  if (b) {
    const index_t at = reserve(sizes + 1, b);
    for (index_t i = 0; i < b; ++i) far_out[at + i] = stage[top - 1 - i];
  }
}

/// Which queued distances belong to the near list in the current window: below theta (the window's
/// top), and no deeper than `depth` local edges above the window's bottom `base`, where the local
/// edge is the metric's weight of the shortest edge between two voxels of v's value (v's weight
/// scale: length / b for the stiffness metrics). A single window over a front that crosses tissues
/// whose weights differ by decades would otherwise be hundreds of edges deep in the stiff ones, and
/// inside a window the near list is expanded in breadth-first rounds, not in distance order, so
/// those voxels would be expanded again and again (docs/backend-thrust.md, "Window"). Distances up
/// to base are always near, so every raise releases something. Only the work depends on this.
template <class T>
struct admission {
  T theta;
  T base;
  T depth;
  T length;  ///< the shortest edge length of the stencil
  template <class M>
  GEOVORONOI_HOST_DEVICE bool near(T d, T fv, const M& metric) const {
    return d <= theta && (d <= base || d <= base + depth * search::edge_weight(metric, length, fv, fv));
  }
};

/// Expands near-list entries [j*Chunk, (j+1)*Chunk). Queued neighbours are staged locally (near ones
/// from the front, far ones from the back), then appended to the next near list and the far pile
/// with one reservation each.
template <class P, class Accept, int Chunk>
struct expand_fn {
  using T = typename P::value_type;
  using cell = key_cell<T>;
  using kt = search::key_traits<T>;
  static constexpr int N = P::neighbours;
  static constexpr index_t top = index_t(Chunk) * N;

  P p;
  search::walker_t<P> walk;
  index_t n;
  cell* keys;
  flag_t* flags;
  const index_t* list;
  index_t count;
  index_t* near_out;
  index_t* far_out;
  index_t* sizes;  // [0] near_out's, [1] far_out's
  admission<T> adm;
  Accept accept;
  int* error;
  int* overflow;  // set when a rejected candidate's distance is +inf
  T largest;      // the largest finite T

  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    index_t stage[top];
    const index_t begin = j * Chunk;
    const index_t end = begin + Chunk < count ? begin + Chunk : count;
    index_t a = 0, b = 0;
    for (index_t i = begin; i < end; ++i) {
      const index_t u = list[i];
#ifndef __CUDA_ARCH__
      if constexpr (search::implicit_grid_v<P>) {
        if (i + 2 < count) {  // prefetch the neighbourhood of the voxel expanded two steps ahead
          const index_t w = list[i + 2];
          const index_t nx = walk.nx, nxy = walk.nxy;
          for (int dz = P::dim == 3 ? -1 : 0; dz <= (P::dim == 3 ? 1 : 0); ++dz)
            for (int dy = -1; dy <= 1; ++dy) {
              const index_t c = w + dz * nxy + dy * nx;
              if (c >= 1 && c + 1 < n) {
                __builtin_prefetch(keys + c - 1, 1);
                __builtin_prefetch(p.field + c - 1, 0);
                __builtin_prefetch(flags + c - 1, 1);
              }
            }
        }
      }
#endif
      // before the load: a later drop of u's key re-queues u
      const bool again = (flag_begin_expansion(flags + u) & expanded_bit) != 0;
      const auto ku = cell::load(keys + u);
      const T du = kt::distance(ku);
      const label_t lu = kt::label(ku);
      const T fu = p.field[u];
      auto relax = [&](int k, index_t v) {
        // weights are >= 0, so v cannot improve; a re-expansion still looks (suspect check below)
        if (!again && !(ku < cell::load(keys + v))) return;
        const T fv = p.field[v];
        if (!geovoronoi::detail::inside<typename P::metric_type>(fv)) return;
        const T w = search::edge_weight(p.metric, p.edges.length[k], fu, fv);
        if (!(w >= T(0))) {
          raise(error);
          return;
        }
        const T nd = search::extend(du, w);
        if (!accept(v, nd)) {
          if (!(nd <= largest)) raise(overflow);  // the unbounded solves reject nothing else
          return;
        }
        if (!cell::lower(keys + v, kt::make(nd, lu))) {
          // u was expanded before with a larger key. If v holds the distance u proposes now but a
          // lower label, that label may have come from u's stale proposal (its sum rounding to the
          // same float): the repair pass re-derives v's label (docs/backend-thrust.md).
          if (again) {
            const auto kv = cell::load(keys + v);
            if (kt::distance(kv) == nd && kt::label(kv) < lu) flag_set_bits(flags + v, suspect_bit);
          }
          return;
        }
        publish_fence();
        if constexpr (!search::implicit_grid_v<P>) {
          // an explicit graph's node may have more than N edges: flush a full stage
          if (a + b == top) {
            flush_stage(stage, top, a, b, sizes, near_out, far_out);
            a = b = 0;
          }
        }
        if (adm.near(nd, fv, p.metric)) {
          if (flag_transition(flags + v, from_not_near{}, queued_near)) stage[a++] = v;
        } else if (flag_transition(flags + v, from_idle{}, queued_far)) {
          stage[top - 1 - b++] = v;
        }
      };
      walk.for_each_neighbour(p, u, relax);
    }
    flush_stage(stage, top, a, b, sizes, near_out, far_out);
  }
};

/// Splits far-pile entries [j*Chunk, (j+1)*Chunk) by theta; stale entries (no longer queued far)
/// are dropped, duplicates resolve through the flag's compare-and-swap.
template <class P, int Chunk>
struct split_fn {
  using T = typename P::value_type;
  using cell = key_cell<T>;
  using kt = search::key_traits<T>;
  P p;
  cell* keys;
  flag_t* flags;
  const index_t* list;
  index_t count;
  index_t* near_out;
  index_t* far_out;
  index_t* sizes;
  admission<T> adm;

  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    index_t stage[Chunk];
    const index_t begin = j * Chunk;
    const index_t end = begin + Chunk < count ? begin + Chunk : count;
    index_t a = 0, b = 0;
    for (index_t i = begin; i < end; ++i) {
      const index_t v = list[i];
      if ((flag_load(flags + v) & state_mask) != queued_far) continue;
      const T d = kt::distance(cell::load(keys + v));
      if (d <= adm.theta && adm.near(d, p.field[v], p.metric)) {
        if (flag_transition(flags + v, from_far{}, queued_near)) stage[a++] = v;
      } else {
        stage[Chunk - 1 - b++] = v;
      }
    }
    flush_stage(stage, Chunk, a, b, sizes, near_out, far_out);
  }
};

/// Distance of a queued-far entry, +inf for a stale one.
template <class T>
struct far_distance {
  const key_cell<T>* keys;
  const flag_t* flags;
  T inf;
  GEOVORONOI_HOST_DEVICE T operator()(index_t v) const {
    if ((flag_load(flags + v) & state_mask) != queued_far) return inf;
    return search::key_traits<T>::distance(key_cell<T>::load(keys + v));
  }
};
template <class T>
struct far_distance_or_low {
  far_distance<T> d;
  GEOVORONOI_HOST_DEVICE T operator()(index_t v) const {
    const T x = d(v);
    return x == d.inf ? T(-1) : x;
  }
};
template <class T>
struct far_within {
  far_distance<T> d;
  T theta;
  GEOVORONOI_HOST_DEVICE index_t operator()(index_t v) const { return d(v) <= theta ? 1 : 0; }
};

/// CUDA system: candidate windows delta_0 = 0, delta_k = base * 2^(k-1) above the smallest queued
/// distance; theta is the narrowest holding `target` entries (one counting reduction per window).
inline constexpr int windows = 64;

template <class T>
T window(T base, int k) noexcept {
  return k == 0 ? T(0) : std::ldexp(base, k - 1);
}

/// Smallest weight of an edge into v (+inf when no neighbour is inside the domain): how far a
/// distance must rise above v's before a path through v's neighbours can undercut it.
template <class P>
typename P::value_type min_in_weight(const P& p, const search::walker_t<P>& walk, index_t v) {
  using T = typename P::value_type;
  T best = std::numeric_limits<T>::infinity();
  const T fv = p.field[v];
  auto look = [&](int k, index_t u) {
    const T fu = p.field[u];
    if (!geovoronoi::detail::inside<typename P::metric_type>(fu)) return;
    const T w = search::edge_weight(p.metric, p.edges.length[k], fu, fv);
    if (w < best) best = w;
  };
  walk.for_each_neighbour(p, v, look);
  return best;
}

/// Host systems: theta from a sample of the far pile. Reads up to `samples` evenly spaced entries
/// (no pass over the pile) and takes the smaller of two thresholds:
///  * count: the sampled distance below which about `target` of the live entries lie;
///  * step: the smallest sampled distance plus `step_hops` times the median of the sampled entries'
///    smallest incoming edge weights. Inside one window the near list is expanded in rounds, in
///    breadth-first order rather than in distance order, so a window many edges deep lets voxels be
///    reached first through paths of fewer but heavier edges, and each of them is expanded again;
///    on a field whose values span decades (an MRI) a window from the count alone was hundreds of
///    edges deep in the stiff tissues and cost 7 expansions per voxel (docs/backend-thrust.md,
///    "Window").
/// Returns false when every sampled entry was stale. Only the work per round depends on theta,
/// never the result.
/// Depth of the step window in (median) edges: 1-2 doubles the threshold raises on smooth fields,
/// 16-32 lets re-expansions back in on the MRI-like phantom (1.05 expansions per voxel at 4-8).
inline constexpr int step_hops = 4;
/// Depth of the per-voxel admission (admission::depth), in local edges.
inline constexpr int local_depth = 4;

template <class P>
bool sample_theta(const P& p, const search::walker_t<P>& walk, const key_cell<typename P::value_type>* keys, const flag_t* flags,
                  const index_t* list, index_t size, index_t target, std::vector<typename P::value_type>& scratch,
                  std::vector<typename P::value_type>& weights, typename P::value_type& theta,
                  typename P::value_type& base) {
  using T = typename P::value_type;
  constexpr index_t samples = 1024;
  constexpr index_t weight_samples = 256;
  const index_t s = std::min(size, samples);
  scratch.clear();
  weights.clear();
  T lo = std::numeric_limits<T>::infinity();
  for (index_t i = 0; i < s; ++i) {
    const index_t v = list[i * size / s];
    if ((flag_load(flags + v) & state_mask) != queued_far) continue;
    const T d = search::key_traits<T>::distance(key_cell<T>::load(keys + v));
    scratch.push_back(d);
    lo = std::min(lo, d);
    if (static_cast<index_t>(weights.size()) * s < weight_samples * (i + 1)) {
      const T w = min_in_weight(p, walk, v);
      if (w < std::numeric_limits<T>::infinity()) weights.push_back(w);
    }
  }
  if (scratch.empty()) return false;
  const index_t live = static_cast<index_t>(scratch.size());
  // rank of the target-th smallest live entry, scaled from the pile to the sample
  const double frac = double(target) / double(size);
  const index_t rank = std::min<index_t>(live - 1, static_cast<index_t>(frac * double(live)));
  std::nth_element(scratch.begin(), scratch.begin() + rank, scratch.end());
  theta = scratch[static_cast<std::size_t>(rank)];
  base = lo;
  if (!weights.empty()) {
    const std::size_t q = weights.size() / 2;
    std::nth_element(weights.begin(), weights.begin() + static_cast<std::ptrdiff_t>(q), weights.end());
    const T step = lo + T(step_hops) * weights[q];
    if (step < theta) theta = step;
  }
  return true;
}

template <class V>
void grow(V& v, index_t need) {
  if (static_cast<index_t>(v.size()) < need) v.resize(static_cast<std::size_t>(std::max(need, 2 * index_t(v.size()))));
}

template <class Exec>
void set_sizes(vec<Exec, index_t>& sizes, index_t a, index_t b) {
  sizes[0] = a;  // a host store, or one small copy to the device
  sizes[1] = b;
}

/// CUDA system: theta = smallest queued far distance + the narrowest window holding `target`
/// entries. False when every far entry is stale.
template <class Exec, class T>
bool window_theta(const Exec& exec, const key_cell<T>* keys, const flag_t* flags, const index_t* fl, index_t far_size,
                  index_t target, T& theta, T& bottom) {
  const T inf = std::numeric_limits<T>::infinity();
  const far_distance<T> fd{keys, flags, inf};
  const T lo = ::thrust::transform_reduce(exec, fl, fl + far_size, fd, inf, ::thrust::minimum<T>());
  if (!(lo < inf)) return false;
  const T hi =
      ::thrust::transform_reduce(exec, fl, fl + far_size, far_distance_or_low<T>{fd}, T(-1), ::thrust::maximum<T>());
  const T spread = hi - lo;
  const T base = spread > T(0) ? std::max(std::ldexp(spread, -(windows - 8)), std::numeric_limits<T>::min()) : T(1);
  int pick = windows - 1;
  for (int k = 0; k < windows; ++k) {
    const index_t c = ::thrust::transform_reduce(exec, fl, fl + far_size, far_within<T>{fd, lo + window(base, k)},
                                                 index_t(0), ::thrust::plus<index_t>());
    if (c >= target || !(lo + window(base, k) < hi)) {
      pick = k;
      break;
    }
  }
  theta = lo + window(base, pick);
  bottom = lo;
  return true;
}

/**
 * Runs the engine until no voxel is queued. On entry, keys hold the sources' keys (unreached
 * elsewhere), flags are idle except for the voxels listed in @p far (queued_far). accept(v, nd)
 * filters candidates exactly like the sequential engine's accept.
 *
 * Per threshold raise: one parallel split of the far pile (theta from a sample on host systems);
 * per round: one parallel expansion step. Small steps run on the calling thread (parallel_for).
 */
template <class Exec, class P, class Accept>
engine_counts run(const Exec& exec, const P& p, key_cell<typename P::value_type>* keys, flag_t* flags,
                  vec<Exec, index_t>& far, index_t far_size, const Accept& accept, index_t target,
                  const geovoronoi::detail::solve_control& ctl = {}, double total = 1) {
  using T = typename P::value_type;
  constexpr int N = P::neighbours;
  constexpr bool device = is_cuda_policy_v<Exec>;
  constexpr int chunk = device ? 1 : 32;
  constexpr int split_chunk = device ? 1 : 64;
  const index_t cap = device ? (index_t(1) << 18) : (index_t(1) << 14);
  const search::walker_t<P> walk(p);
  const index_t n = search::node_count(p);
  const index_t degree = search::max_degree(p);  // N on a grid
  target = std::max<index_t>(target, 1);

  vec<Exec, index_t> near, next, far2, sizes(2);
  vec<Exec, int> error(1, 0), overflow(1, 0);
  std::vector<T> scratch, weights;
  engine_counts counts;
  index_t near_size = 0;
  admission<T> adm{T(0), T(0), T(local_depth), p.edges.length[0]};
  for (int k = 1; k < N; ++k) adm.length = std::min(adm.length, p.edges.length[k]);

  while (near_size > 0 || far_size > 0) {
    if (near_size == 0) {
      // raise theta and split the far pile; when only stale entries were seen, a split with a theta
      // below every distance compacts the pile (drops the stale entries) and the loop samples again
      const index_t* fl = raw(far);
      T next_theta = T(0), bottom = T(0);
      bool live = false;
      if constexpr (device)
        live = window_theta(exec, keys, flags, fl, far_size, target, next_theta, bottom);
      else
        live = sample_theta(p, walk, keys, flags, fl, far_size, target, scratch, weights, next_theta, bottom);
      admission<T> split_adm = adm;
      if (live) {
        adm.theta = next_theta;
        adm.base = bottom;
        split_adm = adm;
      } else {
        split_adm.theta = split_adm.base = -std::numeric_limits<T>::infinity();
      }
      if (device && !live) {  // the device check above scanned the whole pile: nothing is queued
        far_size = 0;
        continue;
      }
      grow(near, std::min(n, far_size));
      grow(far2, far_size);
      set_sizes<Exec>(sizes, 0, 0);
      parallel_for(exec, (far_size + split_chunk - 1) / split_chunk,
                   split_fn<P, split_chunk>{p, keys, flags, fl, far_size, raw(near), raw(far2), raw(sizes), split_adm},
                   far_size);
      near_size = read<Exec>(raw(sizes));
      far_size = read<Exec>(raw(sizes) + 1);
      using std::swap;
      swap(far, far2);
      ++counts.splits;
      continue;
    }
    // one round: expand the near list in sub-batches
    index_t next_size = 0;
    for (index_t s = 0; s < near_size; s += cap) {
      const index_t cnt = std::min(cap, near_size - s);
      grow(next, std::min(n, next_size + cnt * degree));
      grow(far, far_size + cnt * degree);
      set_sizes<Exec>(sizes, next_size, far_size);
      parallel_for(exec, (cnt + chunk - 1) / chunk,
                   expand_fn<P, Accept, chunk>{p, walk, n, keys, flags, raw(near) + s, cnt, raw(next), raw(far), raw(sizes),
                                               adm, accept, raw(error), raw(overflow),
                                               std::numeric_limits<T>::max()},
                   cnt * degree);
      next_size = read<Exec>(raw(sizes));
      far_size = read<Exec>(raw(sizes) + 1);
      counts.expansions += static_cast<std::uint64_t>(cnt);
      ++counts.rounds;
    }
    if (read<Exec>(raw(error)) != 0)
      search::bad_weight();
    // progress by expansions over the domain's voxels (about one expansion per voxel), once a round
    if (ctl.reporting()) ctl.report(std::min(0.999, double(counts.expansions) / total));
    using std::swap;
    swap(near, next);
    near_size = next_size;
  }
  counts.overflowed = read<Exec>(raw(overflow)) != 0;
  return counts;
}

}  // namespace geovoronoi::thrust::detail

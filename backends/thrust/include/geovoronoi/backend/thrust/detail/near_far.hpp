#pragma once
// The Thrust backend's engine: near-far frontier relaxation with packed (distance, label) keys.
//
// Voxels waiting to be expanded sit either in the near list (key distance <= theta) or in the far
// pile (above theta). A round expands the whole near list in parallel: each expansion pushes
// candidate keys to its neighbours with an atomic min, and a neighbour whose key dropped is queued
// (near or far by its new distance) unless it is queued already. When the near list runs dry, theta
// rises to the smallest far distance plus a window delta sized so that the next near list holds
// about `target` voxels, and the far pile is split. With a narrow window almost every voxel is
// expanded once, with its final key (Dijkstra's order, in batches); a wide one gives parallelism at
// the price of re-expansions. The fixed point is the same either way (see docs/backend-thrust.md).

#include <geovoronoi/backend/thrust/detail/atomics.hpp>
#include <geovoronoi/backend/thrust/detail/system.hpp>
#include <geovoronoi/detail/key.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <thrust/functional.h>
#include <thrust/transform_reduce.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <utility>

namespace geovoronoi::thrust::detail {

/// Work counters of one engine run.
struct engine_counts {
  std::uint64_t expansions = 0;  ///< voxels expanded (a voxel expanded twice counts twice)
  std::uint64_t rounds = 0;      ///< parallel expansion rounds
  std::uint64_t splits = 0;      ///< threshold raises (far-pile splits)
};

/// Grid extents for neighbour walks inside functors.
struct extents3 {
  index_t nx, ny, nz;
};

template <class P>
extents3 extents_of(const P& p) noexcept {
  return {p.geometry.extent(0), p.geometry.extent(1), P::dim == 3 ? p.geometry.extent(P::dim - 1) : 1};
}

/// Calls f(k, v) for every neighbour v = u + offset k inside the grid.
template <class P, class F>
GEOVORONOI_HOST_DEVICE inline void for_each_neighbour(const P& p, const extents3& e, index_t u, F& f) {
  const index_t nxy = e.nx * e.ny;
  const index_t z = u / nxy;
  const index_t r = u - z * nxy;
  const index_t y = r / e.nx;
  const index_t x = r - y * e.nx;
  const bool interior =
      x > 0 && x < e.nx - 1 && y > 0 && y < e.ny - 1 && (P::dim == 2 || (z > 0 && z < e.nz - 1));
  for (int k = 0; k < P::neighbours; ++k) {
    if (!interior) {
      const index_t xx = x + p.edges.offset[k][0], yy = y + p.edges.offset[k][1], zz = z + p.edges.offset[k][2];
      if (xx < 0 || xx >= e.nx || yy < 0 || yy >= e.ny || zz < 0 || zz >= e.nz) continue;
    }
    f(k, u + p.edges.delta[k]);
  }
}

/// Expands near-list entries [j*chunk, (j+1)*chunk); queued neighbours go to the chunk's region,
/// near ones from the front, far ones from the back. Entry j == chunks writes the zero count that
/// turns the exclusive scan into offsets with a total.
template <class P, class Accept>
struct expand_fn {
  using T = typename P::value_type;
  using cell = key_cell<T>;
  using kt = geovoronoi::detail::key_traits<T>;
  static constexpr int N = P::neighbours;

  P p;
  extents3 ext;
  cell* keys;
  flag_t* flags;
  const index_t* list;
  index_t count;
  index_t chunk;
  index_t chunks;
  index_t* region;
  index_t* n_near;
  index_t* n_far;
  T theta;
  Accept accept;
  int* error;

  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    if (j == chunks) {
      n_near[j] = 0;
      n_far[j] = 0;
      return;
    }
    const index_t begin = j * chunk;
    const index_t end = begin + chunk < count ? begin + chunk : count;
    const index_t top = chunk * N;
    index_t* reg = region + j * top;
    index_t a = 0, b = 0;
    for (index_t i = begin; i < end; ++i) {
      const index_t u = list[i];
      flag_clear(flags + u);  // before the load: a later drop of u's key re-queues u
      const auto ku = cell::load(keys + u);
      const T du = kt::distance(ku);
      const label_t lu = kt::label(ku);
      const T fu = p.field[u];
      auto relax = [&](int k, index_t v) {
        if (!(ku < cell::load(keys + v))) return;  // weights are >= 0: v cannot improve
        const T fv = p.field[v];
        if (!geovoronoi::detail::inside<typename P::metric_type>(fv)) return;
        const T w = p.metric(p.edges.length[k], fu, fv);
        if (!(w >= T(0))) {
          raise(error);
          return;
        }
        const T nd = du + w;
        if (!accept(v, nd)) return;
        if (!cell::lower(keys + v, kt::make(nd, lu))) return;
        publish_fence();
        if (nd <= theta) {
          for (;;) {
            const flag_t f = flag_load(flags + v);
            if (f == queued_near) break;
            if (flag_cas(flags + v, f, queued_near)) {
              reg[a++] = v;
              break;
            }
          }
        } else if (flag_load(flags + v) == idle && flag_cas(flags + v, idle, queued_far)) {
          reg[top - 1 - b++] = v;
        }
      };
      for_each_neighbour(p, ext, u, relax);
    }
    n_near[j] = a;
    n_far[j] = b;
  }
};

/// Splits far-pile entries [j*chunk, (j+1)*chunk) by theta; stale entries (no longer queued far)
/// are dropped, duplicates resolve through the flag's compare-and-swap.
template <class T>
struct split_fn {
  using cell = key_cell<T>;
  using kt = geovoronoi::detail::key_traits<T>;
  cell* keys;
  flag_t* flags;
  const index_t* list;
  index_t count;
  index_t chunk;
  index_t chunks;
  index_t* region;
  index_t* n_near;
  index_t* n_far;
  T theta;

  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    if (j == chunks) {
      n_near[j] = 0;
      n_far[j] = 0;
      return;
    }
    const index_t begin = j * chunk;
    const index_t end = begin + chunk < count ? begin + chunk : count;
    index_t* reg = region + j * chunk;
    index_t a = 0, b = 0;
    for (index_t i = begin; i < end; ++i) {
      const index_t v = list[i];
      if (flag_load(flags + v) != queued_far) continue;
      if (kt::distance(cell::load(keys + v)) <= theta) {
        if (flag_cas(flags + v, queued_far, queued_near)) reg[a++] = v;
      } else {
        reg[chunk - 1 - b++] = v;
      }
    }
    n_near[j] = a;
    n_far[j] = b;
  }
};

/// Copies each chunk's queued voxels to their places in the next near list and the far pile.
struct gather_fn {
  const index_t* region;
  index_t slots;
  const index_t* off_near;
  const index_t* off_far;
  index_t* near_out;
  index_t* far_out;
  GEOVORONOI_HOST_DEVICE void operator()(index_t j) const {
    const index_t* reg = region + j * slots;
    const index_t a = off_near[j + 1] - off_near[j], b = off_far[j + 1] - off_far[j];
    for (index_t i = 0; i < a; ++i) near_out[off_near[j] + i] = reg[i];
    for (index_t i = 0; i < b; ++i) far_out[off_far[j] + i] = reg[slots - b + i];
  }
};

/// Distance of a queued-far entry, +inf for a stale one.
template <class T>
struct far_distance {
  const key_cell<T>* keys;
  const flag_t* flags;
  GEOVORONOI_HOST_DEVICE T operator()(index_t v) const {
    if (flag_load(flags + v) != queued_far) return std::numeric_limits<T>::infinity();
    return geovoronoi::detail::key_traits<T>::distance(key_cell<T>::load(keys + v));
  }
};
template <class T>
struct far_distance_or_low {
  far_distance<T> d;
  GEOVORONOI_HOST_DEVICE T operator()(index_t v) const {
    const T x = d(v);
    return x == std::numeric_limits<T>::infinity() ? T(-1) : x;
  }
};
template <class T>
struct far_within {
  far_distance<T> d;
  T theta;
  GEOVORONOI_HOST_DEVICE index_t operator()(index_t v) const { return d(v) <= theta ? 1 : 0; }
};

template <class U, class V>
void grow(V& v, index_t need) {
  if (static_cast<index_t>(v.size()) < need) v.resize(static_cast<std::size_t>(std::max(need, 2 * index_t(v.size()))));
}

/**
 * Runs the engine until no voxel is queued. On entry, keys hold the sources' keys (unreached
 * elsewhere), flags are idle except for the voxels listed in @p far (queued_far). accept(v, nd)
 * filters candidates exactly like the sequential engine's accept.
 */
template <class Exec, class P, class Accept>
engine_counts run(const Exec& exec, const P& p, key_cell<typename P::value_type>* keys, flag_t* flags,
                  vec<Exec, index_t>& far, index_t far_size, const Accept& accept, index_t target) {
  using T = typename P::value_type;
  constexpr int N = P::neighbours;
  constexpr bool device = is_cuda_policy_v<Exec>;
  const index_t chunk = device ? 1 : 32;
  const index_t cap = device ? (index_t(1) << 18) : (index_t(1) << 14);
  const extents3 ext = extents_of(p);
  target = std::max<index_t>(target, 1);

  vec<Exec, index_t> near, next, far2, region, cn, cf;
  vec<Exec, int> error(1, 0);
  engine_counts counts;
  index_t near_size = 0;
  T delta = T(0);
  T theta = T(0);
  const T inf = std::numeric_limits<T>::infinity();

  while (near_size > 0 || far_size > 0) {
    if (near_size == 0) {
      // raise theta: the smallest queued distance plus a window holding about `target` voxels
      const far_distance<T> fd{keys, flags};
      const index_t* fl = raw(far);
      T lo = inf, hi = T(-1);
      if (go_parallel<Exec>(far_size)) {
        lo = ::thrust::transform_reduce(exec, fl, fl + far_size, fd, inf, ::thrust::minimum<T>());
        hi = ::thrust::transform_reduce(exec, fl, fl + far_size, far_distance_or_low<T>{fd}, T(-1),
                                        ::thrust::maximum<T>());
      } else {
        for (index_t i = 0; i < far_size; ++i) {
          const T x = fd(fl[i]);
          if (x < lo) lo = x;
          if (x != inf && x > hi) hi = x;
        }
      }
      if (!(lo < inf)) {  // every entry was stale
        far_size = 0;
        continue;
      }
      const bool par = go_parallel<Exec>(far_size);
      auto within = [&](T th) {
        if (par)
          return ::thrust::transform_reduce(exec, fl, fl + far_size, far_within<T>{fd, th}, index_t(0),
                                            ::thrust::plus<index_t>());
        index_t c = 0;
        for (index_t i = 0; i < far_size; ++i) c += far_within<T>{fd, th}(fl[i]);
        return c;
      };
      index_t c = within(lo + delta);
      for (int guard = 0; c < target && lo + delta < hi && guard < 64; ++guard) {
        delta = delta > T(0) ? delta * T(2) : (hi - lo) / T(4096);
        if (!(delta > T(0))) delta = hi - lo;
        c = within(lo + delta);
      }
      if (c > 4 * target && delta > T(0)) {
        const index_t c2 = within(lo + delta / T(2));
        if (c2 >= target) delta /= T(2);
      }
      theta = lo + delta;
      const index_t chunks = (far_size + chunk * 64 - 1) / (chunk * 64);
      const index_t slots = chunk * 64;
      grow<index_t>(region, chunks * slots);
      grow<index_t>(cn, chunks + 1);
      grow<index_t>(cf, chunks + 1);
      parallel_for(exec, chunks + 1,
                   split_fn<T>{keys, flags, fl, far_size, slots, chunks, raw(region), raw(cn), raw(cf), theta},
                   far_size);
      const index_t tn = exclusive_scan(exec, raw(cn), chunks + 1);
      const index_t tf = exclusive_scan(exec, raw(cf), chunks + 1);
      grow<index_t>(near, tn);
      grow<index_t>(far2, tf);
      parallel_for(exec, chunks, gather_fn{raw(region), slots, raw(cn), raw(cf), raw(near), raw(far2)}, tn + tf);
      using std::swap;
      swap(far, far2);
      far_size = tf;
      near_size = tn;
      ++counts.splits;
      continue;
    }
    // one round: expand the near list in sub-batches
    index_t next_size = 0;
    for (index_t s = 0; s < near_size; s += cap) {
      const index_t cnt = std::min(cap, near_size - s);
      const index_t chunks = (cnt + chunk - 1) / chunk;
      grow<index_t>(region, chunks * chunk * N);
      grow<index_t>(cn, chunks + 1);
      grow<index_t>(cf, chunks + 1);
      parallel_for(exec, chunks + 1,
                   expand_fn<P, Accept>{p, ext, keys, flags, raw(near) + s, cnt, chunk, chunks, raw(region), raw(cn),
                                        raw(cf), theta, accept, raw(error)},
                   cnt * N);
      const index_t tn = exclusive_scan(exec, raw(cn), chunks + 1);
      const index_t tf = exclusive_scan(exec, raw(cf), chunks + 1);
      grow<index_t>(next, next_size + tn);
      grow<index_t>(far, far_size + tf);
      parallel_for(exec, chunks,
                   gather_fn{raw(region), chunk * N, raw(cn), raw(cf), raw(next) + next_size, raw(far) + far_size},
                   tn + tf);
      next_size += tn;
      far_size += tf;
      counts.expansions += static_cast<std::uint64_t>(cnt);
      ++counts.rounds;
    }
    if (read<Exec>(raw(error)) != 0)
      throw metric_error("geovoronoi: the metric returned a negative or NaN edge weight; weights must be >= 0");
    using std::swap;
    swap(near, next);
    near_size = next_size;
  }
  return counts;
}

}  // namespace geovoronoi::thrust::detail

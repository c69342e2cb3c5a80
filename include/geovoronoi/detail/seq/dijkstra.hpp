#pragma once
// The sequential engine: label-carrying Dijkstra on the implicit grid graph with a radix heap over
// packed (distance, label) keys. One loop serves the dense solve, the bounded solve and insert-query;
// they differ only in where keys are stored (a dense array or a hash map bounded by what is visited)
// and in which relaxations they accept.

#include <geovoronoi/detail/flat_map.hpp>
#include <geovoronoi/detail/key.hpp>
#include <geovoronoi/detail/radix_heap.hpp>
#include <geovoronoi/detail/stencil_walk.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <string>
#include <vector>

namespace geovoronoi::detail::seq_engine {

/// Keys in a dense per-voxel array.
template <class T>
struct dense_keys {
  using kt = key_traits<T>;
  typename kt::key_type* k;
  typename kt::key_type get(index_t v) const noexcept { return k[v]; }
  void set(index_t v, typename kt::key_type key) noexcept { k[v] = key; }
};

/// Keys in a hash map holding only the voxels visited.
template <class T>
struct sparse_keys {
  using kt = key_traits<T>;
  flat_map<typename kt::key_type> map;
  typename kt::key_type get(index_t v) noexcept {
    const auto* x = map.find(v);
    return x ? *x : kt::unreached;
  }
  void set(index_t v, typename kt::key_type key) { map.get_or_insert(v, key) = key; }
};

[[noreturn]] inline void bad_weight(double w) {
  throw metric_error("geovoronoi: the metric returned the edge weight " + std::to_string(w) +
                     "; weights must be >= 0 and not NaN");
}

/**
 * Runs Dijkstra from the keys already in the heap until it is empty.
 * accept(u, nd) filters relaxations (radius bounds, insert-query pruning): a rejected candidate is
 * neither stored nor queued. Returns the number of voxels settled.
 */
template <class P, class State, class Accept>
std::size_t run(const P& p, State& st, radix_heap<typename P::value_type>& heap, Accept&& accept) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const stencil_walker<P> walk(p);
  std::size_t settled = 0;
  while (!heap.empty()) {
    const auto it = heap.pop();
    if (it.key != st.get(it.voxel)) continue;  // stale entry: a smaller key was queued later
    ++settled;
    const index_t v = it.voxel;
    const T dv = kt::distance(it.key);
    const label_t l = kt::label(it.key);
    const T fv = p.field[v];
    walk.for_each_neighbour(v, [&](int k, index_t u) {
      const T fu = p.field[u];
      if (!detail::inside<typename P::metric_type>(fu)) return;
      const T w = p.metric(p.edges.length[k], fv, fu);
      if (!(w >= T(0))) bad_weight(double(w));
      const T nd = dv + w;
      if (!accept(u, nd)) return;
      const auto nk = kt::make(nd, l);
      if (nk < st.get(u)) {
        st.set(u, nk);
        heap.push(nk, u);
      }
    });
  }
  return settled;
}

}  // namespace geovoronoi::detail::seq_engine

#pragma once
// The sequential backend's dense and bounded solves: the shared Dijkstra engine (detail/search/)
// with keys in a dense per-voxel array, or in the paged scratch of the sparse searches.

#include <geovoronoi/detail/big_array.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/search/sparse.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/overflow.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/result.hpp>

#include <limits>
#include <vector>

namespace geovoronoi::detail::seq {

/// Dense multi-source solve below @p radius: distance and label images. Reports progress and detects
/// overflow as @p ctl and detail/overflow.hpp say.
template <class P>
diagram<typename P::value_type, P::dim> solve(const P& p, const std::vector<source<typename P::value_type>>& sources,
                                              typename P::value_type radius, const solve_control& ctl = {}) {
  using T = typename P::value_type;
  using kt = search::key_traits<T>;
  const index_t n = p.geometry.size();
  big_array<search::node<T>> work(static_cast<std::size_t>(n));
  for (index_t v = 0; v < n; ++v) {
    work[v].set_key(kt::unreached);
    work[v].field = p.field[v];
  }
  search::solve_monitor mon{&ctl, ctl.reporting() ? double(search::count_inside(p)) : 1.0};
  ctl.report(0.0);
  search::dense_keys<T> st{work.data()};
  search::radix_heap<T> heap;
  search::run_from_sources(p, st, heap, sources, radius, mon);
  diagram<T, P::dim> d;
  d.distance = image<T, P::dim>(p.geometry, std::numeric_limits<T>::infinity());
  d.label = image<label_t, P::dim>(p.geometry, no_label);
  for (index_t v = 0; v < n; ++v) {
    const auto k = st.get(v);
    if (k != kt::unreached) {
      d.distance[v] = kt::distance(k);
      d.label[v] = kt::label(k);
    }
  }
  if (mon.overflowed && !(radius <= std::numeric_limits<T>::max())) throw_if_overflowed_dense(p, d.distance.data());
  ctl.report(1.0);
  return d;
}

/// Bounded (sparse) solve in @p scratch: the voxels below @p radius, sorted by voxel.
template <class P, class Scratch>
sparse_solution<typename P::value_type> bounded(const P& p, Scratch& scratch,
                                                const std::vector<source<typename P::value_type>>& sources,
                                                typename P::value_type radius, const solve_control& ctl = {}) {
  return search::bounded(p, scratch.keys, scratch.heap, sources, radius, ctl);
}

}  // namespace geovoronoi::detail::seq

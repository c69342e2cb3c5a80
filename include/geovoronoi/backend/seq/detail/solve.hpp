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
#include <type_traits>
#include <vector>

namespace geovoronoi::detail::seq {

/// Dense multi-source solve below @p radius over the nodes of @p p (a grid's voxels or an explicit
/// graph's nodes): writes the reached nodes' distance and label into @p distance and @p label (one
/// entry per node, left as they are where unreached). Reports progress and detects overflow as @p ctl
/// and detail/overflow.hpp say.
template <class P>
void solve_into(const P& p, const std::vector<source<typename P::value_type>>& sources, typename P::value_type radius,
                const solve_control& ctl, typename P::value_type* distance, label_t* label) {
  using T = typename P::value_type;
  using kt = search::key_traits<T>;
  const index_t n = search::node_count(p);
  // an explicit graph's walk bits go beside each node's key (search::walk_node)
  constexpr bool bits = !search::implicit_grid_v<P>;
  using node_t = std::conditional_t<bits, search::walk_node<T>, search::node<T>>;
  big_array<node_t> work(static_cast<std::size_t>(n));
  [[maybe_unused]] const search::walker_t<P> walk(p);
  for (index_t v = 0; v < n; ++v) {
    work[v].set_key(kt::unreached);
    work[v].field = p.field[v];
    if constexpr (bits) work[v].bits = walk.bits(v);
  }
  search::solve_monitor mon{&ctl, ctl.reporting() ? double(search::count_inside(p)) : 1.0};
  ctl.report(0.0);
  search::dense_keys<T, node_t> st{work.data()};
  search::radix_heap<T> heap;
  search::run_from_sources(p, st, heap, sources, radius, mon);
  for (index_t v = 0; v < n; ++v) {
    const auto k = st.get(v);
    if (k != kt::unreached) {
      distance[v] = kt::distance(k);
      label[v] = kt::label(k);
    }
  }
  if (mon.overflowed && !(radius <= std::numeric_limits<T>::max())) throw_if_overflowed_dense(p, distance);
  ctl.report(1.0);
}

/// Dense multi-source solve below @p radius: distance and label images.
template <class P>
diagram<typename P::value_type, P::dim> solve(const P& p, const std::vector<source<typename P::value_type>>& sources,
                                              typename P::value_type radius, const solve_control& ctl = {}) {
  using T = typename P::value_type;
  diagram<T, P::dim> d;
  d.distance = image<T, P::dim>(p.geometry, std::numeric_limits<T>::infinity());
  d.label = image<label_t, P::dim>(p.geometry, no_label);
  solve_into(p, sources, radius, ctl, d.distance.data(), d.label.data());
  return d;
}

/// The same over the nodes of an explicit graph: per-node distance and label.
template <class P>
node_diagram<typename P::value_type> solve_nodes(const P& p, const std::vector<source<typename P::value_type>>& sources,
                                                 typename P::value_type radius, const solve_control& ctl = {}) {
  using T = typename P::value_type;
  node_diagram<T> d;
  const auto n = static_cast<std::size_t>(search::node_count(p));
  d.distance.assign(n, std::numeric_limits<T>::infinity());
  d.label.assign(n, no_label);
  solve_into(p, sources, radius, ctl, d.distance.data(), d.label.data());
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

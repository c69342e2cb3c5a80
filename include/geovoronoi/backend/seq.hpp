#pragma once
/// @file backend/seq.hpp
/// @brief The sequential backend: Dijkstra with a monotone radix heap on the implicit grid graph.
///
/// Select it by passing geovoronoi::seq as the first argument of any solver entry point
/// (geovoronoi/voronoi.hpp). It is the reference every other backend is tested against, and it is
/// itself tested against a brute-force Bellman-Ford oracle.

#include <geovoronoi/detail/big_array.hpp>
#include <geovoronoi/detail/parents.hpp>
#include <geovoronoi/detail/seq/dijkstra.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <vector>

namespace geovoronoi {
namespace sequential {

/// Policy type of the sequential backend.
struct par_t {};

namespace impl = geovoronoi::detail::seq_engine;

template <class P>
using T_of = typename P::value_type;

/// Dense multi-source solve (backend hook; call geovoronoi::voronoi or geovoronoi::geodesic_solve).
template <class P>
diagram<T_of<P>, P::dim> backend_solve(par_t, const P& p, const std::vector<source<T_of<P>>>& sources,
                                       const solve_options& opt) {
  using T = T_of<P>;
  using kt = detail::key_traits<T>;
  const index_t n = p.geometry.size();
  const T radius = detail::radius_in<T>(opt.max_distance);
  detail::big_array<impl::node<T>> work(static_cast<std::size_t>(n));
  for (index_t v = 0; v < n; ++v) {
    work[v].set_key(kt::unreached);
    work[v].field = p.field[v];
  }
  impl::dense_keys<T> st{work.data()};
  detail::radix_heap<T> heap;
  impl::run_from_sources(p, st, heap, sources, radius);
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
  return d;
}

/// Bounded (sparse) multi-source solve; scratch memory proportional to the voxels reached.
template <class P>
sparse_solution<T_of<P>> backend_bounded(par_t, const P& p, const std::vector<source<T_of<P>>>& sources,
                                         T_of<P> radius) {
  using T = T_of<P>;
  using kt = detail::key_traits<T>;
  impl::sparse_keys<T> st;
  st.f = p.field;
  detail::radix_heap<T> heap;
  impl::run_from_sources(p, st, heap, sources, radius);
  std::vector<std::pair<index_t, typename kt::key_type>> out;
  out.reserve(st.map.size());
  st.map.for_each([&](index_t v, const typename kt::key_type& k) { out.push_back({v, k}); });
  std::sort(out.begin(), out.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  sparse_solution<T> r;
  r.voxel.reserve(out.size());
  r.distance.reserve(out.size());
  r.label.reserve(out.size());
  for (const auto& [v, k] : out) {
    r.voxel.push_back(v);
    r.distance.push_back(kt::distance(k));
    r.label.push_back(kt::label(k));
  }
  return r;
}

/// Insert-query for a batch of queries, one after the other, each with a hash map sized by its cell.
template <class P>
query_cells<T_of<P>> backend_insert_queries(par_t, const P& p, const diagram<T_of<P>, P::dim>& d,
                                            const std::vector<index_t>& queries) {
  using T = T_of<P>;
  using kt = detail::key_traits<T>;
  query_cells<T> out;
  out.query = queries;
  out.offsets.reserve(queries.size() + 1);
  impl::sparse_keys<T> st;
  st.f = p.field;
  detail::radix_heap<T> heap;
  const T* dist = d.distance.data();
  std::vector<std::pair<index_t, typename kt::key_type>> cell;
  for (const index_t q : queries) {
    st.map.reset(cell.size() + 16);
    heap.clear();
    if (T(0) < dist[q]) {
      st.set(q, kt::make(T(0), 0));
      heap.push(kt::make(T(0), 0), q);
    }
    impl::run(p, st, heap, [dist](index_t u, T nd) { return nd < dist[u]; });
    cell.clear();
    st.map.for_each([&](index_t v, const typename kt::key_type& k) { cell.push_back({v, k}); });
    std::sort(cell.begin(), cell.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const auto& [v, k] : cell) {
      out.voxel.push_back(v);
      out.distance.push_back(kt::distance(k));
      out.owner.push_back(d.label[v]);
    }
    out.offsets.push_back(out.voxel.size());
  }
  return out;
}

}  // namespace sequential

/// The sequential backend's policy object: `geovoronoi::voronoi(geovoronoi::seq, ...)`.
inline constexpr sequential::par_t seq{};

}  // namespace geovoronoi

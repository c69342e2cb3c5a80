#pragma once
/// @file backend/seq.hpp
/// @brief The sequential backend: Dijkstra with a monotone radix heap on the implicit grid graph.
///
/// Select it by passing geovoronoi::seq as the first argument of any solver entry point
/// (geovoronoi/voronoi.hpp). It is the reference every other backend is tested against, and it is
/// itself tested against a brute-force Bellman-Ford oracle. The sparse searches (bounded_solve,
/// single_source, insert_queries) keep their keys in a paged scratch whose memory follows what they
/// visit; pass geovoronoi::seq(ws) with a sequential::workspace to reuse it across calls.

#include <geovoronoi/detail/big_array.hpp>
#include <geovoronoi/detail/parents.hpp>
#include <geovoronoi/detail/seq/dijkstra.hpp>
#include <geovoronoi/detail/seq/sparse.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <limits>
#include <numeric>
#include <type_traits>
#include <vector>

namespace geovoronoi {
namespace sequential {

namespace impl = geovoronoi::detail::seq_engine;

/**
 * @brief Reusable scratch memory of the sequential backend's sparse searches (bounded_solve,
 *        single_source, insert_queries).
 *
 * Without one, each call allocates its own scratch: a page table of 8 bytes per 64 voxels of the grid
 * plus pages for the voxels the search visits. A workspace keeps that memory from one call to the
 * next, so many small calls on the same grid (Distance Ratio's bounded solves, Sibson's batches of
 * queries) pay for the table once. Between calls it holds only the table (all empty) and the pool of
 * pages, sized by the largest search so far. Pass it with the policy: `geovoronoi::seq(ws)`.
 * A workspace serves one call at a time (it is not thread-safe: give each thread its own); it works
 * with any grid, any problem and both value types, and results do not depend on it.
 *
 * @code
 * geovoronoi::sequential::workspace ws;
 * for (const auto& batch : batches) {
 *   auto cells = geovoronoi::insert_queries(geovoronoi::seq(ws), p, d, batch);
 *   // ...
 * }
 * @endcode
 */
class workspace {
 public:
  /// Bytes held between calls.
  std::size_t bytes() const noexcept {
    return f_.keys.pages.bytes() + d_.keys.pages.bytes();
  }
  /// Gives the memory back (the next call allocates afresh).
  void release() {
    f_ = {};
    d_ = {};
  }
  /// The scratch for value type @p T (float or double).
  template <class T>
  impl::sparse_scratch<T>& scratch() noexcept {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>, "workspace: T must be float or double");
    if constexpr (std::is_same_v<T, float>)
      return f_;
    else
      return d_;
  }

 private:
  impl::sparse_scratch<float> f_;
  impl::sparse_scratch<double> d_;
};

/// Policy type of the sequential backend: `geovoronoi::seq`, or `geovoronoi::seq(ws)` to reuse a
/// workspace's scratch memory across calls.
struct par_t {
  workspace* ws = nullptr;

  /// The same policy, with sparse searches using @p w's scratch memory (which must outlive the calls).
  constexpr par_t operator()(workspace& w) const noexcept { return par_t{&w}; }

  /// Calls f(scratch) with the workspace's scratch for T, or with a fresh one.
  template <class T, class F>
  decltype(auto) with_scratch(F&& f) const {
    if (ws) return f(ws->scratch<T>());
    impl::sparse_scratch<T> local;
    return f(local);
  }
};

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

/// Bounded (sparse) multi-source solve (backend hook; call geovoronoi::bounded_solve): scratch
/// proportional to the voxels reached, plus the policy's workspace page table.
template <class P>
sparse_solution<T_of<P>> backend_bounded(par_t policy, const P& p, const std::vector<source<T_of<P>>>& sources,
                                         T_of<P> radius) {
  return policy.with_scratch<T_of<P>>([&](auto& s) { return impl::bounded(p, s.keys, s.heap, sources, radius); });
}

/// Insert-query for a batch of queries (backend hook; call geovoronoi::insert_queries), one after the
/// other in one scratch: each query's search touches its cell and the cell's rim only.
template <class P>
query_cells<T_of<P>> backend_insert_queries(par_t policy, const P& p, const diagram<T_of<P>, P::dim>& d,
                                            const std::vector<index_t>& queries) {
  query_cells<T_of<P>> out;
  out.query.reserve(queries.size());
  out.offsets.reserve(queries.size() + 1);
  policy.with_scratch<T_of<P>>(
      [&](auto& s) { impl::insert_queries(p, s.keys, s.heap, d, queries.data(), queries.size(), out); });
  return out;
}

/// The shape functions may run their insert-queries as fused host searches on this backend (its
/// engine is a host Dijkstra anyway): see detail/shape/fused_query.hpp.
inline std::true_type backend_queries_on_host(par_t) { return {}; }

}  // namespace sequential

/// The sequential backend's policy object: `geovoronoi::voronoi(geovoronoi::seq, ...)`.
inline constexpr sequential::par_t seq{};

}  // namespace geovoronoi

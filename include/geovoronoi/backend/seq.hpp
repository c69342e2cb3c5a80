#pragma once
/// @file backend/seq.hpp
/// @brief The sequential backend: Dijkstra with a monotone radix heap on the implicit grid graph.
///
/// Select it by passing geovoronoi::seq as the first argument of any solver entry point
/// (geovoronoi/voronoi.hpp). It is the reference every other backend is tested against, and it is
/// itself tested against a brute-force Bellman-Ford oracle. The sparse searches (bounded_solve,
/// single_source, insert_queries) keep their keys in a paged scratch whose memory follows what they
/// visit; pass geovoronoi::seq(ws) with a seq_workspace to reuse it across calls.

#include <geovoronoi/backend/seq/detail/insert.hpp>
#include <geovoronoi/backend/seq/detail/solve.hpp>
#include <geovoronoi/detail/search/sparse.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/result.hpp>

#include <type_traits>
#include <vector>

namespace geovoronoi {

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
 * geovoronoi::seq_workspace ws;
 * for (const auto& batch : batches) {
 *   auto cells = geovoronoi::insert_queries(geovoronoi::seq(ws), p, d, batch);
 *   // ...
 * }
 * @endcode
 */
class seq_workspace {
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
  detail::search::sparse_scratch<T>& scratch() noexcept {
    static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>, "workspace: T must be float or double");
    if constexpr (std::is_same_v<T, float>)
      return f_;
    else
      return d_;
  }

 private:
  detail::search::sparse_scratch<float> f_;
  detail::search::sparse_scratch<double> d_;
};

/// Policy type of the sequential backend: `geovoronoi::seq`, or `geovoronoi::seq(ws)` to reuse a
/// workspace's scratch memory across calls.
struct seq_t {
  using backend_policy_tag = void;  ///< marks a backend policy (is_backend_policy)
  seq_workspace* ws = nullptr;

  /// The same policy, with sparse searches using @p w's scratch memory (which must outlive the calls).
  constexpr seq_t operator()(seq_workspace& w) const noexcept { return seq_t{&w}; }

  /// Calls f(scratch) with the workspace's scratch for T, or with a fresh one.
  template <class T, class F>
  decltype(auto) with_scratch(F&& f) const {
    if (ws) return f(ws->scratch<T>());
    detail::search::sparse_scratch<T> local;
    return f(local);
  }
};

/// Dense multi-source solve (backend hook; call geovoronoi::voronoi or geovoronoi::geodesic_solve).
/// Reports progress through @p ctl (solve_options::progress); one thread whatever ctl.threads says.
template <class P>
diagram<typename P::value_type, P::dim> backend_solve(seq_t, const P& p,
                                                      const std::vector<source<typename P::value_type>>& sources,
                                                      typename P::value_type radius,
                                                      const detail::solve_control& ctl = {}) {
  return detail::seq::solve(p, sources, radius, ctl);
}

/// Dense multi-source solve over the nodes of an explicit graph (backend hook; call
/// geovoronoi::voronoi with a branching problem): the same engine as backend_solve.
template <class P>
node_diagram<typename P::value_type> backend_solve_nodes(seq_t, const P& p,
                                                         const std::vector<source<typename P::value_type>>& sources,
                                                         typename P::value_type radius,
                                                         const detail::solve_control& ctl = {}) {
  return detail::seq::solve_nodes(p, sources, radius, ctl);
}

/// Bounded (sparse) multi-source solve (backend hook; call geovoronoi::bounded_solve): scratch
/// proportional to the voxels reached, plus the policy's workspace page table.
template <class P>
sparse_solution<typename P::value_type> backend_bounded(seq_t policy, const P& p,
                                                        const std::vector<source<typename P::value_type>>& sources,
                                                        typename P::value_type radius,
                                                        const detail::solve_control& ctl = {}) {
  return policy.with_scratch<typename P::value_type>(
      [&](auto& s) { return detail::seq::bounded(p, s, sources, radius, ctl); });
}

/// Insert-query for a batch of queries (backend hook; call geovoronoi::insert_queries), one after the
/// other in one scratch: each query's search touches its cell and the cell's rim only.
template <class P>
query_cells<typename P::value_type> backend_insert_queries(seq_t policy, const P& p,
                                                           const diagram<typename P::value_type, P::dim>& d,
                                                           const std::vector<index_t>& queries) {
  return policy.with_scratch<typename P::value_type>(
      [&](auto& s) { return detail::seq::insert_queries(p, s, d, queries); });
}

/// The shape functions may run their insert-queries as fused host searches on this backend (its
/// engine is a host Dijkstra anyway): see detail/shape/fused_query.hpp.
inline std::true_type backend_queries_on_host(seq_t) { return {}; }

/// The sequential backend's policy object: `geovoronoi::voronoi(geovoronoi::seq, ...)`.
inline constexpr seq_t seq{};

}  // namespace geovoronoi

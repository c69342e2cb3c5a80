#pragma once
// The solvers' dispatch layer: calls a backend's hooks on input that is already checked and
// normalised. The public entry points (voronoi.hpp) check and normalise once, then come here; the
// library's own callers (the shape functions) come here directly with input they built themselves
// and know to be valid, so nothing is re-checked, re-sorted or formatted per node or per query.
//
// Preconditions, which nothing here checks:
//   sources: non-empty, distinct voxels inside the grid and the domain, finite initial distances
//            >= +0 (never -0: its sign bit would order its packed key after every positive one),
//            labels >= 0;
//   radius:  not NaN, already in the distance type T (no conversion from double here);
//   queries: voxels inside the grid and the domain; the diagram is on the problem's grid.

#include <geovoronoi/detail/hooks.hpp>
#include <geovoronoi/detail/search/parents.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/result.hpp>

#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::dispatch {

/// Dense solve below @p radius; the seeds' voxels recorded, the parent image added on request;
/// progress and threads as @p ctl says, where the backend supports them.
template <class Policy, class P>
diagram<typename P::value_type, P::dim> solve(const Policy& policy, const P& p,
                                              const std::vector<source<typename P::value_type>>& sources,
                                              typename P::value_type radius, bool with_parent,
                                              const solve_control& ctl = {}) {
  if constexpr (is_backend_policy_v<Policy>) {  // else the entry point's static_assert has spoken
    static_assert(hooks::has_solve<Policy, P>::value,
                  "geovoronoi: this backend provides no dense solve (backend_solve) for this problem");
    if constexpr (hooks::has_solve<Policy, P>::value) {
      auto d = [&] {
        if constexpr (hooks::has_solve_control<Policy, P>::value) {
          return backend_solve(policy, p, sources, radius, ctl);
        } else {  // a backend that cannot report: the start and the end only
          ctl.report(0.0);
          auto r = backend_solve(policy, p, sources, radius);
          ctl.report(1.0);
          return r;
        }
      }();
      d.seeds.reserve(sources.size());
      for (const auto& x : sources) d.seeds.push_back(x.voxel);
      if (with_parent) search::compute_parents(p, d, sources);
      return d;
    }
  }
  return {};
}

/// Bounded (sparse) solve: the voxels below @p radius, sorted by voxel.
template <class Policy, class P>
sparse_solution<typename P::value_type> bounded(const Policy& policy, const P& p,
                                                const std::vector<source<typename P::value_type>>& sources,
                                                typename P::value_type radius, const solve_control& ctl = {}) {
  if constexpr (is_backend_policy_v<Policy>) {
    static_assert(hooks::has_bounded<Policy, P>::value,
                  "geovoronoi: this backend provides no bounded solve (backend_bounded) for this problem");
    if constexpr (hooks::has_bounded_control<Policy, P>::value) {
      return backend_bounded(policy, p, sources, radius, ctl);
    } else if constexpr (hooks::has_bounded<Policy, P>::value) {
      ctl.report(0.0);
      auto r = backend_bounded(policy, p, sources, radius);
      ctl.report(1.0);
      return r;
    }
  }
  return {};
}

/// New cells of @p queries in @p d.
template <class Policy, class P>
query_cells<typename P::value_type> insert_queries(const Policy& policy, const P& p,
                                                   const diagram<typename P::value_type, P::dim>& d,
                                                   const std::vector<index_t>& queries) {
  if constexpr (is_backend_policy_v<Policy>) {
    static_assert(hooks::has_insert<Policy, P>::value,
                  "geovoronoi: this backend provides no insert-query (backend_insert_queries) for this problem");
    if constexpr (hooks::has_insert<Policy, P>::value) return backend_insert_queries(policy, p, d, queries);
  }
  return {};
}

}  // namespace geovoronoi::detail::dispatch

#pragma once
// The hooks a backend policy provides, found by argument-dependent lookup on its policy type, and the
// one place that detects them. A hook that a backend lacks is either a compile error naming it (the
// solves, dispatch.hpp) or a documented fallback (the host loops and threads, parallel.hpp):
//
//   backend_solve(policy, problem, sources, radius [, solve_control])        dense multi-source solve
//   backend_bounded(policy, problem, sources, radius [, solve_control])      voxels below a radius
//   backend_solve_nodes(policy, problem, sources, radius, solve_control)      dense solve over an explicit
//                                                                             graph's nodes (branching grids)
//   backend_insert_queries(policy, problem, diagram, queries)                 new cells of query voxels
//   backend_with_threads(policy, threads, f)                                  f() on that many host threads
//   backend_host_parallel_for(policy, n, f)                                   f(i), i in [0, n), maybe concurrent
//   backend_host_threads(policy) -> unsigned                                  threads that loop may use (default:
//                                                                             the hardware's with a parallel
//                                                                             loop, else 1)
//   backend_queries_on_host(policy) -> std::true_type / std::false_type      whether Sibson and Laplace may
//                                                                             run their insert-queries as
//                                                                             host searches (search/fused_*)

#include <geovoronoi/config.hpp>
#include <geovoronoi/result.hpp>

#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::hooks {

template <class Policy, class P, class = void>
struct has_solve : std::false_type {};
template <class Policy, class P>
struct has_solve<Policy, P,
                 std::void_t<decltype(backend_solve(std::declval<const Policy&>(), std::declval<const P&>(),
                                                    std::declval<const std::vector<source<typename P::value_type>>&>(),
                                                    std::declval<typename P::value_type>()))>> : std::true_type {};

template <class Policy, class P, class = void>
struct has_solve_control : std::false_type {};
template <class Policy, class P>
struct has_solve_control<
    Policy, P,
    std::void_t<decltype(backend_solve(std::declval<const Policy&>(), std::declval<const P&>(),
                                       std::declval<const std::vector<source<typename P::value_type>>&>(),
                                       std::declval<typename P::value_type>(), std::declval<const solve_control&>()))>>
    : std::true_type {};

template <class Policy, class P, class = void>
struct has_solve_nodes : std::false_type {};
template <class Policy, class P>
struct has_solve_nodes<
    Policy, P,
    std::void_t<decltype(backend_solve_nodes(std::declval<const Policy&>(), std::declval<const P&>(),
                                             std::declval<const std::vector<source<typename P::value_type>>&>(),
                                             std::declval<typename P::value_type>(),
                                             std::declval<const solve_control&>()))>> : std::true_type {};

template <class Policy, class P, class = void>
struct has_bounded : std::false_type {};
template <class Policy, class P>
struct has_bounded<Policy, P,
                   std::void_t<decltype(backend_bounded(std::declval<const Policy&>(), std::declval<const P&>(),
                                                        std::declval<const std::vector<source<typename P::value_type>>&>(),
                                                        std::declval<typename P::value_type>()))>> : std::true_type {};

template <class Policy, class P, class = void>
struct has_bounded_control : std::false_type {};
template <class Policy, class P>
struct has_bounded_control<
    Policy, P,
    std::void_t<decltype(backend_bounded(std::declval<const Policy&>(), std::declval<const P&>(),
                                         std::declval<const std::vector<source<typename P::value_type>>&>(),
                                         std::declval<typename P::value_type>(), std::declval<const solve_control&>()))>>
    : std::true_type {};

template <class Policy, class P, class = void>
struct has_insert : std::false_type {};
template <class Policy, class P>
struct has_insert<Policy, P,
                  std::void_t<decltype(backend_insert_queries(
                      std::declval<const Policy&>(), std::declval<const P&>(),
                      std::declval<const diagram<typename P::value_type, P::dim>&>(),
                      std::declval<const std::vector<index_t>&>()))>> : std::true_type {};

template <class Policy, class = void>
struct has_with_threads : std::false_type {};
template <class Policy>
struct has_with_threads<Policy, std::void_t<decltype(backend_with_threads(std::declval<const Policy&>(), 0u,
                                                                          std::declval<int (*)()>()))>>
    : std::true_type {};

/// A loop body for detecting backend_host_parallel_for.
struct parallel_for_probe {
  void operator()(index_t) const noexcept {}
};
template <class Policy, class = void>
struct has_host_parallel_for : std::false_type {};
template <class Policy>
struct has_host_parallel_for<Policy, std::void_t<decltype(backend_host_parallel_for(
                                         std::declval<const Policy&>(), index_t{}, parallel_for_probe{}))>>
    : std::true_type {};

template <class Policy, class = void>
struct has_host_threads : std::false_type {};
template <class Policy>
struct has_host_threads<Policy, std::void_t<decltype(backend_host_threads(std::declval<const Policy&>()))>>
    : std::true_type {};

/// Whether the backend's Sibson and Laplace insert-queries may run as host searches.
template <class Policy, class = void>
struct queries_on_host : std::false_type {};
template <class Policy>
struct queries_on_host<Policy, std::void_t<decltype(backend_queries_on_host(std::declval<const Policy&>()))>>
    : decltype(backend_queries_on_host(std::declval<const Policy&>())) {};

}  // namespace geovoronoi::detail::hooks

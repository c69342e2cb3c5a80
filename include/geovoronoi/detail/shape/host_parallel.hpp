#pragma once
// Host-side loops of the shape functions, parallel where the backend offers host threads.
//
// A backend may provide, found by argument-dependent lookup on its policy type,
//     template <class F> void backend_host_parallel_for(const Policy&, index_t n, F&& f);
// calling f(i) once for every i in [0, n), possibly concurrently, and rethrowing on the calling thread
// the first exception a call threw. Without it (the sequential backend), the loop runs in order.

#include <geovoronoi/config.hpp>

#include <type_traits>
#include <utility>

namespace geovoronoi::detail::shape {

struct no_host_parallel_probe {
  void operator()(index_t) const noexcept {}
};

template <class Policy, class = void>
struct has_host_parallel_for : std::false_type {};
template <class Policy>
struct has_host_parallel_for<Policy, std::void_t<decltype(backend_host_parallel_for(
                                         std::declval<const Policy&>(), index_t{}, no_host_parallel_probe{}))>>
    : std::true_type {};

/// Runs f(i) for i in [0, n) through the backend's host-parallel loop if it has one, else in order.
template <class Policy, class F>
void host_parallel_for(const Policy& policy, index_t n, F&& f) {
  if (n <= 0) return;
  if constexpr (has_host_parallel_for<Policy>::value) {
    backend_host_parallel_for(policy, n, std::forward<F>(f));
  } else {
    for (index_t i = 0; i < n; ++i) f(i);
  }
}

}  // namespace geovoronoi::detail::shape

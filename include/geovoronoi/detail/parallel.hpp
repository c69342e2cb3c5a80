#pragma once
// Host threads and host loops, through the backend's hooks (hooks.hpp) where it has them: the shape
// functions' per-query and per-node loops run here, in parallel on backends with host threads.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/hooks.hpp>

#include <algorithm>
#include <thread>
#include <type_traits>
#include <utility>

namespace geovoronoi::detail {

/**
 * Runs f() with @p threads host threads for @p policy's backend: through the backend's hook
 * backend_with_threads(policy, threads, f) (Thrust on OpenMP or TBB), else f() as it is (seq, CUDA:
 * nothing to set). 0 keeps the system's default.
 */
template <class Policy, class F>
decltype(auto) with_threads(const Policy& policy, unsigned threads, F&& f) {
  if constexpr (hooks::has_with_threads<Policy>::value) {
    if (threads != 0) return backend_with_threads(policy, threads, std::forward<F>(f));
  }
  (void)policy;
  (void)threads;
  return f();
}

/// Runs f(i) for i in [0, n) through the backend's host-parallel loop (backend_host_parallel_for: f
/// called once for every i, possibly concurrently, the first exception rethrown on the calling
/// thread) if it has one, else in order on the calling thread.
template <class Policy, class F>
void host_parallel_for(const Policy& policy, index_t n, F&& f) {
  if (n <= 0) return;
  if constexpr (hooks::has_host_parallel_for<Policy>::value) {
    backend_host_parallel_for(policy, n, std::forward<F>(f));
  } else {
    (void)policy;
    for (index_t i = 0; i < n; ++i) f(i);
  }
}

/// The host threads @p policy's host-parallel loop may use: its backend_host_threads hook, else the
/// hardware's threads for a backend with a parallel loop, else 1.
template <class Policy>
unsigned host_threads(const Policy& policy) {
  if constexpr (hooks::has_host_threads<Policy>::value) {
    return backend_host_threads(policy);
  } else {
    (void)policy;
    if constexpr (hooks::has_host_parallel_for<Policy>::value) return std::max(1u, std::thread::hardware_concurrency());
    return 1u;
  }
}

}  // namespace geovoronoi::detail

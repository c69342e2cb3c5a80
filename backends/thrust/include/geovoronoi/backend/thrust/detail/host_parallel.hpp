#pragma once
// Host-side parallel loops for code that runs on the host whatever the Thrust system (the shape
// functions' per-query loops): which host threading an execution policy stands for, and a loop that
// carries the first exception of its body back to the calling thread.

#include <geovoronoi/backend/thrust/detail/system.hpp>
#include <geovoronoi/config.hpp>

#include <thrust/system/cpp/detail/execution_policy.h>
#include <thrust/system/omp/detail/execution_policy.h>
#include <thrust/system/tbb/detail/execution_policy.h>

#include <atomic>
#include <exception>
#include <type_traits>
#include <utility>

#ifdef _OPENMP
#include <omp.h>
#endif
#if __has_include(<tbb/task_arena.h>)
#include <tbb/task_arena.h>
#define GEOVORONOI_THRUST_HAS_TBB_ARENA 1
#endif

namespace geovoronoi::thrust::detail {

/// How host loops run for an execution policy: on the calling thread, on the policy's own host
/// threads (OpenMP or TBB systems), or, for the CUDA system, on OpenMP threads when the translation
/// unit is compiled with OpenMP (the loop body is host code).
enum class host_threads { serial, policy, openmp };

template <class D>
std::integral_constant<host_threads, host_threads::policy> host_threads_test(
    const ::thrust::system::omp::detail::execution_policy<D>*);
template <class D>
std::integral_constant<host_threads, host_threads::policy> host_threads_test(
    const ::thrust::system::tbb::detail::execution_policy<D>*);
std::integral_constant<host_threads, host_threads::serial> host_threads_test(...);

template <class Exec>
constexpr host_threads host_threads_of() noexcept {
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef _OPENMP
    return host_threads::openmp;
#else
    return host_threads::serial;
#endif
  } else {
    return decltype(host_threads_test(static_cast<const Exec*>(nullptr)))::value;
  }
}

template <class D>
std::true_type is_tbb_policy_test(const ::thrust::system::tbb::detail::execution_policy<D>*);
std::false_type is_tbb_policy_test(...);
/// Whether an execution policy runs on the TBB system.
template <class Exec>
inline constexpr bool is_tbb_policy_v = decltype(is_tbb_policy_test(static_cast<const Exec*>(nullptr)))::value;

#ifdef _OPENMP
/// The calling thread's OpenMP thread count set for a scope, then restored.
class omp_threads_scope {
 public:
  explicit omp_threads_scope(unsigned threads) : old_(omp_get_max_threads()) { omp_set_num_threads(int(threads)); }
  ~omp_threads_scope() { omp_set_num_threads(old_); }
  omp_threads_scope(const omp_threads_scope&) = delete;
  omp_threads_scope& operator=(const omp_threads_scope&) = delete;

 private:
  int old_;
};
#endif

/**
 * Calls f() with @p threads host threads for @p Exec (0: unchanged): a TBB task arena of that size
 * on the TBB system, the calling thread's OpenMP thread count on the systems whose host loops run
 * on OpenMP threads; as is elsewhere. Results never depend on it, only the speed.
 */
template <class Exec, class F>
decltype(auto) with_host_threads(const Exec&, unsigned threads, F&& f) {
  if constexpr (is_tbb_policy_v<Exec>) {
#ifdef GEOVORONOI_THRUST_HAS_TBB_ARENA
    if (threads != 0) {
      ::tbb::task_arena arena{static_cast<int>(threads)};
      return arena.execute(std::forward<F>(f));
    }
#endif
  } else if constexpr (host_threads_of<Exec>() != host_threads::serial) {
#ifdef _OPENMP
    if (threads != 0) {
      const omp_threads_scope scope(threads);
      return f();
    }
#endif
  }
  (void)threads;
  return f();
}

/// The first exception thrown by any call of a loop body; later calls are skipped once one threw.
struct first_error {
  std::atomic<int> state{0};  // 0 none, 1 being recorded, 2 recorded
  std::exception_ptr error;
  bool failed() const noexcept { return state.load(std::memory_order_relaxed) != 0; }
  void record(std::exception_ptr e) noexcept {
    int expect = 0;
    if (state.compare_exchange_strong(expect, 1, std::memory_order_acq_rel)) {
      error = std::move(e);
      state.store(2, std::memory_order_release);
    }
  }
};

template <class F>
struct guarded_call {
  F* f;
  first_error* err;
  void operator()(index_t i) const noexcept {
    if (err->failed()) return;
    try {
      (*f)(i);
    } catch (...) {
      err->record(std::current_exception());
    }
  }
};

/**
 * Calls f(i) for every i in [0, n) on host threads chosen by host_threads_of<Exec>(), in any
 * order, concurrently where that is parallel. If a call throws, the calls not yet started are
 * skipped and the first exception is rethrown on the calling thread once every thread has finished.
 */
template <class Exec, class F>
void host_parallel_for(const Exec& exec, index_t n, F& f) {
  if (n <= 0) return;
  first_error err;
  const guarded_call<F> call{&f, &err};
  constexpr host_threads how = host_threads_of<Exec>();
  if constexpr (how == host_threads::policy) {
    // every index counts as a large step (per-query work dwarfs waking the threads), and the loop
    // is one long step, so the pacing of short engine steps does not apply
    parallel_for(exec, n, call, n * host_grain, false);
  } else if constexpr (how == host_threads::openmp) {
    (void)exec;
#ifdef _OPENMP
#pragma omp parallel for schedule(dynamic, 1)
    for (index_t i = 0; i < n; ++i) call(i);
#endif
  } else {
    (void)exec;
    for (index_t i = 0; i < n && !err.failed(); ++i) call(i);
  }
  if (err.failed()) std::rethrow_exception(err.error);
}

}  // namespace geovoronoi::thrust::detail

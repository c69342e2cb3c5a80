#pragma once
// What differs between Thrust systems, kept in one place: where the working arrays live (host
// memory for CPP/OMP/TBB, device memory for CUDA), how a few per-chunk counts are scanned, and how
// a value is read back. Everything else is the same code on every system.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/big_array.hpp>

#include <thrust/execution_policy.h>
#include <thrust/for_each.h>
#include <thrust/iterator/counting_iterator.h>
#include <thrust/scan.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <type_traits>
#include <vector>

#ifdef __CUDACC__
#include <thrust/copy.h>
#include <thrust/device_ptr.h>
#include <thrust/system/cuda/vector.h>
#endif

namespace geovoronoi::thrust::detail {

#ifdef __CUDACC__
template <class D>
std::true_type is_cuda_policy_test(const ::thrust::cuda_cub::execution_policy<D>*);
#endif
std::false_type is_cuda_policy_test(...);

/// Whether an execution policy runs on the CUDA system (its memory is device memory).
template <class Exec>
inline constexpr bool is_cuda_policy_v = decltype(is_cuda_policy_test(static_cast<const Exec*>(nullptr)))::value;

/// Host systems: std::vector on huge pages where the system allows them. The engine reads and
/// writes keys and flags at random over the whole volume; with 4 KiB pages nearly every access that
/// misses the cache also misses the TLB (docs/backend-thrust.md, "Memory").
template <class Exec, class U, bool Device = is_cuda_policy_v<Exec>>
struct vector_for {
  using type = std::vector<U, geovoronoi::detail::huge_page_allocator<U>>;
};
#ifdef __CUDACC__
template <class Exec, class U>
struct vector_for<Exec, U, true> {
  using type = ::thrust::cuda::vector<U>;
};
#endif

/// A working array in the memory of the system that @p Exec runs on.
template <class Exec, class U>
using vec = typename vector_for<Exec, U>::type;

template <class U, class A>
U* raw(std::vector<U, A>& v) noexcept {
  return v.data();
}
template <class V>
auto raw(V& v) noexcept -> decltype(::thrust::raw_pointer_cast(v.data())) {
  return ::thrust::raw_pointer_cast(v.data());
}

/// Read one element of system memory on the host.
template <class Exec, class U>
U read(const U* p) {
  if constexpr (is_cuda_policy_v<Exec>) {
#ifdef __CUDACC__
    U x;
    ::thrust::copy(::thrust::device_pointer_cast(p), ::thrust::device_pointer_cast(p) + 1, &x);
    return x;
#endif
  } else {
    return *p;
  }
}

/// Replace counts[0..n) by their exclusive prefix sums; returns the total.
template <class Exec>
index_t exclusive_scan(const Exec& exec, index_t* counts, index_t n) {
  if (n == 0) return 0;
  if constexpr (is_cuda_policy_v<Exec>) {
    const index_t last = read<Exec>(counts + n - 1);
    ::thrust::exclusive_scan(exec, counts, counts + n, counts);
    return read<Exec>(counts + n - 1) + last;
  } else {
    // host memory and few chunks: a plain loop beats a (possibly sequential) library scan
    index_t s = 0;
    for (index_t i = 0; i < n; ++i) {
      const index_t c = counts[i];
      counts[i] = s;
      s += c;
    }
    return s;
  }
}

/// Work (in voxel visits) below which a host system runs a step on the calling thread: waking a
/// thread team costs more than a small step, and much more on a loaded machine.
inline constexpr index_t host_grain = 32768;

/// Whether a step of @p work voxel visits should run in parallel on @p Exec's system.
template <class Exec>
bool go_parallel(index_t work) noexcept {
  return is_cuda_policy_v<Exec> || work >= host_grain;
}

/// Nanoseconds of a monotonic clock (host).
inline std::int64_t host_clock_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// Host systems: a few worker slots that take blocks of indices from a shared counter. Thrust's
/// OpenMP for_each splits its range statically, so one descheduled thread (a loaded machine) would
/// hold up the whole step; with self-scheduling the other threads take its share. The first slot
/// that finds no block left records the time (for host_pacing).
template <class F>
struct self_scheduled {
  F f;
  index_t n;
  index_t block;
  index_t* next;
  std::int64_t* first_idle;
  void operator()(index_t) const {
    for (;;) {
      const index_t b = __atomic_fetch_add(next, index_t(1), __ATOMIC_RELAXED);
      const index_t begin = b * block;
      if (begin >= n) {
        std::int64_t none = 0;
        if (__atomic_load_n(first_idle, __ATOMIC_RELAXED) == 0)
          __atomic_compare_exchange_n(first_idle, &none, host_clock_ns(), false, __ATOMIC_RELAXED, __ATOMIC_RELAXED);
        return;
      }
      const index_t end = begin + block < n ? begin + block : n;
      for (index_t i = begin; i < end; ++i) f(i);
    }
  }
};

/**
 * Host systems: how parallel steps are spread over threads when the machine is shared.
 *
 * A parallel step ends only when every thread of the team has reached its end. When another
 * process holds a core, a thread of the team may wait for a time slice (milliseconds) while the
 * others, having taken all the work, wait for it; a solve has hundreds of steps, so this can cost
 * seconds (OpenMP threads that spin-wait make it worse). When two parallel steps in a row each
 * did their work and then waited more than half the step and over 0.5 ms for a thread to arrive,
 * paced steps run on the calling thread alone for a while: `factor` times the last wait (8 at
 * first, doubling while it keeps happening, up to 256), and never more than 1 s. A parallel step
 * without such a wait resets the factor.
 *
 * Two rules keep this from feeding on itself. The pause is measured in time, not in steps (steps at
 * 256^3 last ten times longer than at 128^3, so a pause of 8-256 steps lasted seconds there). And
 * one waited step is not enough: the first parallel step after a serial stretch (a pause, or the
 * small steps that always run on the calling thread) also pays for waking the idle worker threads,
 * which on a virtual machine can take milliseconds; counted, it starts the next pause, which lets
 * the workers fall idle again. This loop is the likely cause of the 256^3 solves that ran at the
 * one-thread speed on a quiet machine (docs/backend-thrust.md, "Shared machines"). The state is
 * process-wide (a busy machine stays busy from one solve to the next),
 * updated with relaxed atomics: it is a scheduling hint, and the results never depend on it. On a
 * quiet machine nothing changes.
 */
struct host_pacing {
  std::atomic<std::int64_t> serial_until{0};  ///< host_clock_ns() before which paced steps run serially
  std::atomic<int> factor{8};
  std::atomic<int> strikes{0};  ///< consecutive parallel steps that waited

  /// Whether the next step should run on the calling thread.
  bool take_serial() noexcept {
    const std::int64_t until = serial_until.load(std::memory_order_relaxed);
    return until != 0 && host_clock_ns() < until;
  }
  /// Record how a parallel step went.
  void observe(std::int64_t start, std::int64_t first_idle, std::int64_t stop) noexcept {
    const std::int64_t waited = first_idle ? stop - first_idle : 0;
    if (waited > 500000 && 2 * waited > stop - start) {
      if (strikes.fetch_add(1, std::memory_order_relaxed) < 1) return;
      strikes.store(0, std::memory_order_relaxed);
      const int f = factor.load(std::memory_order_relaxed);
      const std::int64_t pause = std::min<std::int64_t>(std::int64_t(f) * waited, 1000000000);
      serial_until.store(stop + pause, std::memory_order_relaxed);
      factor.store(f < 256 ? 2 * f : 256, std::memory_order_relaxed);
    } else {
      strikes.store(0, std::memory_order_relaxed);
      factor.store(8, std::memory_order_relaxed);
    }
  }
};

inline host_pacing& process_pacing() noexcept {
  static host_pacing p;
  return p;
}

/// Call f(i) for i in [0, n) on the policy's system (on the calling thread when @p work is small,
/// or, for a @p paced step, when host_pacing says the team is being held up).
template <class Exec, class F>
void parallel_for(const Exec& exec, index_t n, const F& f, index_t work, bool paced = true) {
  if (n <= 0) return;
  if constexpr (is_cuda_policy_v<Exec>) {
    (void)work;
    (void)paced;
    ::thrust::for_each(exec, ::thrust::counting_iterator<index_t>(0), ::thrust::counting_iterator<index_t>(n), f);
  } else {
    host_pacing& pace = process_pacing();
    if (!go_parallel<Exec>(work) || (paced && pace.take_serial())) {
      for (index_t i = 0; i < n; ++i) f(i);
      return;
    }
    const index_t slots = n < 64 ? n : 64;
    const index_t block = (n + 511) / 512;
    index_t next = 0;
    std::int64_t first_idle = 0;
    const std::int64_t start = host_clock_ns();
    ::thrust::for_each(exec, ::thrust::counting_iterator<index_t>(0), ::thrust::counting_iterator<index_t>(slots),
                       self_scheduled<F>{f, n, block, &next, &first_idle});
    if (paced) pace.observe(start, first_idle, host_clock_ns());
  }
}

}  // namespace geovoronoi::thrust::detail

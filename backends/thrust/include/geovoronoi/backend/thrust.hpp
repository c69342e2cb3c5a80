#pragma once
/// @file backend/thrust.hpp
/// @brief The Thrust backend: parallel near-far relaxation on any Thrust system (CUDA, OpenMP, TBB,
///        CPP), bitwise identical to the sequential backend.
///
/// Select it by passing geovoronoi::thrust::par (the consumer's THRUST_DEVICE_SYSTEM) or
/// geovoronoi::thrust::par_on(policy) (an explicit Thrust execution policy such as thrust::omp::par)
/// as the first argument of any solver entry point in geovoronoi/voronoi.hpp. Link the CMake target
/// geovoronoi::thrust and choose the system yourself, or one of geovoronoi::thrust_omp, thrust_tbb,
/// thrust_cpp, thrust_cuda, which set THRUST_DEVICE_SYSTEM for you. With the CUDA system the
/// translation unit must be compiled by nvcc.
///
/// @code
/// #include <geovoronoi.hpp>
/// #include <geovoronoi/backend/thrust.hpp>
/// geovoronoi::thrust::stats st;
/// auto d = geovoronoi::voronoi(geovoronoi::thrust::par.with_stats(&st), problem, seeds);
/// double work = st.expansions_per_voxel();   // 1.0 would be Dijkstra's
/// @endcode
///
/// The algorithm, its memory use and its limits are described in docs/backend-thrust.md.

#include <geovoronoi/backend/thrust/detail/host_parallel.hpp>
#include <geovoronoi/backend/thrust/detail/insert.hpp>
#include <geovoronoi/backend/thrust/detail/engine.hpp>
#include <geovoronoi/backend/thrust/detail/solve.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/result.hpp>

#include <thrust/execution_policy.h>

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi {
namespace thrust {

/// Work counters of the last call made with a policy that points at this struct.
struct stats {
  std::uint64_t expansions = 0;  ///< voxel expansions (a voxel expanded k times counts k)
  std::uint64_t reached = 0;     ///< voxels with a finite distance (cells' voxels for insert-query)
  std::uint64_t rounds = 0;      ///< parallel expansion rounds
  std::uint64_t splits = 0;      ///< threshold raises
  std::uint64_t suspects = 0;    ///< voxels the engine marked for the label repair (solves only)
  std::uint64_t relabelled = 0;  ///< voxels whose label the repair recomputed (suspects and their heirs)
  /// Expansions per reached voxel: 1 means every voxel was expanded once, with its final key.
  double expansions_per_voxel() const noexcept { return reached ? double(expansions) / double(reached) : 0.0; }
};

/**
 * @brief Policy of the Thrust backend on the consumer's THRUST_DEVICE_SYSTEM (thrust::device).
 *
 * Trivially copyable; `with_*` return modified copies.
 */
struct par_t {
  using backend_policy_tag = void;  ///< marks a backend policy (is_backend_policy), par_on_t's too
  /// Voxels a threshold raise aims to release at once (0: a default per system, 65536 on host
  /// systems, 262144 on CUDA). Larger gives more parallelism per round and more re-expansions.
  std::size_t batch = 0;
  /// Where to write the work counters of each call (none when null).
  stats* report = nullptr;

  constexpr par_t with_batch(std::size_t b) const noexcept { return par_t{b, report}; }
  constexpr par_t with_stats(stats* s) const noexcept { return par_t{batch, s}; }
};

/**
 * @brief Policy of the Thrust backend on an explicit Thrust execution policy.
 * @tparam ExecutionPolicy e.g. the type of thrust::omp::par, thrust::tbb::par, thrust::cpp::par,
 *         thrust::cuda::par.on(stream).
 */
template <class ExecutionPolicy>
struct par_on_t : par_t {
  ExecutionPolicy exec;
  par_on_t() = default;
  par_on_t(const par_t& base, const ExecutionPolicy& e) : par_t(base), exec(e) {}
  par_on_t with_batch(std::size_t b) const { return par_on_t(par_t::with_batch(b), exec); }
  par_on_t with_stats(stats* s) const { return par_on_t(par_t::with_stats(s), exec); }
};

/// The backend on the consumer's THRUST_DEVICE_SYSTEM: `geovoronoi::voronoi(geovoronoi::thrust::par, ...)`.
inline constexpr par_t par{};

/**
 * @brief The backend on an explicit Thrust execution policy.
 * @code
 * auto d = geovoronoi::voronoi(geovoronoi::thrust::par_on(thrust::omp::par), problem, seeds);
 * @endcode
 */
template <class ExecutionPolicy>
par_on_t<ExecutionPolicy> par_on(const ExecutionPolicy& exec, par_t base = {}) {
  return par_on_t<ExecutionPolicy>(base, exec);
}

namespace detail {
template <class Exec>
index_t target_of(const par_t& pol) {
  if (pol.batch) return static_cast<index_t>(pol.batch);
  return is_cuda_policy_v<Exec> ? index_t(1) << 18 : index_t(1) << 16;
}
inline void report(const par_t& pol, const engine_counts& c) {
  if (!pol.report) return;
  pol.report->expansions = c.expansions;
  pol.report->rounds = c.rounds;
  pol.report->splits = c.splits;
  pol.report->reached = c.reached;
  pol.report->suspects = c.suspects;
  pol.report->relabelled = c.relabelled;
}
/// The Thrust execution policy a backend policy runs on.
inline auto exec_of(const par_t&) { return ::thrust::device; }
template <class E>
const E& exec_of(const par_on_t<E>& pol) {
  return pol.exec;
}
/// par_t and every par_on_t<E>: the policies the hooks below accept.
template <class Pol>
using if_policy = std::enable_if_t<std::is_base_of_v<par_t, Pol>, int>;
/// Calls f(exec, target, counts) on @p pol's execution policy and batch target, then reports the
/// counts to @p pol's stats.
template <class Pol, class F>
auto counted(const Pol& pol, F&& f) {
  const auto& exec = exec_of(pol);
  engine_counts c;
  auto r = f(exec, target_of<std::decay_t<decltype(exec)>>(pol), c);
  report(pol, c);
  return r;
}
}  // namespace detail

/// Dense multi-source solve (backend hook; call geovoronoi::voronoi or geovoronoi::geodesic_solve),
/// for par and par_on(...). Labels are exact (tie rule) after a targeted repair pass; see
/// detail/repair.hpp. Reports progress through @p ctl once per expansion round.
template <class Pol, class P, detail::if_policy<Pol> = 0>
diagram<typename P::value_type, P::dim> backend_solve(const Pol& pol, const P& p,
                                                      const std::vector<source<typename P::value_type>>& s,
                                                      typename P::value_type radius,
                                                      const geovoronoi::detail::solve_control& ctl = {}) {
  return detail::counted(pol, [&](const auto& exec, index_t target, detail::engine_counts& c) {
    return detail::solve(exec, p, s, radius, target, c, ctl);
  });
}

/// Dense multi-source solve over the nodes of an explicit graph (backend hook; call geovoronoi::voronoi
/// with a branching problem): the same engine and label repair as backend_solve. The graph's arrays
/// are host memory; on the CUDA system the engine walks device copies of them (made per call, freed
/// on return), the label repair runs on the host.
template <class Pol, class P, detail::if_policy<Pol> = 0>
node_diagram<typename P::value_type> backend_solve_nodes(const Pol& pol, const P& p,
                                                         const std::vector<source<typename P::value_type>>& s,
                                                         typename P::value_type radius,
                                                         const geovoronoi::detail::solve_control& ctl) {
  return detail::counted(pol, [&](const auto& exec, index_t target, detail::engine_counts& c) {
    return detail::solve_nodes(exec, p, s, radius, target, c, ctl);
  });
}

/// Bounded (sparse) solve (backend hook; call geovoronoi::bounded_solve or single_source).
/// Scratch memory on this backend is proportional to the grid, not to the voxels reached.
template <class Pol, class P, detail::if_policy<Pol> = 0>
sparse_solution<typename P::value_type> backend_bounded(const Pol& pol, const P& p,
                                                        const std::vector<source<typename P::value_type>>& s,
                                                        typename P::value_type radius,
                                                        const geovoronoi::detail::solve_control& ctl = {}) {
  return detail::counted(pol, [&](const auto& exec, index_t target, detail::engine_counts& c) {
    return detail::bounded(exec, p, s, radius, target, c, ctl);
  });
}

/// Batched insert-query (backend hook; call geovoronoi::insert_queries or insert_query).
template <class Pol, class P, detail::if_policy<Pol> = 0>
query_cells<typename P::value_type> backend_insert_queries(const Pol& pol, const P& p,
                                                           const diagram<typename P::value_type, P::dim>& d,
                                                           const std::vector<index_t>& q) {
  return detail::counted(pol, [&](const auto& exec, index_t target, detail::engine_counts& c) {
    auto r = detail::insert_queries(exec, p, d, q, target, c);
    c.reached = r.voxel.size();
    return r;
  });
}

/**
 * @brief Host-side parallel loop (backend hook for code that loops over queries on the host, such as
 *        the shape functions): calls f(i) for every i in [0, n).
 *
 * On the OpenMP and TBB systems the calls run concurrently on that system's threads (self-scheduled
 * blocks); on the CPP system serially; on the CUDA system f is host code, so the loop runs on OpenMP
 * threads when the translation unit is compiled with OpenMP, else serially. f must be safe to call
 * concurrently for different i. If a call throws, calls not yet started are skipped and the first
 * exception is rethrown here after every thread has finished.
 */
template <class Pol, class F, detail::if_policy<Pol> = 0>
void backend_host_parallel_for(const Pol& pol, index_t n, F&& f) {
  detail::host_parallel_for(detail::exec_of(pol), n, f);
}

/**
 * @brief Runs f() with @p threads host threads (backend hook behind solve_options::threads and
 *        shape_options::threads): on the OpenMP system, and for the host loops of the CUDA system
 *        when compiled with OpenMP, the calling thread's OpenMP thread count for the call; on the TBB
 *        system a task arena of that many threads; on the CPP system and on the GPU nothing changes.
 */
template <class Pol, class F, detail::if_policy<Pol> = 0>
decltype(auto) backend_with_threads(const Pol& pol, unsigned threads, F&& f) {
  return detail::with_host_threads(detail::exec_of(pol), threads, std::forward<F>(f));
}

/// Whether the shape functions may run insert-queries as fused host searches on this policy: on
/// host systems (their insert-query is the sequential engine on host threads), not on CUDA.
inline std::bool_constant<!detail::is_cuda_policy_v<std::decay_t<decltype(::thrust::device)>>> backend_queries_on_host(
    const par_t&) {
  return {};
}
/// @copydoc backend_queries_on_host
template <class E>
std::bool_constant<!detail::is_cuda_policy_v<E>> backend_queries_on_host(const par_on_t<E>&) {
  return {};
}

}  // namespace thrust
}  // namespace geovoronoi

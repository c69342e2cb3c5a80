#pragma once
/// @file backend/cuda.cuh
/// @brief The CUDA kernel backend: tiled wavefront relaxation in shared memory with an active-tile
///        worklist on the device and packed (distance, label) keys updated with 64-bit atomicMin.
///
/// Select it by passing geovoronoi::cuda::par (or `par.on(stream)`) as the first argument of any
/// solver entry point in geovoronoi/voronoi.hpp. Results are bitwise identical to geovoronoi::seq:
/// edge weights come from the same metric objects and stencil lengths through the relaxation step of
/// detail/search/relax.hpp (additions are __fadd_rn / __dadd_rn) and the target carries
/// --fmad=false. Needs nvcc; link geovoronoi::cuda.
///
/// Device memory: plain cudaMalloc through RAII owners (never managed memory). A dense float solve
/// peaks at 12 bytes per voxel (4 field + 8 key) plus 12 bytes per 512-voxel tile; a double solve at
/// 20 bytes per voxel (8 field + 8 distance + 4 label). Every CUDA failure throws
/// geovoronoi::cuda::cuda_error (a geovoronoi::error) naming the call and CUDA's message.
///
/// @code
/// #include <geovoronoi.hpp>
/// #include <geovoronoi/backend/cuda.cuh>
/// auto d = geovoronoi::voronoi(geovoronoi::cuda::par.on(stream), problem, seeds);
/// @endcode

#include <geovoronoi/backend/cuda/detail/engine.cuh>
#include <geovoronoi/backend/cuda/detail/error.cuh>
#include <geovoronoi/backend/cuda/detail/insert.cuh>
#include <geovoronoi/backend/cuda/detail/repair.cuh>
#include <geovoronoi/backend/cuda/detail/solve.cuh>
#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/detail/overflow.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/result.hpp>

#include <cuda_runtime.h>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace geovoronoi::cuda {

/**
 * @brief Policy type of the CUDA backend: which stream the work is queued on.
 *
 * Calls are synchronous with respect to the host (they return finished results) but only touch
 * @c stream, so several host threads can solve concurrently on different streams.
 */
struct par_t {
  using backend_policy_tag = void;  ///< marks a backend policy (is_backend_policy)
  /// The stream every copy and kernel goes to; nullptr is the default stream.
  cudaStream_t stream = nullptr;
  /// @brief The same policy on stream @p s: `geovoronoi::cuda::par.on(s)`.
  constexpr par_t on(cudaStream_t s) const noexcept { return par_t{s}; }
};

/// The CUDA backend's policy object: `geovoronoi::voronoi(geovoronoi::cuda::par, ...)`.
inline constexpr par_t par{};

/**
 * @brief Dense multi-source solve (backend hook; call geovoronoi::voronoi or geodesic_solve).
 * @throws cuda_error on any CUDA failure, metric_error on a negative or NaN edge weight,
 *         overflow_error when an unbounded solve's distances overflow T (found like seq's). It reports
 *         progress only at the start and the end (the dispatch layer does), and cannot be cancelled.
 */
template <class P>
diagram<detail::T_of<P>, P::dim> backend_solve(par_t policy, const P& p,
                                               const std::vector<source<detail::T_of<P>>>& sources,
                                               detail::T_of<P> radius) {
  using T = detail::T_of<P>;
  diagram<T, P::dim> d;
  d.distance = image<T, P::dim>(p.geometry, std::numeric_limits<T>::infinity());
  d.label = image<label_t, P::dim>(p.geometry, no_label);
  const bool overflowed = detail::solve_each_reached(p, sources, radius, policy.stream, [&](index_t v, T dist, label_t l) {
    d.distance[v] = dist;
    d.label[v] = l;
  });
  if (overflowed && !(radius <= std::numeric_limits<T>::max()))
    geovoronoi::detail::throw_if_overflowed_dense(p, d.distance.data());
  return d;
}

/**
 * @brief Radius-bounded solve (backend hook; call geovoronoi::bounded_solve or single_source).
 *
 * Runs the dense engine with the radius as acceptance bound (device memory is dense, unlike seq's)
 * and returns the reached voxels sorted by index.
 */
template <class P>
sparse_solution<detail::T_of<P>> backend_bounded(par_t policy, const P& p,
                                                 const std::vector<source<detail::T_of<P>>>& sources,
                                                 detail::T_of<P> radius) {
  using T = detail::T_of<P>;
  sparse_solution<T> r;
  const bool overflowed = detail::solve_each_reached(p, sources, radius, policy.stream, [&](index_t v, T dist, label_t l) {
    r.voxel.push_back(v);
    r.distance.push_back(dist);
    r.label.push_back(l);
  });
  if (overflowed && !(radius <= std::numeric_limits<T>::max()))
    geovoronoi::detail::throw_if_overflowed_sparse(p, r.voxel.data(), r.distance.data(), r.size());
  return r;
}

/// Queries per kernel launch of insert_queries (bounds the output slots: 4096 voxels each).
inline constexpr std::size_t query_batch = 256;

/**
 * @brief New cells of many queries at once (backend hook; call geovoronoi::insert_queries).
 *
 * One block per query relaxes a box around it in shared memory; queries whose cell reaches an open
 * box face are recomputed by the tiled engine over the whole grid. Same output as seq.
 */
template <class P>
query_cells<detail::T_of<P>> backend_insert_queries(par_t policy, const P& p, const diagram<detail::T_of<P>, P::dim>& d,
                                                    const std::vector<index_t>& queries) {
  using T = detail::T_of<P>;
  using B = detail::query_box_shape<P::dim>;
  const cudaStream_t s = policy.stream;
  query_cells<T> out;
  out.query = queries;
  out.offsets.reserve(queries.size() + 1);
  if (queries.empty()) return out;
  const auto t = detail::tiling_of(p);
  const detail::device_problem<P> dp(p, s);
  detail::device_buffer<T> old(std::size_t(t.voxels()));
  old.upload(d.distance.data(), old.size(), s);

  const std::size_t batch = std::min(query_batch, queries.size());
  detail::device_buffer<index_t> dq(batch);
  detail::device_buffer<index_t> ovox(batch * B::voxels);
  detail::device_buffer<T> odist(batch * B::voxels);
  detail::device_buffer<std::uint32_t> ocount(batch), oflow(batch);
  std::vector<std::uint32_t> count(batch), flow(batch);
  std::vector<index_t> vox;
  std::vector<T> dist;
  detail::device_buffer<unsigned long long> fallback;  // allocated on the first overflow

  for (std::size_t b0 = 0; b0 < queries.size(); b0 += batch) {
    const std::size_t nb = std::min(batch, queries.size() - b0);
    dq.upload(queries.data() + b0, nb, s);
    const detail::query_out<T> o{ovox.data(), odist.data(), ocount.data(), oflow.data()};
    detail::insert_box_kernel<P><<<unsigned(nb), detail::query_threads, 0, s>>>(dp.view, t, old.data(), dq.data(), o);
    GEOVORONOI_CUDA_CHECK_LAUNCH("insert_box_kernel");
    ocount.download(count.data(), nb, s);
    oflow.download(flow.data(), nb, s);
    vox.resize(nb * B::voxels);
    dist.resize(nb * B::voxels);
    ovox.download(vox.data(), vox.size(), s);
    odist.download(dist.data(), dist.size(), s);
    detail::sync(s, "insert_box_kernel");
    for (std::size_t i = 0; i < nb; ++i) {
      if (!flow[i]) {
        const std::size_t at = i * B::voxels;
        for (std::size_t j = 0; j < count[i]; ++j) {
          out.voxel.push_back(vox[at + j]);
          out.distance.push_back(dist[at + j]);
          out.owner.push_back(d.label[vox[at + j]]);
        }
      } else {
        // the cell leaves the box: relax from the query over the whole grid
        const index_t q = queries[b0 + i];
        if (!fallback.size()) fallback = detail::device_buffer<unsigned long long>(std::size_t(t.voxels()));
        fallback.fill_bytes(0xFF, s);
        std::vector<detail::seed_word> seed;
        if (T(0) < d.distance[q]) seed.push_back({q, detail::distance_word(T(0))});
        detail::run_engine(dp.view, detail::rule_insert<T>{old.data()}, t, fallback.data(), seed, s);
        std::vector<unsigned long long> words(fallback.size());
        fallback.download(words.data(), words.size(), s);
        detail::sync(s, "insert-query fallback");
        for (std::size_t v = 0; v < words.size(); ++v)
          if (words[v] != detail::unreached) {
            out.voxel.push_back(index_t(v));
            out.distance.push_back(detail::word_distance<T>(words[v]));
            out.owner.push_back(d.label[index_t(v)]);
          }
      }
      out.offsets.push_back(out.voxel.size());
    }
  }
  return out;
}

}  // namespace geovoronoi::cuda

/// @file bench/voronoi/thrust.cpp
/// @brief The Thrust backend over the voronoi case matrix, on the OpenMP system (`thrust_omp`), the TBB system
///        (`thrust_tbb`) and,
///        when compiled by nvcc, on the CUDA system (`thrust_cuda`, timed with CUDA events).
///
/// Linked with bench/voronoi/seq.cpp into one executable so that ratios come from one run:
///   bench_voronoi_thrust --benchmark_filter='voronoi/(seq|thrust_omp)/gradient/128/10/26'
/// Counter `relaxations_per_voxel`: voxel expansions (each relaxes the voxel's N edges) per reached
/// voxel in the last solve; 1.0 is Dijkstra's (every voxel expanded once, with its final key).
/// Counter `rounds`: parallel expansion steps; `relabelled`: voxels whose label the repair pass recomputed.

#include "common.hpp"

#include <geovoronoi/backend/thrust.hpp>

#if defined(GEOVORONOI_BENCH_THRUST_OMP)
#include <thrust/system/omp/execution_policy.h>
#endif
#if defined(GEOVORONOI_BENCH_THRUST_TBB)
#include <thrust/system/tbb/execution_policy.h>
#endif
#if defined(__CUDACC__)
#include <cuda_runtime.h>
#include <thrust/system/cuda/execution_policy.h>
#endif

namespace {
namespace gb = geovoronoi::bench;

gb::case_hooks stats_hooks(geovoronoi::thrust::stats* st) {
  gb::case_hooks h;
  h.before = [st](benchmark::State&) { *st = {}; };
  h.after = [st](benchmark::State& state) {
    state.counters["relaxations_per_voxel"] = st->expansions_per_voxel();
    state.counters["rounds"] = double(st->rounds);
    state.counters["relabelled"] = double(st->relabelled);
  };
  return h;
}

const std::vector<int> sizes{64, 128, 256};
const std::vector<int> seed_counts{10, 100, 1000};
const std::vector<int> conns{6, 26};
}  // namespace

#if defined(GEOVORONOI_BENCH_THRUST_OMP)
GEOVORONOI_BENCH_REGISTER(register_thrust_omp_cases) {
  static geovoronoi::thrust::stats st;
  gb::register_voronoi_cases("thrust_omp", geovoronoi::thrust::par_on(::thrust::omp::par).with_stats(&st), sizes,
                             seed_counts, conns, gb::field_names(), false, stats_hooks(&st));
  gb::register_voronoi_cases("thrust_omp", geovoronoi::thrust::par_on(::thrust::omp::par).with_stats(&st), {221},
                             {20}, {26}, {"mri"}, false, stats_hooks(&st));
}
#endif

#if defined(GEOVORONOI_BENCH_THRUST_TBB)
GEOVORONOI_BENCH_REGISTER(register_thrust_tbb_cases) {
  static geovoronoi::thrust::stats st;
  gb::register_voronoi_cases("thrust_tbb", geovoronoi::thrust::par_on(::thrust::tbb::par).with_stats(&st), sizes,
                             seed_counts, conns, gb::field_names(), false, stats_hooks(&st));
  gb::register_voronoi_cases("thrust_tbb", geovoronoi::thrust::par_on(::thrust::tbb::par).with_stats(&st), {221},
                             {20}, {26}, {"mri"}, false, stats_hooks(&st));
}
#endif

#if defined(__CUDACC__)
GEOVORONOI_BENCH_REGISTER(register_thrust_cuda_cases) {
  int devices = 0;
  if (cudaGetDeviceCount(&devices) != cudaSuccess || devices == 0) return;  // nothing to time
  static geovoronoi::thrust::stats st;
  const auto policy = geovoronoi::thrust::par_on(::thrust::cuda::par).with_stats(&st);
  auto solve = [policy](const auto& p, const std::vector<geovoronoi::coord<3>>& s) {
    cudaEvent_t a, b;
    cudaEventCreate(&a);
    cudaEventCreate(&b);
    cudaEventRecord(a);
    auto d = geovoronoi::voronoi(policy, p, s);
    cudaEventRecord(b);
    cudaEventSynchronize(b);
    float ms = 0;
    cudaEventElapsedTime(&ms, a, b);
    cudaEventDestroy(a);
    cudaEventDestroy(b);
    benchmark::DoNotOptimize(d);
    return double(ms) * 1e-3;
  };
  gb::register_solver_cases("thrust_cuda", solve, sizes, seed_counts, conns, gb::field_names(), true,
                            stats_hooks(&st));
  gb::register_solver_cases("thrust_cuda", solve, std::vector<int>{221}, std::vector<int>{20}, std::vector<int>{26},
                            std::vector<std::string>{"mri"}, true, stats_hooks(&st));
}
#endif

GEOVORONOI_BENCH_MAIN()

/// @file bench/voronoi/cuda.cu
/// @brief The CUDA kernel backend over the voronoi case matrix, timed with CUDA events.
///
/// Cases (all with UseManualTime, the time being what the events measure on the backend's stream):
///  - `voronoi/cuda/<field>/<n>/<seeds>/<conn>`: the device solve alone: the field is already on the
///    device and the result stays there (allocation of the keys, seeding, both engine passes with their
///    worklists and host checks of the active count every few iterations). n = 64..512; constant, gradient, steak; 10, 100, 1000 seeds.
///  - `voronoi/cuda_end_to_end/<field>/<n>/<seeds>/<conn>`: the whole `geovoronoi::voronoi(cuda::par, ...)`
///    call: field upload, solve, download and unpacking into the diagram images.
///  - `copy/cuda/<n>`: a device-to-device copy of the float solve's working set (12 bytes per voxel):
///    the bandwidth ceiling the solve's passes are compared against.
/// Counters: voxels_per_second, ns_per_voxel (bench/common.hpp); iterations (engine iterations per
/// solve); model_bytes_per_voxel (peak device memory of the solve from the backend's memory model);
/// resident_bytes_per_voxel (device memory held after the solve, measured with cudaMemGetInfo);
/// achieved_bytes_per_second of the copy.
/// Without a CUDA device the executable registers nothing and says so.

#include "common.hpp"

#include <geovoronoi/backend/cuda.cuh>

#include <cstdio>
#include <memory>

namespace {
namespace gv = geovoronoi;
namespace cd = geovoronoi::cuda::detail;

/// One stream and two events for the whole run, created on first use (not at start-up).
struct timing {
  cudaStream_t stream = nullptr;
  cd::event start, stop;
  timing() { GEOVORONOI_CUDA_CHECK(cudaStreamCreate(&stream)); }
  ~timing() { (void)cudaStreamDestroy(stream); }
  double seconds() {
    GEOVORONOI_CUDA_CHECK(cudaEventSynchronize(stop.get()));
    float ms = 0;
    GEOVORONOI_CUDA_CHECK(cudaEventElapsedTime(&ms, start.get(), stop.get()));
    return double(ms) * 1e-3;
  }
};
timing& clock_() {
  static timing t;
  return t;
}

struct last_stats {
  long long iterations = 0;
  double resident = 0;
};
last_stats& stats() {
  static last_stats s;
  return s;
}

/// Device solve only: field upload and result download are outside the events.
struct device_solve {
  template <class P>
  double operator()(const P& p, const std::vector<gv::coord<3>>& seeds) const {
    auto& c = clock_();
    const auto t = cd::tiling_of(p);
    std::size_t free_before = 0, free_after = 0, total = 0;
    GEOVORONOI_CUDA_CHECK(cudaMemGetInfo(&free_before, &total));
    const cd::device_problem<P> dp(p, c.stream);
    std::vector<gv::source<float>> src;
    for (std::size_t i = 0; i < seeds.size(); ++i) src.push_back({p.geometry.index(seeds[i]), 0.0f, gv::label_t(i)});
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.start.get(), c.stream));
    // the backend's own dense solve (both passes); the state stays on the device until the end
    const auto st = cd::solve_dense(dp, t, src, std::numeric_limits<float>::infinity(), c.stream, &stats().iterations);
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.stop.get(), c.stream));
    const double secs = c.seconds();
    GEOVORONOI_CUDA_CHECK(cudaMemGetInfo(&free_after, &total));
    stats().resident = double(free_before - free_after) / double(t.voxels());
    return secs;
  }
};

/// The public entry point, transfers included.
struct end_to_end {
  template <class P>
  double operator()(const P& p, const std::vector<gv::coord<3>>& seeds) const {
    auto& c = clock_();
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.start.get(), c.stream));
    const auto d = gv::voronoi(gv::cuda::par.on(c.stream), p, seeds);
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.stop.get(), c.stream));
    benchmark::DoNotOptimize(d.distance.data());
    return c.seconds();
  }
};

void copy_case(benchmark::State& state, int n) {
  auto& c = clock_();
  const std::size_t bytes = std::size_t(n) * n * n * (sizeof(float) + sizeof(unsigned long long));
  cd::device_buffer<unsigned char> a(bytes), b(bytes);
  a.fill_bytes(1, c.stream);
  for (auto _ : state) {
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.start.get(), c.stream));
    GEOVORONOI_CUDA_CHECK(cudaMemcpyAsync(b.data(), a.data(), bytes, cudaMemcpyDeviceToDevice, c.stream));
    GEOVORONOI_CUDA_CHECK(cudaEventRecord(c.stop.get(), c.stream));
    state.SetIterationTime(c.seconds());
  }
  // a copy reads and writes every byte
  state.counters["achieved_bytes_per_second"] =
      benchmark::Counter(2.0 * double(bytes) * double(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["working_set_bytes"] = double(bytes);
}

bool have_device() {
  int n = 0;
  const cudaError_t e = cudaGetDeviceCount(&n);
  if (e != cudaSuccess || n == 0) {
    std::fprintf(stderr, "bench_voronoi_cuda: no CUDA device (%s); no case registered\n",
                 e != cudaSuccess ? cudaGetErrorString(e) : "0 devices");
    (void)cudaGetLastError();
    return false;
  }
  return true;
}
}  // namespace

GEOVORONOI_BENCH_REGISTER(register_cuda_cases) {
  if (!have_device()) return;
  namespace b = geovoronoi::bench;
  b::case_hooks hooks;
  hooks.after = [](benchmark::State& state) {
    state.counters["iterations"] = double(stats().iterations);
    state.counters["resident_bytes_per_voxel"] = stats().resident;
    const auto t = cd::make_tiling<3>(256, 256, 256);
    state.counters["model_bytes_per_voxel"] =
        double(cd::solve_device_bytes<float>(t.voxels(), t.tiles())) / double(t.voxels());
  };
  for (int n : {64, 128, 256, 512}) {
    const benchmark::IterationCount iters = n <= 128 ? 20 : n <= 256 ? 5 : 2;
    b::register_solver_cases("cuda", device_solve{}, {n}, {10, 100, 1000}, {6, 26}, b::field_names(), true, hooks,
                             iters);
    if (n <= 256)
      b::register_solver_cases("cuda_end_to_end", end_to_end{}, {n}, {10}, {26}, b::field_names(), true, {}, iters);
    benchmark::RegisterBenchmark(("copy/cuda/" + std::to_string(n)).c_str(),
                                 [n](benchmark::State& s) { copy_case(s, n); })
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond)
        ->Iterations(10);
  }
}

#ifndef GEOVORONOI_BENCH_COMBINED
GEOVORONOI_BENCH_MAIN()
#endif

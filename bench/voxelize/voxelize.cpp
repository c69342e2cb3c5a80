// The mesh voxelizer (voxelize.hpp) on icospheres of 20 * 4^s triangles, scaled to an ellipsoid that
// fills most of an n^3 grid of unit spacing, against a per-voxel ray-casting baseline.
// Names: voxelize/<rule>/s<subdivisions>/<n>/threads:<t> (t = 0: the hardware's threads), and
// raycast/s<subdivisions>/<n>: every voxel centre casts one ray along +x against every triangle
// (Moller-Trumbore, double), the textbook method, run on a small grid because it costs
// voxels x triangles; compare the voxels_per_second counters.
// The closed rule includes its checks (edge pairing, volume, self-intersection); the winding rule on
// a closed mesh skips the self-intersection check and runs the same exact sweep, so the difference
// of the two is the cost of the checks. winding_open removes one triangle: every voxel's winding
// number then comes from the hierarchical solid-angle sum (the floating-point path).
#include <benchmark/benchmark.h>
#include <geovoronoi/phantom.hpp>
#include <geovoronoi/voxelize.hpp>

#include <array>
#include <cstdlib>
#include <map>
#include <vector>

namespace gv = geovoronoi;
namespace {

bool smoke() { return std::getenv("GEOVORONOI_BENCH_SMOKE") != nullptr; }

const gv::triangle_mesh& mesh(int subdivisions, int n) {
  static std::map<std::pair<int, int>, gv::triangle_mesh> cache;
  auto& m = cache[{subdivisions, n}];
  if (m.triangles.empty()) {
    const double c = 0.5 * (n - 1);
    m = gv::phantom::ellipsoid_mesh({c + 0.1, c - 0.2, c + 0.3}, {0.47 * n, 0.4 * n, 0.33 * n}, subdivisions);
  }
  return m;
}

void run_voxelize(benchmark::State& state, gv::inside_rule rule, bool open) {
  const int s = int(state.range(0)), n = int(state.range(1));
  const gv::grid<3> g({n, n, n});
  std::vector<gv::voxelize_part> parts(1);
  parts[0].mesh = mesh(s, n);
  if (open) parts[0].mesh.triangles.erase(parts[0].mesh.triangles.begin());  // a hole: the tree path
  gv::voxelize_options o;
  o.rule = rule;
  o.threads = unsigned(state.range(2));
  for (auto _ : state) {
    auto v = gv::voxelize<float>(parts, g, o);
    benchmark::DoNotOptimize(v.label.data());
    state.counters["inside_voxels"] = double(v.stats.inside_voxels);
    state.counters["crossings"] = double(v.stats.crossings);
  }
  state.counters["triangles"] = double(parts[0].mesh.triangles.size());
  state.counters["voxels_per_second"] = benchmark::Counter(double(g.size()) * double(state.iterations()), benchmark::Counter::kIsRate);
}

void run_raycast(benchmark::State& state) {
  const int s = int(state.range(0)), n = int(state.range(1)), big = int(state.range(2));
  const auto& m = mesh(s, big);  // the mesh of the big grid, sampled on n^3 centres spread over it
  const double step = double(big) / n;
  std::size_t inside = 0;
  for (auto _ : state) {
    inside = 0;
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const double p[3] = {(x + 0.5) * step, (y + 0.5) * step + 1e-7, (z + 0.5) * step + 2e-7};
          int count = 0;
          for (const auto& t : m.triangles) {
            const auto &a = m.vertices[t[0]], &b = m.vertices[t[1]], &c = m.vertices[t[2]];
            const double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
            const double h[3] = {0, -e2[2], e2[1]};  // (1, 0, 0) x e2
            const double det = e1[1] * h[1] + e1[2] * h[2];
            if (det == 0) continue;
            const double sv[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
            const double u = (sv[1] * h[1] + sv[2] * h[2]) / det;
            if (u < 0 || u > 1) continue;
            const double q[3] = {sv[1] * e1[2] - sv[2] * e1[1], sv[2] * e1[0] - sv[0] * e1[2], sv[0] * e1[1] - sv[1] * e1[0]};
            const double v = q[0] / det;
            if (v < 0 || u + v > 1) continue;
            if ((e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det <= 0) continue;
            count += det > 0 ? 1 : -1;
          }
          inside += count != 0;
        }
    benchmark::DoNotOptimize(inside);
  }
  state.counters["inside_voxels"] = double(inside);
  state.counters["triangles"] = double(m.triangles.size());
  state.counters["voxels_per_second"] =
      benchmark::Counter(double(n) * n * n * double(state.iterations()), benchmark::Counter::kIsRate);
}

void args_voxelize(benchmark::internal::Benchmark* b) {
  if (smoke()) {
    b->Args({3, 32, 0})->Iterations(1);
    return;
  }
  b->Args({6, 256, 0})->Args({6, 256, 1})->Args({7, 256, 0})->Args({4, 64, 0})->MinTime(2.0);
}

void args_raycast(benchmark::internal::Benchmark* b) {
  if (smoke()) {
    b->Args({3, 4, 32})->Iterations(1);
    return;
  }
  b->Args({6, 16, 256})->Iterations(1);
}

}  // namespace

void args_open(benchmark::internal::Benchmark* b) {
  if (smoke()) {
    b->Args({3, 16, 0})->Iterations(1);
    return;
  }
  b->Args({5, 64, 0})->Args({5, 64, 1})->Iterations(1);
}

BENCHMARK_CAPTURE(run_voxelize, closed, gv::inside_rule::closed, false)
    ->Name("voxelize/closed")->ArgNames({"s", "n", "threads"})->Apply(args_voxelize)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(run_voxelize, winding, gv::inside_rule::winding, false)
    ->Name("voxelize/winding")->ArgNames({"s", "n", "threads"})->Apply(args_voxelize)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(run_voxelize, winding_open, gv::inside_rule::winding, true)
    ->Name("voxelize/winding_open")->ArgNames({"s", "n", "threads"})->Apply(args_open)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(run_raycast)->Name("raycast")->ArgNames({"s", "n", "of"})->Apply(args_raycast)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();

#pragma once
/// @file bench/branching/cases.hpp
/// @brief Voronoi on branching grids, `branching/<backend>/<case>`, each timed against its regular
///        reference in the same benchmark, the two solves alternating iteration by iteration.
///
/// The reference of a case is the regular grid of the same material at the coarse resolution: the
/// case's phantom drawn on the branching grid's coarse grid (same extents, spacing and origin), so it
/// has about as many domain voxels as the branching grid has copies and the same range of stiffness.
/// Same metric (min_stiffness), same connectivity (26), 10 seeds: the case's seed voxels taken to
/// their coarse cell (topped up from phantom::spread_seeds where such a cell is empty in the
/// reference). Cases:
///   fingers/f4: phantom::fingers on 256 x 256 x 64 fine voxels, 8 fingers, 1-voxel gaps, factor 4;
///               reference: phantom::fingers on the 64 x 64 x 16 coarse grid (8 fingers, 1-voxel gaps);
///   steak/f2:   phantom::steak on 256 x 192 x 64 fine voxels, factor 2 (stiffness: the mean of each
///               copy's fine voxels); reference: phantom::steak on the 128 x 96 x 32 coarse grid;
///   cube/f1:    a constant 64^3 cube at factor 1, which is the regular grid itself: the reference is
///               the same graph, so the ratio is the cost of the explicit adjacency alone.
/// Counters: copies, links, ref_voxels (the reference's domain voxels), ns_per_copy (wall time of the
/// branching solve per copy), ref_ns_per_voxel (wall time of the reference solve per domain voxel),
/// ratio = ns_per_copy / ref_ns_per_voxel (the target is <= 1.5). The reported Time is the branching
/// solve's. Building the grids is setup, not timed; both timings include the front end (seed mapping,
/// result allocation).

#include "common.hpp"

#include <geovoronoi/branching_grid.hpp>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace geovoronoi::bench::branching {

using bgrid = branching_grid<3, float, 26>;

struct bcase {
  image<float, 3> fine;
  bgrid bg;
  std::vector<coord<3>> seeds;
  image<float, 3> ref;  ///< the reference: the same phantom on the coarse grid
  std::vector<coord<3>> ref_seeds;
  index_t ref_voxels = 0;  ///< domain voxels of ref
};

/// The case @p name, built once per process.
inline const bcase& get_case(const std::string& name) {
  static std::map<std::string, std::unique_ptr<bcase>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<bcase>();
  auto& c = *slot;
  const bool smoke = smoke_run();
  int factor = 1;
  if (name == "fingers") {
    factor = 4;
    c.fine = phantom::fingers(smoke ? grid<3>({64, 32, 8}) : grid<3>({256, 256, 64}), 8, 1);
  } else if (name == "steak") {
    factor = 2;
    c.fine = phantom::steak(smoke ? grid<3>({32, 24, 8}) : grid<3>({256, 192, 64}));
  } else {  // cube
    const index_t n = smoke ? 16 : 64;
    c.fine = phantom::constant(grid<3>({n, n, n}));
  }
  c.bg = make_branching_grid(c.fine, factor, connectivity<26>{});
  const grid<3>& g = c.bg.coarse();
  if (name == "fingers")
    c.ref = phantom::fingers(g, 8, 1);
  else if (name == "steak")
    c.ref = phantom::steak(g);
  else
    c.ref = phantom::constant(g);
  for (index_t v = 0; v < c.ref.size(); ++v) c.ref_voxels += c.ref[v] > 0 ? 1 : 0;
  // 10 well-spread seeds, at most one per copy; the reference's: the same voxels' coarse cells
  std::vector<index_t> used, used_ref;
  for (const auto& s : phantom::spread_seeds(c.fine, 16)) {
    const index_t copy = c.bg.fine_copy()(s);
    if (std::find(used.begin(), used.end(), copy) != used.end()) continue;
    used.push_back(copy);
    c.seeds.push_back(s);
    const coord<3> cs{s[0] / factor, s[1] / factor, s[2] / factor};
    if (c.ref(cs) > 0 && std::find(used_ref.begin(), used_ref.end(), g.index(cs)) == used_ref.end()) {
      used_ref.push_back(g.index(cs));
      c.ref_seeds.push_back(cs);
    }
    if (c.seeds.size() == 10) break;
  }
  for (const auto& s : phantom::spread_seeds(c.ref, 32)) {
    if (c.ref_seeds.size() >= c.seeds.size()) break;
    if (std::find(used_ref.begin(), used_ref.end(), g.index(s)) != used_ref.end()) continue;
    used_ref.push_back(g.index(s));
    c.ref_seeds.push_back(s);
  }
  return c;
}

/// Registers the three cases for @p policy: each iteration runs the branching solve, then the
/// reference's, each timed on its own.
template <class Policy>
void register_cases(const std::string& backend, Policy policy) {
  const std::vector<std::pair<std::string, int>> cases{{"fingers", 4}, {"steak", 2}, {"cube", 1}};
  for (const auto& [name, factor] : cases) {
    const std::string label = "branching/" + backend + "/" + name + "/f" + std::to_string(factor);
    benchmark::RegisterBenchmark(label.c_str(), [policy, name = name](benchmark::State& state) {
      const auto& c = get_case(name);
      const auto p = make_problem(c.bg, min_stiffness{});
      const auto rp = make_problem(c.ref.geometry(), c.ref, min_stiffness{}, connectivity<26>{});
      using clock = std::chrono::steady_clock;
      double branching_s = 0, ref_s = 0;
      for (auto _ : state) {
        const auto t0 = clock::now();
        auto d = voronoi(policy, p, c.seeds);
        benchmark::DoNotOptimize(d);
        benchmark::ClobberMemory();
        const auto t1 = clock::now();
        auto rd = voronoi(policy, rp, c.ref_seeds);
        benchmark::DoNotOptimize(rd);
        benchmark::ClobberMemory();
        const auto t2 = clock::now();
        const double b = std::chrono::duration<double>(t1 - t0).count();
        branching_s += b;
        ref_s += std::chrono::duration<double>(t2 - t1).count();
        state.SetIterationTime(b);
      }
      const double it = double(state.iterations());
      const double ns_copy = branching_s * 1e9 / (double(c.bg.copies()) * it);
      const double ns_ref = ref_s * 1e9 / (double(c.ref_voxels) * it);
      state.counters["copies"] = double(c.bg.copies());
      state.counters["links"] = double(c.bg.links());
      state.counters["ref_voxels"] = double(c.ref_voxels);
      state.counters["ns_per_copy"] = ns_copy;
      state.counters["ref_ns_per_voxel"] = ns_ref;
      state.counters["ratio"] = ns_copy / ns_ref;
    })->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(min_time_1s);
  }
}

}  // namespace geovoronoi::bench::branching

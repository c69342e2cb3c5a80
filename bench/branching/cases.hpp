#pragma once
/// @file bench/branching/cases.hpp
/// @brief Voronoi on branching grids, `branching/<backend>/<case>`, against the regular solve of a grid
///        with about as many voxels as the branching grid has copies, `branching/<backend>/regular/<n>`,
///        in the same run. Cases (26-connectivity, min_stiffness, 10 seeds spread over the fine material):
///   fingers/f4: phantom::fingers on 256 x 256 x 64 fine voxels, 8 fingers, 1-voxel gaps, factor 4;
///   steak/f2:   phantom::steak on 256 x 192 x 64 fine voxels, factor 2;
///   cube/f1:    a constant 64^3 cube at factor 1 (the regular grid as a branching grid: the same graph
///               as regular/64, so the ratio is the cost of the explicit adjacency alone).
/// Counters: copies, links, ns_per_copy (wall time per solve over copies); the regular cases report
/// ns_per_copy too (voxels are its copies). Building the branching grid is setup, not timed.

#include "common.hpp"

#include <geovoronoi/branching_grid.hpp>

#include <chrono>
#include <cmath>
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
};

/// The case @p name, built once per process.
inline const bcase& get_case(const std::string& name) {
  static std::map<std::string, std::unique_ptr<bcase>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<bcase>();
  const bool smoke = smoke_run();
  int factor = 1;
  if (name == "fingers") {
    slot->fine = smoke ? phantom::fingers(grid<3>({64, 32, 8}), 8, 1) : phantom::fingers(grid<3>({256, 256, 64}), 8, 1);
    factor = 4;
  } else if (name == "steak") {
    slot->fine = phantom::steak(smoke ? grid<3>({32, 24, 8}) : grid<3>({256, 192, 64}));
    factor = 2;
  } else {  // cube
    const index_t n = smoke ? 16 : 64;
    slot->fine = phantom::constant(grid<3>({n, n, n}));
  }
  slot->bg = make_branching_grid(slot->fine, factor, connectivity<26>{});
  // 10 well-spread seeds, at most one per copy
  std::vector<index_t> used;
  for (const auto& s : phantom::spread_seeds(slot->fine, 16)) {
    const index_t c = slot->bg.fine_copy()(s);
    if (std::find(used.begin(), used.end(), c) != used.end()) continue;
    used.push_back(c);
    slot->seeds.push_back(s);
    if (slot->seeds.size() == 10) break;
  }
  return *slot;
}

/// Times @p solve() over the state's iterations and reports the counters.
template <class Solve>
void timed(benchmark::State& state, double nodes, double links, Solve&& solve) {
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    auto d = solve();
    benchmark::DoNotOptimize(d);
    benchmark::ClobberMemory();
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  state.counters["copies"] = nodes;
  state.counters["links"] = links;
  state.counters["ns_per_copy"] = secs * 1e9 / (nodes * double(state.iterations()));
}

/// Registers the three branching cases and their regular references for @p policy.
template <class Policy>
void register_cases(const std::string& backend, Policy policy) {
  const std::vector<std::pair<std::string, int>> cases{{"fingers", 4}, {"steak", 2}, {"cube", 1}};
  for (const auto& [name, factor] : cases) {
    const std::string label = "branching/" + backend + "/" + name + "/f" + std::to_string(factor);
    benchmark::RegisterBenchmark(label.c_str(), [policy, name = name](benchmark::State& state) {
      const auto& c = get_case(name);
      const auto p = make_problem(c.bg, min_stiffness{});
      timed(state, double(c.bg.copies()), double(c.bg.links()), [&] { return voronoi(policy, p, c.seeds); });
    })->UseRealTime()->Unit(benchmark::kMillisecond)->Apply(min_time_1s);
    // the regular reference: a constant cube with about as many voxels as the case has copies
    const index_t n = std::max<index_t>(2, index_t(std::lround(std::cbrt(double(get_case(name).bg.copies())))));
    const std::string rlabel = "branching/" + backend + "/regular/" + std::to_string(n) + "/for_" + name;
    benchmark::RegisterBenchmark(rlabel.c_str(), [policy, n, name = name](benchmark::State& state) {
      static std::map<index_t, image<float, 3>> fields;
      auto& f = fields[n];
      if (f.empty()) f = phantom::constant(grid<3>({n, n, n}));
      const auto p = make_problem(f.geometry(), f, min_stiffness{}, connectivity<26>{});
      const auto seeds = bench_seeds(f, 10);
      timed(state, double(f.size()), 0.0, [&] { return voronoi(policy, p, seeds); });
    })->UseRealTime()->Unit(benchmark::kMillisecond)->Apply(min_time_1s);
  }
}

}  // namespace geovoronoi::bench::branching

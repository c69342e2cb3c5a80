#pragma once
/// @file bench/branching/shape_cases.hpp
/// @brief Shape functions on branching grids, and their update after a blade cut.
///
/// `branching_shape/<backend>/<case>/<method>`: Sibson and Distance Ratio (K = 4) at every copy of
///   steak/f2: phantom::steak on 128 x 96 x 32 fine voxels, factor 2 (mean stiffness), 40 seeds;
///   fingers/f4: phantom::fingers on 128 x 128 x 32 fine voxels, 8 fingers, 1-voxel gaps, factor 4,
///               40 seeds.
///   Connectivity 26, min_stiffness; the diagram is setup. Counters: copies, ns_per_copy.
/// `branching_update/seq/<case>/distance_ratio`: a blade (a plane of fine +x edges, a fine voxel thick,
///   inside a coarse column, over half the height) cut into the grid; each iteration times the update
///   (update() of the diagram, update_shape_functions() with the kept state) and the full recompute on
///   the cut grid (voronoi() with parents, shape_functions() keeping the state), and checks that the
///   two give the same bits (else the benchmark fails). Building the cut grid is setup. Counters:
///   update_ms, full_ms, speedup = full / update (the target is >= 10).

#include "common.hpp"

#include <geovoronoi/branching_shape.hpp>

#include <chrono>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace geovoronoi::bench::branching_shape {

using bgrid = branching_grid<3, float, 26>;

struct scase {
  image<float, 3> fine;
  int factor = 1;
  bgrid bg;
  std::vector<coord<3>> seeds;
};

inline const scase& get_case(const std::string& name) {
  static std::map<std::string, std::unique_ptr<scase>> cache;
  auto& slot = cache[name];
  if (slot) return *slot;
  slot = std::make_unique<scase>();
  auto& c = *slot;
  const bool smoke = smoke_run();
  if (name == "fingers") {
    c.factor = 4;
    c.fine = phantom::fingers(smoke ? grid<3>({64, 32, 8}) : grid<3>({128, 128, 32}), 8, 1);
  } else {
    c.factor = 2;
    c.fine = phantom::steak(smoke ? grid<3>({32, 24, 8}) : grid<3>({128, 96, 32}));
  }
  c.bg = make_branching_grid(c.fine, c.factor, connectivity<26>{});
  std::vector<index_t> used;
  for (const auto& s : phantom::spread_seeds(c.fine, 80)) {
    const index_t copy = c.bg.fine_copy()(s);
    if (copy < 0 || std::find(used.begin(), used.end(), copy) != used.end()) continue;
    used.push_back(copy);
    c.seeds.push_back(s);
    if (c.seeds.size() == (smoke ? 8u : 40u)) break;
  }
  return c;
}

/// The blade of a case: fine +x edges at x = factor * (coarse columns / 3) + 1 (inside a coarse
/// column), for y in the lower half, every z.
inline cut_set<3> blade(const scase& c) {
  const grid<3>& g = c.fine.geometry();
  cut_set<3> cut(g, connectivity<26>{});
  constexpr auto offs = connectivity<26>::offsets();
  int px = -1;
  for (int k = 0; k < 26; ++k)
    if (offs[k][0] == 1 && offs[k][1] == 0 && offs[k][2] == 0) px = k;
  const index_t x = c.factor * (c.bg.coarse().extent(0) / 3) + 1;
  for (index_t z = 0; z < g.extent(2); ++z)
    for (index_t y = 0; y < g.extent(1) / 2; ++y) cut.insert(g.index({x, y, z}), px);
  return cut;
}

template <class Policy>
void register_shape_cases(const std::string& backend, Policy policy) {
  for (const std::string name : {"steak", "fingers"})
    for (const auto m : {shape_method::sibson, shape_method::distance_ratio}) {
      const std::string mname = m == shape_method::sibson ? "sibson" : "distance_ratio";
      const std::string label = "branching_shape/" + backend + "/" + name + "/" + mname;
      benchmark::RegisterBenchmark(label.c_str(), [policy, name, m](benchmark::State& state) {
        const auto& c = get_case(name);
        const auto p = make_problem(c.bg, min_stiffness{});
        const auto d = voronoi(policy, p, c.seeds);
        shape_options o;
        o.method = m;
        double total_s = 0;
        for (auto _ : state) {
          const auto t0 = std::chrono::steady_clock::now();
          auto w = shape_functions(policy, p, d, o);
          benchmark::DoNotOptimize(w);
          const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
          total_s += s;
          state.SetIterationTime(s);
        }
        state.counters["copies"] = double(c.bg.copies());
        state.counters["ns_per_copy"] = total_s * 1e9 / (double(c.bg.copies()) * double(state.iterations()));
      })->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(min_time_1s);
    }
}

inline bool same_bits(const copy_weights<float>& a, const copy_weights<float>& b) {
  return a.node == b.node && a.weight.size() == b.weight.size() &&
         std::memcmp(a.weight.data(), b.weight.data(), a.weight.size() * sizeof(float)) == 0;
}

template <class Policy>
void register_update_cases(const std::string& backend, Policy policy) {
  for (const std::string name : {"steak", "fingers"}) {
    const std::string label = "branching_update/" + backend + "/" + name + "/distance_ratio";
    benchmark::RegisterBenchmark(label.c_str(), [policy, name](benchmark::State& state) {
      const auto& c = get_case(name);
      const auto p = make_problem(c.bg, min_stiffness{});
      solve_options so;
      so.with_parent = true;
      shape_options o;
      o.method = shape_method::distance_ratio;
      o.keep_update_state = true;
      const auto d = voronoi(policy, p, c.seeds, so);
      const auto w = shape_functions(policy, p, d, o);
      const auto cut = blade(c);
      const auto after = make_branching_grid(c.fine, c.factor, connectivity<26>{}, cut);
      const auto pa = make_problem(after, min_stiffness{});
      using clock = std::chrono::steady_clock;
      double up_s = 0, full_s = 0;
      for (auto _ : state) {
        const auto t0 = clock::now();
        auto ud = update(policy, pa, c.bg, d, c.seeds);
        auto uw = update_shape_functions(policy, pa, c.bg, d, ud, w, o);
        const auto t1 = clock::now();
        auto fd = voronoi(policy, pa, c.seeds, so);
        auto fw = shape_functions(policy, pa, fd, o);
        const auto t2 = clock::now();
        if (!same_bits(uw, fw) || ud.distance != fd.distance || ud.label != fd.label || ud.parent != fd.parent) {
          state.SkipWithError("the update differs from the full recompute");
          break;
        }
        up_s += std::chrono::duration<double>(t1 - t0).count();
        full_s += std::chrono::duration<double>(t2 - t1).count();
        state.SetIterationTime(std::chrono::duration<double>(t1 - t0).count());
      }
      const double it = double(state.iterations());
      state.counters["copies"] = double(after.copies());
      state.counters["update_ms"] = up_s * 1e3 / it;
      state.counters["full_ms"] = full_s * 1e3 / it;
      state.counters["speedup"] = full_s / up_s;
    })->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(min_time_1s);
  }
}

}  // namespace geovoronoi::bench::branching_shape

// The shape-function benchmark cases, written once; each backend's file registers them with its
// policy. Names: shape/<method>/<backend>/<case>.
//   table1       100x40x20 voxels, constant field, 20 nodes (phantom::spread_seeds), uniform metric,
//                26-connected, weights for all 80,000 voxels (Toss et al. 2016, Table 1 setting)
//   128cube_100  128^3 voxels, constant field, 100 nodes, uniform metric, 26-connected (Distance Ratio)
//   steak        128x96x32 steak phantom, 12 nodes, min_stiffness metric, 26-connected
// The diagram is computed once outside the timed region; one iteration = one shape_functions() call.
#pragma once
#include <benchmark/benchmark.h>
#include <geovoronoi.hpp>

#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

namespace gvbench_shape {
namespace gv = geovoronoi;

inline const char* method_name(gv::shape_method m) {
  return m == gv::shape_method::sibson ? "sibson" : m == gv::shape_method::laplace ? "laplace" : "distance_ratio";
}

struct volume {
  gv::grid<3> g;
  gv::image<float, 3> field;
  std::vector<gv::coord<3>> nodes;
};

inline std::shared_ptr<volume> make_case(const std::string& name) {
  if (name == "table1") {
    const gv::grid<3> g({100, 40, 20});
    auto f = gv::phantom::constant(g);
    auto s = gv::phantom::spread_seeds(f, 20);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s)});
  }
  if (name == "128cube_100") {
    const gv::grid<3> g({128, 128, 128});
    auto f = gv::phantom::constant(g);
    auto s = gv::phantom::spread_seeds(f, 100);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s)});
  }
  const gv::grid<3> g({128, 96, 32});
  auto f = gv::phantom::steak(g);
  auto s = gv::phantom::spread_seeds(f, 12);
  return std::make_shared<volume>(volume{g, std::move(f), std::move(s)});
}

template <class Metric, class Policy>
void run_case(benchmark::State& state, Policy policy, std::shared_ptr<volume> c, gv::shape_method m) {
  const auto p = gv::make_problem(c->g, c->field, Metric{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(policy, p, c->nodes);
  gv::index_t reached = 0;
  for (gv::index_t v = 0; v < c->g.size(); ++v) reached += d.label[v] != gv::no_label;
  gv::shape_options o;
  o.method = m;
  for (auto _ : state) {
    auto w = gv::shape_functions(policy, p, d, o);
    benchmark::DoNotOptimize(w.weight.data());
  }
  state.counters["nodes"] = double(c->nodes.size());
  state.counters["voxels"] = double(reached);
  state.counters["voxels_per_s"] =
      benchmark::Counter(double(reached) * double(state.iterations()), benchmark::Counter::kIsRate);
}

/// Registers every case for one backend.
template <class Policy>
void register_cases(Policy policy, const std::string& backend) {
  const auto methods = {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace};
  // smoke mode (GEOVORONOI_BENCH_SMOKE, see bench/common.hpp): the small Table 1 case only; the steak's
  // Sibson alone takes minutes
  const bool smoke = std::getenv("GEOVORONOI_BENCH_SMOKE") != nullptr;
  for (const std::string name : {"table1", "128cube_100", "steak"})
    for (auto m : methods) {
      if (smoke && name != "table1") continue;
      if (name == "128cube_100" && m != gv::shape_method::distance_ratio) continue;
      const std::string id = std::string("shape/") + method_name(m) + "/" + backend + "/" + name;
      auto b = benchmark::RegisterBenchmark(id.c_str(), [policy, name, m](benchmark::State& st) {
        auto c = make_case(name);
        if (name == "steak")
          run_case<gv::min_stiffness>(st, policy, c, m);
        else
          run_case<gv::uniform>(st, policy, c, m);
      });
      b->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
    }
}

}  // namespace gvbench_shape

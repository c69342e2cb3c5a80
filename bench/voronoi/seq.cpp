/// @file bench/voronoi/seq.cpp
/// @brief The sequential backend (geovoronoi::seq) over the full voronoi case matrix:
///        n = 64, 128, 256; 10, 100, 1000 seeds; 6- and 26-connectivity; constant, gradient, steak;
///        plus the MRI-like pelvis (`voronoi/seq/mri/221/20/26`: 221x271x69, 0.9x0.9x2.5, 20 seeds).

#include "common.hpp"

GEOVORONOI_BENCH_REGISTER(register_seq_cases) {
  geovoronoi::bench::register_voronoi_cases("seq", geovoronoi::seq, {64, 128, 256}, {10, 100, 1000}, {6, 26},
                                            geovoronoi::bench::field_names());
  geovoronoi::bench::register_voronoi_cases("seq", geovoronoi::seq, {221}, {20}, {26}, {"mri"});
}

#ifndef GEOVORONOI_BENCH_COMBINED
GEOVORONOI_BENCH_MAIN()
#endif

// ---- incremental update after a cut (issue 13) ----------------------------------------------------
// The demo's problem: the steak phantom 128x96x32 (1 mm voxels), its 12 nodes on the mid slice,
// 26-connected, min_stiffness. `voronoi/seq/steak128` is the full solve (with parents) of the problem
// after the cut; `update/seq/steak128/cut20` updates the diagram before the cut (with parents) in
// place after a planar 20 x 20 mm blade beside the bone's stem (the plane x = 70.5 mm, y 60..80,
// z 6..26). Each iteration restores the diagram before the cut outside the timed region.
#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/update.hpp>

namespace {
namespace gvb = geovoronoi;

struct steak_cut_case {
  gvb::image<float, 3> field;
  std::vector<gvb::coord<3>> seeds;
  gvb::cut_set<3> blade;
  gvb::cut_table table;
  steak_cut_case() {
    const gvb::grid<3> g({128, 96, 32}, {1.0, 1.0, 1.0});
    field = gvb::phantom::steak(g);
    auto plane = field;
    for (gvb::index_t v = 0; v < g.size(); ++v)
      if (g.coords(v)[2] != g.extent(2) / 2) plane[v] = 0.0f;
    seeds = gvb::phantom::spread_seeds(plane, 12);
    gvb::triangle_mesh m;
    m.vertices = {{70.5, 60, 6}, {70.5, 80, 6}, {70.5, 80, 26}, {70.5, 60, 26}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    blade = gvb::cut_from_mesh(g, gvb::connectivity<26>{}, m);
    table = gvb::cut_table(blade);
  }
  static const steak_cut_case& get() {
    static const steak_cut_case c;
    return c;
  }
};

void bench_full_steak128(benchmark::State& state) {
  const auto& c = steak_cut_case::get();
  const auto p = gvb::make_problem(c.field.geometry(), c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto after = gvb::with_cuts(p, c.table);
  for (auto _ : state) {
    auto d = gvb::voronoi(gvb::seq, after, c.seeds, gvb::solve_options{true});
    benchmark::DoNotOptimize(d);
  }
}

void bench_update_steak128_cut20(benchmark::State& state) {
  const auto& c = steak_cut_case::get();
  const auto p = gvb::make_problem(c.field.geometry(), c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto after = gvb::with_cuts(p, c.table);
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  auto d = before;
  gvb::update_stats s;
  for (auto _ : state) {
    state.PauseTiming();
    d.distance = before.distance;
    d.label = before.label;
    d.parent = before.parent;
    state.ResumeTiming();
    s = gvb::update_in_place(gvb::seq, after, d, c.blade);
    benchmark::DoNotOptimize(d);
  }
  state.counters["cut_edges"] = double(c.blade.size());
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["boundary"] = double(s.boundary);
}
// `update/seq/steak128/carve8`: the 8^3 voxels x 66..73, y 62..69, z 12..19 (beside the bone's stem)
// leave the domain (stiffness 0); same restore-outside-the-timer scheme.
void bench_update_steak128_carve8(benchmark::State& state) {
  const auto& c = steak_cut_case::get();
  const auto& g = c.field.geometry();
  const auto p = gvb::make_problem(g, c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  auto carved_field = c.field;
  gvb::carving carve;
  for (gvb::index_t z = 12; z < 20; ++z)
    for (gvb::index_t y = 62; y < 70; ++y)
      for (gvb::index_t x = 66; x < 74; ++x) {
        carve.voxels.push_back(g.index({x, y, z}));
        carved_field[carve.voxels.back()] = 0.0f;
      }
  const auto after = gvb::make_problem(g, carved_field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  auto d = before;
  gvb::update_stats s;
  for (auto _ : state) {
    state.PauseTiming();
    d.distance = before.distance;
    d.label = before.label;
    d.parent = before.parent;
    state.ResumeTiming();
    s = gvb::update_in_place(gvb::seq, after, d, carve);
    benchmark::DoNotOptimize(d);
  }
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["boundary"] = double(s.boundary);
}
}  // namespace

GEOVORONOI_BENCH_REGISTER(register_update_cases) {
  benchmark::RegisterBenchmark("update/seq/steak128/carve8", bench_update_steak128_carve8)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Apply(geovoronoi::bench::min_time_1s);
  benchmark::RegisterBenchmark("voronoi/seq/steak128", bench_full_steak128)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Apply(geovoronoi::bench::min_time_1s);
  benchmark::RegisterBenchmark("update/seq/steak128/cut20", bench_update_steak128_cut20)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Apply(geovoronoi::bench::min_time_1s);
}

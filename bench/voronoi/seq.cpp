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

// ---- incremental update after a cut ---------------------------------------------------------------
// The demo's problem: the steak phantom 128x96x32 (1 mm voxels), its 12 nodes on the mid slice,
// 26-connected, min_stiffness. `voronoi/seq/steak128` is the full solve (with parents) of the problem
// after the cut; `update/seq/steak128/cut20` updates the diagram before the cut (with parents) in
// place after a planar 20 x 20 mm blade beside the bone's stem (the plane x = 70.5 mm, y 60..80,
// z 6..26). Each iteration restores the diagram before the cut outside the timed region.
// bench_voronoi_thrust, which links this file, registers every case on thrust_omp as well
// (`voronoi/thrust_omp/steak128`, `update/thrust_omp/steak128/<edit>`).
#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/update.hpp>
#if defined(GEOVORONOI_BENCH_THRUST_OMP)  // bench_voronoi_thrust links this file: its update cases too
#include <geovoronoi/backend/thrust.hpp>
#include <thrust/system/omp/execution_policy.h>
#endif

namespace {
namespace gvb = geovoronoi;

/// Writes one byte per cache line of a 64 MiB buffer (twice the 32 MiB L3 of the development VM):
/// afterwards nothing the next timed step reads is in any cache level. For the `_cold` cases.
void evict_caches() {
  static std::vector<unsigned char> buffer(std::size_t(64) << 20);
  for (std::size_t i = 0; i < buffer.size(); i += 64) buffer[i] = static_cast<unsigned char>(buffer[i] + 1);
  benchmark::DoNotOptimize(buffer.data());
  benchmark::ClobberMemory();
}

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

template <class Policy>
void bench_full_steak128(benchmark::State& state, const Policy& pol, bool cold) {
  const auto& c = steak_cut_case::get();
  const auto p = gvb::make_problem(c.field.geometry(), c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto after = gvb::with_cuts(p, c.table);
  for (auto _ : state) {
    if (cold) {
      state.PauseTiming();
      evict_caches();
      state.ResumeTiming();
    }
    auto d = gvb::voronoi(pol, after, c.seeds, gvb::solve_options{true});
    benchmark::DoNotOptimize(d);
  }
}

/// Times update_in_place(pol, after, d, change) on a copy of @p before that is restored outside the
/// timer before every iteration; returns the last iteration's statistics. @p cold: the caches are
/// also emptied (evict_caches) after the restore, outside the timer. Warm, the bench repeats the same
/// update on a region that the previous iteration left in L2; cold is the other bound (an
/// application that ran other work between two edits lies in between).
template <class Policy, class P, class Change>
gvb::update_stats time_updates(benchmark::State& state, const Policy& pol, const P& after,
                               const gvb::diagram<float, 3>& before, const Change& change, bool cold = false) {
  auto d = before;
  gvb::update_stats s;
  for (auto _ : state) {
    state.PauseTiming();
    d.distance = before.distance;
    d.label = before.label;
    d.parent = before.parent;
    d.seeds = before.seeds;
    if (cold) evict_caches();
    state.ResumeTiming();
    s = gvb::update_in_place(pol, after, d, change);
    benchmark::DoNotOptimize(d);
  }
  return s;
}

template <class Policy>
void bench_update_steak128_cut20(benchmark::State& state, const Policy& pol, bool cold) {
  const auto& c = steak_cut_case::get();
  const auto p = gvb::make_problem(c.field.geometry(), c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto after = gvb::with_cuts(p, c.table);
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  const auto s = time_updates(state, pol, after, before, c.blade, cold);
  state.counters["cut_edges"] = double(c.blade.size());
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["boundary"] = double(s.boundary);
}
// `update/seq/steak128/carve8`: the 8^3 voxels x 66..73, y 62..69, z 12..19 (beside the bone's stem)
// leave the domain (stiffness 0); same restore-outside-the-timer scheme.
template <class Policy>
void bench_update_steak128_carve8(benchmark::State& state, const Policy& pol) {
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
  const auto s = time_updates(state, pol, after, before, carve);
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["boundary"] = double(s.boundary);
}

// `update/seq/steak128/stiffen8` and `soften8`: the field of the same 8^3 voxels doubled (stiffer) or
// halved (softer); restiffened voxels, same restore scheme.
template <class Policy>
void bench_update_steak128_restiffen8(benchmark::State& state, const Policy& pol, float factor) {
  const auto& c = steak_cut_case::get();
  const auto& g = c.field.geometry();
  const auto p = gvb::make_problem(g, c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  auto edited = c.field;
  gvb::change<3> ch;
  for (gvb::index_t z = 12; z < 20; ++z)
    for (gvb::index_t y = 62; y < 70; ++y)
      for (gvb::index_t x = 66; x < 74; ++x) {
        const auto v = g.index({x, y, z});
        ch.restiffened.push_back(v);
        edited[v] *= factor;
      }
  const auto after = gvb::make_problem(g, edited, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto s = time_updates(state, pol, after, before, ch);
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["lowered"] = double(s.lowered);
  state.counters["settled"] = double(s.settled);
}

// `update/seq/steak128/add_node`: a 13th node appended at (40, 30, 8); `move_node`: the node whose
// cell has the median size (the 6th smallest of 12) moves by (+3, +2, 0) voxels; `move_node_largest`:
// the node with the largest cell (about 40 % of the domain) does. A move re-solves the moved node's
// whole cell, so its cost is proportional to that cell. The diagram (and its node list) is restored
// outside the timer.
template <class Policy>
void bench_update_steak128_nodes(benchmark::State& state, const Policy& pol, int move, bool cold = false) {
  const auto& c = steak_cut_case::get();
  const auto& g = c.field.geometry();
  const auto p = gvb::make_problem(g, c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  gvb::change<3> ch;
  if (move) {
    std::vector<std::pair<gvb::index_t, std::size_t>> cells(c.seeds.size());
    for (std::size_t i = 0; i < cells.size(); ++i) cells[i] = {0, i};
    for (gvb::index_t v = 0; v < g.size(); ++v)
      if (before.label[v] >= 0) ++cells[std::size_t(before.label[v])].first;
    std::sort(cells.begin(), cells.end());
    const std::size_t which = move == 1 ? cells[cells.size() / 2 - 1].second : cells.back().second;
    state.counters["node"] = double(which);
    state.counters["cell"] = double(move == 1 ? cells[cells.size() / 2 - 1].first : cells.back().first);
    auto to = c.seeds[which];
    to[0] += 3, to[1] += 2;
    while (!(c.field[g.index(to)] > 0.0f)) --to[0];
    ch.nodes = {gvb::node_edit<3>::move(which, to)};
  } else {
    gvb::coord<3> at{40, 30, 8};  // inside the steak (meat); the first inside voxel along x otherwise
    while (!(c.field[g.index(at)] > 0.0f)) ++at[0];
    ch.nodes = {gvb::node_edit<3>::add(at)};
  }
  const auto s = time_updates(state, pol, p, before, ch, cold);
  state.counters["invalidated"] = double(s.invalidated);
  state.counters["lowered"] = double(s.lowered);
  state.counters["settled"] = double(s.settled);
}

// `update/seq/steak128/sweep`: a vertical blade (z 6..26 mm) sweeps 30 mm along y in 10 steps (3 mm
// and 0.8 mm along x each); every step cuts the strip swept since the previous position and updates
// the diagram. One iteration is one step (the diagram goes back to the uncut one before step 0,
// outside the timer), so the time is per update. `sweep_with_cut` also times, per step, building the
// strip's cut set (cut_from_blade_sweep), merging it and building the table of all cuts so far.
struct sweep_case {
  static constexpr int steps = 10;
  std::vector<std::vector<gvb::point<3>>> positions;
  std::vector<gvb::cut_set<3>> strip;
  std::vector<gvb::cut_table> table;  // every cut up to and including step t
  sweep_case() {
    const auto& c = steak_cut_case::get();
    const auto& g = c.field.geometry();
    for (int t = 0; t <= steps; ++t)
      positions.push_back({{66.5 + 0.8 * t, 50.0 + 3.0 * t, 6.0}, {66.5 + 0.8 * t, 50.0 + 3.0 * t, 26.0}});
    gvb::cut_set<3> all(g, gvb::connectivity<26>{});
    for (int t = 0; t < steps; ++t) {
      strip.push_back(gvb::cut_from_blade_sweep(g, gvb::connectivity<26>{}, {positions[t], positions[t + 1]}));
      all.merge(strip.back());
      table.emplace_back(all);
    }
  }
  static const sweep_case& get() {
    static const sweep_case s;
    return s;
  }
};

template <class Policy>
void bench_update_steak128_sweep(benchmark::State& state, const Policy& pol, bool with_cut) {
  const auto& c = steak_cut_case::get();
  const auto& sw = sweep_case::get();
  const auto& g = c.field.geometry();
  const auto p = gvb::make_problem(g, c.field, gvb::min_stiffness{}, gvb::connectivity<26>{});
  const auto before = gvb::voronoi(gvb::seq, p, c.seeds, gvb::solve_options{true});
  auto d = before;
  gvb::cut_set<3> all(g, gvb::connectivity<26>{});
  std::size_t t = 0, invalidated = 0, updates = 0;
  for (auto _ : state) {
    if (t % sweep_case::steps == 0) {
      state.PauseTiming();
      d.distance = before.distance;
      d.label = before.label;
      d.parent = before.parent;
      all = gvb::cut_set<3>(g, gvb::connectivity<26>{});
      state.ResumeTiming();
    }
    const int step = int(t % sweep_case::steps);
    if (with_cut) {
      auto piece = gvb::cut_from_blade_sweep(g, gvb::connectivity<26>{}, {sw.positions[step], sw.positions[step + 1]});
      all.merge(piece);
      const gvb::cut_table table(all);
      invalidated += gvb::update_in_place(pol, gvb::with_cuts(p, table), d, piece).invalidated;
    } else {
      invalidated += gvb::update_in_place(pol, gvb::with_cuts(p, sw.table[step]), d, sw.strip[step]).invalidated;
    }
    benchmark::DoNotOptimize(d);
    ++t, ++updates;
  }
  state.counters["updates_per_s"] = benchmark::Counter(double(updates), benchmark::Counter::kIsRate);
  state.counters["invalidated_per_step"] = double(invalidated) / double(updates);
}

/// Registers `voronoi/<backend>/steak128[_cold]` and `update/<backend>/steak128/<edit>[_cold]` for one
/// backend policy. The update is the same host algorithm on every backend (docs/cuts.md); the full
/// solve is the backend's own, so the ratios say what an update saves on that backend.
template <class Policy>
void register_update_family(const std::string& backend, const Policy& pol) {
  // every case in milliseconds of wall time, at least a second of iterations
  auto add = [](const std::string& name, auto fn) {
    benchmark::RegisterBenchmark(name.c_str(), fn)
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Apply(geovoronoi::bench::min_time_1s);
  };
  const std::string full = "voronoi/" + backend + "/steak128", upd = "update/" + backend + "/steak128/";
  add(upd + "carve8", [pol](benchmark::State& s) { bench_update_steak128_carve8(s, pol); });
  add(full, [pol](benchmark::State& s) { bench_full_steak128(s, pol, false); });
  add(upd + "cut20", [pol](benchmark::State& s) { bench_update_steak128_cut20(s, pol, false); });
  // the cold variants empty every cache before each timed step (evict_caches)
  add(full + "_cold", [pol](benchmark::State& s) { bench_full_steak128(s, pol, true); });
  add(upd + "cut20_cold", [pol](benchmark::State& s) { bench_update_steak128_cut20(s, pol, true); });
  add(upd + "add_node_cold", [pol](benchmark::State& s) { bench_update_steak128_nodes(s, pol, 0, true); });
  add(upd + "stiffen8", [pol](benchmark::State& s) { bench_update_steak128_restiffen8(s, pol, 2.0f); });
  add(upd + "soften8", [pol](benchmark::State& s) { bench_update_steak128_restiffen8(s, pol, 0.5f); });
  add(upd + "add_node", [pol](benchmark::State& s) { bench_update_steak128_nodes(s, pol, 0); });
  add(upd + "move_node", [pol](benchmark::State& s) { bench_update_steak128_nodes(s, pol, 1); });
  add(upd + "move_node_largest", [pol](benchmark::State& s) { bench_update_steak128_nodes(s, pol, 2); });
  add(upd + "sweep", [pol](benchmark::State& s) { bench_update_steak128_sweep(s, pol, false); });
  add(upd + "sweep_with_cut", [pol](benchmark::State& s) { bench_update_steak128_sweep(s, pol, true); });
}
}  // namespace

GEOVORONOI_BENCH_REGISTER(register_update_cases) {
  register_update_family("seq", gvb::seq);
#if defined(GEOVORONOI_BENCH_THRUST_OMP)
  register_update_family("thrust_omp", gvb::thrust::par_on(::thrust::omp::par));
#endif
}

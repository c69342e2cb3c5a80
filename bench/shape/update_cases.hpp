// Shape functions after a change (shape_update.hpp), written once; each backend's file
// registers them with its policy. Names: shape_update/<method>/<backend>/steak128/<edit>, and
// shape_update/distance_ratio_kept/... for Distance Ratio computed with keep_update_state (the update
// repairs the kept searches; its baseline full_cpu_s is still the plain computation, and
// full_kept_cpu_s the one that keeps them).
//
// The problem is exactly `shape/<method>/<backend>/steak128` (cases.hpp: the 128x96x32 steak, its 12
// spread nodes, min_stiffness, 26-connected); the edits are those of bench/voronoi/seq.cpp:
//   cut20     the planar 20 x 20 mm blade x = 70.5, y 60..80, z 6..26 (cut_from_mesh)
//   carve8    the 8^3 voxels x 66..73, y 62..69, z 12..19 leave the domain
//   add_node  a 13th node appended at (40, 30, 8) (the first inside voxel along +x from there)
// Setup, outside the timer: the diagram before (with parents), the diagram after (update()), and the
// weights before (shape_functions(), once per method and process, cached: Sibson takes minutes). Its
// CPU time is the counter full_cpu_s, the baseline measured in the same process: the same
// computation as `shape/<method>/<backend>/steak128`. One iteration = one
// update_shape_functions_in_place() on a copy of the weights before, restored outside the timer.
// Counters: rows, recomputed, fraction (recomputed / rows), changed rows, changed_voxels (X),
// region_voxels (R),
// nodes_affected (Distance Ratio), full_cpu_s and speedup_cpu = full_cpu_s / CPU time of one update.
// GEOVORONOI_BENCH_VERIFY=1 also computes the weights after from scratch (as long again) and sets
// the counter verified to 1 when they equal the update bit for bit (0 otherwise).
#pragma once
#include "cases.hpp"

#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/shape_functions.hpp>
#include <geovoronoi/shape_update.hpp>
#include <geovoronoi/update.hpp>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <ctime>
#include <map>
#include <stdexcept>
#include <utility>

namespace gvbench_shape {

/// CPU time of the process (every thread), in seconds.
inline double cpu_seconds() { return double(std::clock()) / double(CLOCKS_PER_SEC); }

struct steak_edit {
  gv::image<float, 3> field;  // after the edit
  gv::change<3> change;
  bool cut = false;
  gv::cut_table table;  // the blade, when cut
};

inline steak_edit make_steak_edit(const volume& c, const std::string& edit) {
  const auto& g = c.g;
  steak_edit e{c.field, {}, false, {}};
  if (edit == "cut20") {
    gv::triangle_mesh m;
    m.vertices = {{70.5, 60, 6}, {70.5, 80, 6}, {70.5, 80, 26}, {70.5, 60, 26}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    e.change.cut = gv::cut_from_mesh(g, gv::connectivity<26>{}, m);
    e.table = gv::cut_table(*e.change.cut);
    e.cut = true;
  } else if (edit == "carve8") {
    for (gv::index_t z = 12; z < 20; ++z)
      for (gv::index_t y = 62; y < 70; ++y)
        for (gv::index_t x = 66; x < 74; ++x) {
          const auto v = g.index({x, y, z});
          for (const auto& s : c.nodes)
            if (g.index(s) == v) throw std::logic_error("shape_update bench: carve8 would remove a node");
          if (!(e.field[v] > 0.0f)) continue;
          e.change.carved.push_back(v);
          e.field[v] = 0.0f;
        }
  } else if (edit == "add_node") {
    gv::coord<3> at{40, 30, 8};
    while (!(c.field[g.index(at)] > 0.0f)) ++at[0];
    e.change.nodes = {gv::node_edit<3>::add(at)};
  } else {
    throw std::invalid_argument("shape_update bench: unknown edit " + edit);
  }
  return e;
}

/// The weights before the edit, computed once per method in this process, and the CPU seconds that took.
template <class Policy>
const std::pair<gv::shape_weights<float, 3>, double>& weights_before(Policy policy, const volume& c,
                                                                    const gv::diagram<float, 3>& d, gv::shape_method m,
                                                                    bool kept = false) {
  static std::map<int, std::pair<gv::shape_weights<float, 3>, double>> cache;
  const int key = int(m) + (kept ? 16 : 0);
  const auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  const auto p = gv::make_problem(c.g, c.field, gv::min_stiffness{}, gv::connectivity<26>{});
  gv::shape_options o;
  o.method = m;
  o.keep_update_state = kept;
  const double t0 = cpu_seconds();
  auto w = gv::shape_functions(policy, p, d, o);
  const double t = cpu_seconds() - t0;
  return cache.emplace(key, std::make_pair(std::move(w), t)).first->second;
}

template <class Policy>
void run_update_case(benchmark::State& state, Policy policy, gv::shape_method m, const std::string& edit,
                     bool kept = false) {
  static const auto c = make_case("steak128");
  const auto p = gv::make_problem(c->g, c->field, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto before = gv::voronoi(gv::seq, p, c->nodes, gv::solve_options{true});
  const auto e = make_steak_edit(*c, edit);
  // the baseline is always the plain computation (what recomputing all weights costs)
  const double full_cpu = weights_before(policy, *c, before, m).second;
  const auto& cached = weights_before(policy, *c, before, m, kept);
  const auto& w0 = cached.first;
  if (kept) state.counters["full_kept_cpu_s"] = cached.second;
  gv::shape_options o;
  o.method = m;
  o.keep_update_state = kept;
  auto measure = [&](const auto& after) {
    const auto d_after = gv::update(gv::seq, after, before, e.change);
    auto w = w0;
    gv::shape_update_stats s;
    double cpu = 0;
    std::size_t n = 0;
    for (auto _ : state) {
      state.PauseTiming();
      std::copy(w0.node.begin(), w0.node.end(), w.node.begin());
      std::copy(w0.weight.begin(), w0.weight.end(), w.weight.begin());
      w.nodes = w0.nodes;
      w.update_state = w0.update_state;
      state.ResumeTiming();
      const double t0 = cpu_seconds();
      s = gv::update_shape_functions_in_place(policy, after, before, d_after, w, e.change, o);
      cpu += cpu_seconds() - t0;
      ++n;
      benchmark::DoNotOptimize(w.weight.data());
    }
    state.counters["rows"] = double(s.rows);
    state.counters["recomputed"] = double(s.recomputed);
    state.counters["fraction"] = s.rows ? double(s.recomputed) / double(s.rows) : 0.0;
    state.counters["changed"] = double(s.changed);
    state.counters["changed_voxels"] = double(s.changed_voxels);
    state.counters["region_voxels"] = double(s.region_voxels);
    state.counters["nodes_affected"] = double(s.nodes_affected);
    state.counters["full"] = s.full ? 1.0 : 0.0;
    state.counters["full_cpu_s"] = full_cpu;
    state.counters["speedup_cpu"] = n && cpu > 0 ? full_cpu / (cpu / double(n)) : 0.0;
    if (const char* v = std::getenv("GEOVORONOI_BENCH_VERIFY"); v && std::strcmp(v, "0") != 0) {
      const double t0 = cpu_seconds();
      const auto full = gv::shape_functions(policy, after, d_after, o);
      state.counters["full_after_cpu_s"] = cpu_seconds() - t0;
      bool same = full.nodes == w.nodes && full.node == w.node && full.weight.size() == w.weight.size();
      for (std::size_t i = 0; same && i < full.weight.size(); ++i)
        same = std::memcmp(&full.weight[i], &w.weight[i], sizeof(float)) == 0;
      state.counters["verified"] = same ? 1.0 : 0.0;
      if (!same) state.SkipWithError("the updated weights differ from a full computation");
    }
  };
  if (e.cut) {
    measure(gv::with_cuts(p, e.table));
  } else {
    const auto after = gv::make_problem(c->g, e.field, gv::min_stiffness{}, gv::connectivity<26>{});
    measure(after);
  }
}

/**
 * shape_update_at/<method>/<backend>/mri/221/20/26/points1000/cut20: the rows at the 1000 points of
 * `shape/<method>/<backend>/mri/221/20/26/points1000` (cases.hpp) updated after a 20 x 20 mm planar
 * blade (x = 99.45 mm, between voxel columns 110 and 111; y 112..132 mm, z 76..96 mm) by
 * update_shape_functions_at_in_place(). Setup, outside the timer: the diagram before (with parents) and
 * after (update()), the rows before (shape_functions_at()); after the timed loop the updated rows must
 * equal shape_functions_at() on the problem after the cut bit for bit (else the case fails). Counters
 * as the steak cases (rows, recomputed, region_voxels, ...), at_after_s: the wall seconds of that
 * shape_functions_at() after the cut.
 */
template <class Policy>
void run_update_at_case(benchmark::State& state, Policy policy, gv::shape_method m) {
  const auto c = make_case("mri/221/20/26/points1000");
  const auto p = gv::make_problem(c->g, c->field, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto before = gv::voronoi(gv::seq, p, c->nodes, gv::solve_options{true});
  gv::triangle_mesh blade;
  blade.vertices = {{99.45, 112, 76}, {99.45, 132, 76}, {99.45, 132, 96}, {99.45, 112, 96}};
  blade.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto cuts = gv::cut_from_mesh(c->g, gv::connectivity<26>{}, blade);
  const gv::cut_table table(cuts);
  const auto after = gv::with_cuts(p, table);
  gv::change<3> chg;
  chg.cut = cuts;
  const auto d_after = gv::update(gv::seq, after, before, chg);
  gv::shape_options o;
  o.method = m;
  const auto w0 = gv::shape_functions_at(policy, p, before, c->points, o);
  auto w = w0;
  gv::shape_update_stats s;
  for (auto _ : state) {
    state.PauseTiming();
    w = w0;
    state.ResumeTiming();
    s = gv::update_shape_functions_at_in_place(policy, after, before, d_after, w, chg, o);
    benchmark::DoNotOptimize(w.weight.data());
  }
  const auto t0 = std::chrono::steady_clock::now();
  const auto full = gv::shape_functions_at(policy, after, d_after, c->points, o);
  state.counters["at_after_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  bool same = full.node == w.node && full.weight.size() == w.weight.size();
  for (std::size_t i = 0; same && i < full.weight.size(); ++i)
    same = std::memcmp(&full.weight[i], &w.weight[i], sizeof(float)) == 0;
  if (!same) throw std::logic_error("shape_update_at bench: the updated rows differ from shape_functions_at after the cut");
  state.counters["rows"] = double(s.rows);
  state.counters["recomputed"] = double(s.recomputed);
  state.counters["changed"] = double(s.changed);
  state.counters["changed_voxels"] = double(s.changed_voxels);
  state.counters["region_voxels"] = double(s.region_voxels);
  state.counters["nodes_affected"] = double(s.nodes_affected);
  state.counters["full"] = s.full ? 1.0 : 0.0;
}

/// Registers shape_update/<method>/<backend>/steak128/<edit>; none in smoke mode (the weights before
/// alone take seconds to minutes).
template <class Policy>
void register_update_cases(Policy policy, const std::string& backend) {
  if (std::getenv("GEOVORONOI_BENCH_SMOKE") != nullptr) return;
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace})
    for (const bool kept : {false, true})
      for (const std::string edit : {"cut20", "carve8", "add_node"}) {
        if (kept && m != gv::shape_method::distance_ratio) continue;
        const std::string id = std::string("shape_update/") + method_name(m) + (kept ? "_kept" : "") + "/" + backend +
                               "/steak128/" + edit;
        auto b = benchmark::RegisterBenchmark(id.c_str(), [policy, m, edit, kept](benchmark::State& st) {
          run_update_case(st, policy, m, edit, kept);
        });
        b->Unit(benchmark::kMillisecond)->UseRealTime();
        // Distance Ratio updates take milliseconds: repeat; Sibson and Laplace: one shot
        if (m == gv::shape_method::distance_ratio)
          b->MinTime(1.0);
        else
          b->Iterations(1);
      }
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    const std::string id =
        std::string("shape_update_at/") + method_name(m) + "/" + backend + "/mri/221/20/26/points1000/cut20";
    auto b = benchmark::RegisterBenchmark(id.c_str(), [policy, m](benchmark::State& st) { run_update_at_case(st, policy, m); });
    b->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(1);
  }
}

}  // namespace gvbench_shape

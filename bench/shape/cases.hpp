// The shape-function benchmark cases, written once; each backend's file registers them with its
// policy. Names: shape/<method>/<backend>/<case>.
//   table1       100x40x20 voxels, constant field, 20 nodes (phantom::spread_seeds), uniform metric,
//                26-connected, weights for all 80,000 voxels (Toss et al. 2016, Table 1 setting)
//   128cube_100  128^3 voxels, constant field, 100 nodes, uniform metric, 26-connected (Distance Ratio)
//   steak128     128x96x32 steak phantom (the demo's), 12 nodes, min_stiffness metric, 26-connected
//   steak64      the same phantom at 64x48x16 (quick guide for the steak128 figures)
//   beam         20x20x100 two-material bar (phantom::two_material_beam), 5 nodes, min_stiffness, 26
//   at1000       shape_functions_at on steak128 at 1000 random inside voxels (phantom::random_seeds)
//   mri/221/20/26           the MRI-like pelvis (phantom::mri_like on phantom::mri_like_grid(221):
//                221x271x69 voxels of 0.9x0.9x2.5 mm), 20 nodes (phantom::random_seeds, salt 2016, as
//                voronoi/*/mri/221/20/26), min_stiffness, 26-connected: Distance Ratio at every voxel;
//                after the timed loop the rows at the 1000 points of points1000 are computed by
//                shape_functions_at and must equal the full rows bit for bit (else the case fails)
//   mri/221/20/26/points1000  shape_functions_at on the same problem at 1000 random inside voxels
//                (phantom::random_seeds, salt 2026)
//   mri/221/20/26/block  Sibson and Laplace: shape_functions_at on the inside voxels of a 32x32x8 block
//                at the grid's centre, in voxel order: the queries the whole grid's run makes (lane
//                searches of neighbouring voxels); counter full_volume_s extrapolates the time per
//                point to every inside voxel (what shape_functions() would take)
// The diagram is computed once outside the timed region; one iteration = one shape_functions() call.
// Counters: peak_rss_MB is the process's peak resident set so far (run one case per process for its
// own figure); scratch_MB and visits_per_query come from shape_options::stats.
#pragma once
#include <benchmark/benchmark.h>
#include <geovoronoi.hpp>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <sys/resource.h>

#include <memory>
#include <string>
#include <vector>

namespace gvbench_shape {
namespace gv = geovoronoi;

inline const char* method_name(gv::shape_method m) {
  return m == gv::shape_method::sibson ? "sibson" : m == gv::shape_method::laplace ? "laplace" : "distance_ratio";
}

inline double peak_rss_mb() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return double(u.ru_maxrss) / 1024.0;
}

/**
 * The sequential backend without its opt-in to fused host queries: Sibson and Laplace then take the
 * path that materialises every cell through insert_queries and re-reads it (the code before the fused
 * search), so one benchmark run can compare the two.
 */
struct materialise_seq_t {
  using backend_policy_tag = void;  // a backend policy (policy.hpp) that forwards to seq
};
template <class P, class S, class O>
auto backend_solve(materialise_seq_t, const P& p, const S& s, const O& o) {
  return backend_solve(gv::seq, p, s, o);
}
template <class P, class S, class R>
auto backend_bounded(materialise_seq_t, const P& p, const S& s, R radius) {
  return backend_bounded(gv::seq, p, s, radius);
}
template <class P, class D>
auto backend_insert_queries(materialise_seq_t, const P& p, const D& d, const std::vector<gv::index_t>& q) {
  return backend_insert_queries(gv::seq, p, d, q);
}

struct volume {
  gv::grid<3> g;
  gv::image<float, 3> field;
  std::vector<gv::coord<3>> nodes;
  std::vector<gv::coord<3>> points;  // at1000, mri points1000 only
  /// mri full volume: the points whose rows are checked against the full rows after the timed loop
  std::vector<gv::coord<3>> check_points;
};

/// The MRI-like case (`mri/221/20/26`, with @p points: `.../points1000`), built once per process.
inline std::shared_ptr<volume> make_mri_case(bool points, bool block = false) {
  static const auto base = [] {
    const gv::grid<3> g = gv::phantom::mri_like_grid(221);
    auto f = gv::phantom::mri_like(g);
    auto s = gv::phantom::random_seeds(f, 20, 2016);
    auto pts = gv::phantom::random_seeds(f, 1000, 2026);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s), {}, std::move(pts)});
  }();
  auto c = std::make_shared<volume>(*base);
  if (points) c->points = c->check_points, c->check_points.clear();
  if (block) {
    c->check_points.clear();
    const auto n = c->g.extents();
    for (gv::index_t z = n[2] / 2 - 4; z < n[2] / 2 + 4; ++z)
      for (gv::index_t y = n[1] / 2 - 16; y < n[1] / 2 + 16; ++y)
        for (gv::index_t x = n[0] / 2 - 16; x < n[0] / 2 + 16; ++x)
          if (c->field[c->g.index({x, y, z})] > 0) c->points.push_back({x, y, z});
  }
  return c;
}

inline std::shared_ptr<volume> make_case(const std::string& name) {
  if (name == "mri/221/20/26/block") return make_mri_case(false, true);
  if (name == "mri/221/20/26" || name == "mri/221/20/26/points1000") return make_mri_case(name != "mri/221/20/26");
  if (name == "table1") {
    const gv::grid<3> g({100, 40, 20});
    auto f = gv::phantom::constant(g);
    auto s = gv::phantom::spread_seeds(f, 20);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s), {}, {}});
  }
  if (name == "128cube_100") {
    const gv::grid<3> g({128, 128, 128});
    auto f = gv::phantom::constant(g);
    auto s = gv::phantom::spread_seeds(f, 100);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s), {}, {}});
  }
  if (name == "beam") {
    const gv::grid<3> g({20, 20, 100});
    auto f = gv::phantom::two_material_beam(g);
    auto s = gv::phantom::spread_seeds(f, 5);
    return std::make_shared<volume>(volume{g, std::move(f), std::move(s), {}, {}});
  }
  const gv::grid<3> g = name == "steak64" ? gv::grid<3>({64, 48, 16}) : gv::grid<3>({128, 96, 32});
  auto f = gv::phantom::steak(g);
  auto s = gv::phantom::spread_seeds(f, 12);
  std::vector<gv::coord<3>> pts;
  if (name == "at1000") pts = gv::phantom::random_seeds(f, 1000, 2026);
  return std::make_shared<volume>(volume{g, std::move(f), std::move(s), std::move(pts), {}});
}

template <class Metric, class Policy>
void run_case(benchmark::State& state, Policy policy, std::shared_ptr<volume> c, gv::shape_method m, bool reuse,
              bool filter) {
  const auto p = gv::make_problem(c->g, c->field, Metric{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, p, c->nodes);
  gv::index_t reached = 0;
  for (gv::index_t v = 0; v < c->g.size(); ++v) reached += d.label[v] != gv::no_label;
  gv::shape_options o;
  o.method = m;
  o.reuse_constant_regions = reuse;
  o.skip_single_owner_rows = filter;
  gv::shape_stats stats;
  o.stats = &stats;
  gv::shape_weights<float, 3> last;
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    if (c->points.empty()) {
      auto w = gv::shape_functions(policy, p, d, o);
      benchmark::DoNotOptimize(w.weight.data());
      if (!c->check_points.empty()) last = std::move(w);
    } else {
      auto w = gv::shape_functions_at(policy, p, d, c->points, o);
      benchmark::DoNotOptimize(w.weight.data());
    }
  }
  if (!c->check_points.empty()) {  // rows at points: bit for bit the full rows at the same voxels
    gv::shape_options po = o;
    po.stats = nullptr;
    const auto at = gv::shape_functions_at(policy, p, d, c->check_points, po);
    const auto k = std::size_t(at.k);
    for (std::size_t i = 0; i < at.points; ++i)
      for (std::size_t s = 0; s < k; ++s) {
        const std::size_t a = i * k + s, f = std::size_t(at.voxel[i]) * k + s;
        if (at.node[a] != last.node[f] || std::memcmp(&at.weight[a], &last.weight[f], sizeof(float)) != 0)
          throw std::logic_error("shape bench: the row at point " + std::to_string(i) +
                                 " differs from the full computation's row");
      }
    state.counters["rows_checked"] = double(at.points);
  }
  if (!c->points.empty()) {  // the time per point, extrapolated to every inside voxel
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    gv::index_t inside = 0;
    for (gv::index_t v = 0; v < c->g.size(); ++v) inside += c->field[v] > 0;
    state.counters["full_volume_s"] = s / double(state.iterations()) / double(c->points.size()) * double(inside);
  }
  state.counters["nodes"] = double(c->nodes.size());
  state.counters["voxels"] = double(c->points.empty() ? reached : gv::index_t(c->points.size()));
  state.counters["peak_rss_MB"] = peak_rss_mb();
  state.counters["scratch_MB"] = double(stats.peak_scratch_bytes) / 1048576.0;
  state.counters["visits_per_query"] = stats.queries ? double(stats.voxels_visited) / double(stats.queries) : 0.0;
  state.counters["single_owner_rows"] = double(stats.single_owner_rows);
}

/// Registers every case for one backend (@p with_uniform: also the constant-field cases; @p reuse:
/// shape_options::reuse_constant_regions; @p filter: shape_options::skip_single_owner_rows).
template <class Policy>
void register_cases(Policy policy, const std::string& backend, bool with_uniform = true, bool reuse = true,
                    bool filter = true) {
  const auto methods = {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace};
  // smoke mode (GEOVORONOI_BENCH_SMOKE, see bench/common.hpp): the small Table 1 case only; the steak's
  // Sibson alone takes minutes
  const bool smoke = std::getenv("GEOVORONOI_BENCH_SMOKE") != nullptr;
  for (const std::string name : {"table1", "128cube_100", "beam", "steak64", "at1000", "steak128"})
    for (auto m : methods) {
      if (smoke && name != "table1") continue;
      if (name == "128cube_100" && m != gv::shape_method::distance_ratio) continue;
      if (!with_uniform && (name == "table1" || name == "128cube_100")) continue;
      const std::string id = std::string("shape/") + method_name(m) + "/" + backend + "/" + name;
      auto b = benchmark::RegisterBenchmark(id.c_str(), [policy, name, m, reuse, filter](benchmark::State& st) {
        auto c = make_case(name);
        if (name == "table1" || name == "128cube_100")
          run_case<gv::uniform>(st, policy, c, m, reuse, filter);
        else
          run_case<gv::min_stiffness>(st, policy, c, m, reuse, filter);
      });
      b->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
    }
  // the MRI-like volume: the plain configuration only (not the comparison variants), none in smoke mode
  if (smoke || !with_uniform || !reuse || !filter) return;
  for (const std::string name : {"mri/221/20/26/points1000", "mri/221/20/26", "mri/221/20/26/block"})
    for (auto m : methods) {
      if (name == "mri/221/20/26" && m != gv::shape_method::distance_ratio) continue;  // Sibson: hours
      if (name == "mri/221/20/26/block" && m == gv::shape_method::distance_ratio) continue;  // per node, not per point
      const std::string id = std::string("shape/") + method_name(m) + "/" + backend + "/" + name;
      auto b = benchmark::RegisterBenchmark(id.c_str(), [policy, name, m](benchmark::State& st) {
        run_case<gv::min_stiffness>(st, policy, make_case(name), m, true, true);
      });
      b->Unit(benchmark::kSecond)->UseRealTime()->Iterations(1);
    }
}

}  // namespace gvbench_shape

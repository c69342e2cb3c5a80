/// @file bench/voronoi/seq_sparse.cpp
/// @brief The sequential backend's sparse searches (insert-query and bounded solve) with their scratch
///        as a parameter: dense pages of 2^k voxels (`paged<2^k>`; the backend ships 64), plus the
///        dense solve of the same problem as a per-voxel reference.
///        Names: `sparse/<operation>/<scratch>/<case>`.
///
/// Cases (the shape-function benchmarks' settings, bench/shape/cases.hpp):
///   table1       100x40x20, constant field, 20 nodes (phantom::spread_seeds), uniform metric, 26-conn;
///                insert: a batch of 2000 queries, every k-th reached voxel
///   steak        128x96x32 steak phantom, 12 nodes, min_stiffness, 26-conn; insert as for table1
///   128cube_100  128^3 constant, 100 nodes, uniform, 26-conn; bounded: from 10 of the nodes (0, 10, ...
///                90) alone, radius 2x the largest distance in its cell (Distance Ratio's support)
/// Counters: `voxels_per_second` = cell voxels (insert), voxels reached (bounded) or voxels the
/// dense solve reaches (dense) per second of real time; `ns_per_voxel` its inverse.
/// `sparse/bounded_api/<seq|seq_ws>/...` and `sparse/insert_api/...` go through the front end, with a
/// fresh scratch per call or one seq_workspace for all calls.

#include "common.hpp"

#include <algorithm>
#include <memory>
#include <string>

namespace {
namespace gv = geovoronoi;
namespace eng = gv::detail::search;

struct sparse_case {
  gv::grid<3> g;
  gv::image<float, 3> field;
  std::vector<gv::coord<3>> nodes;
  bool stiffness = false;  // min_stiffness instead of uniform
};

const sparse_case& get_case(const std::string& name) {
  static std::map<std::string, std::unique_ptr<sparse_case>> cache;
  auto& slot = cache[name];
  if (!slot) {
    if (name == "table1") {
      const gv::grid<3> g({100, 40, 20});
      auto f = gv::phantom::constant(g);
      auto s = gv::phantom::spread_seeds(f, 20);
      slot.reset(new sparse_case{g, std::move(f), std::move(s), false});
    } else if (name == "steak") {
      const gv::grid<3> g({128, 96, 32});
      auto f = gv::phantom::steak(g);
      auto s = gv::phantom::spread_seeds(f, 12);
      slot.reset(new sparse_case{g, std::move(f), std::move(s), true});
    } else if (name == "128cube_100") {
      const gv::grid<3> g({128, 128, 128});
      auto f = gv::phantom::constant(g);
      auto s = gv::phantom::spread_seeds(f, 100);
      slot.reset(new sparse_case{g, std::move(f), std::move(s), false});
    } else {
      throw std::invalid_argument("seq_sparse: unknown case " + name);
    }
  }
  return *slot;
}

/// Calls f(problem) with the case's metric.
template <class F>
void with_problem(const sparse_case& c, F&& f) {
  if (c.stiffness)
    f(gv::make_problem(c.g, c.field, gv::min_stiffness{}, gv::connectivity<26>{}));
  else
    f(gv::make_problem(c.g, c.field, gv::uniform{}, gv::connectivity<26>{}));
}

/// 2000 queries: every k-th voxel the diagram reaches, seeds included (they have empty cells).
std::vector<gv::index_t> pick_queries(const gv::diagram<float, 3>& d, std::size_t count) {
  std::vector<gv::index_t> reached;
  for (gv::index_t v = 0; v < d.label.size(); ++v)
    if (d.label[v] != gv::no_label) reached.push_back(v);
  std::vector<gv::index_t> q;
  const std::size_t step = std::max<std::size_t>(1, reached.size() / count);
  for (std::size_t i = 0; i < reached.size() && q.size() < count; i += step) q.push_back(reached[i]);
  return q;
}

template <class Keys>
void insert_case(benchmark::State& state, const std::string& name) {
  const auto& c = get_case(name);
  with_problem(c, [&](const auto& p) {
    const auto d = gv::voronoi(gv::seq, p, c.nodes);
    const auto queries = pick_queries(d, 2000);
    double cell_voxels = 0;
    for (auto _ : state) {
      eng::sparse_scratch<float, Keys> s;  // a fresh scratch per batch, as insert_queries(seq, ...) does
      gv::query_cells<float> out;
      eng::insert_queries(p, s.keys, s.heap, d, queries.data(), queries.size(), out);
      cell_voxels += double(out.voxel.size());
      benchmark::DoNotOptimize(out.voxel.data());
    }
    state.counters["voxels_per_second"] = benchmark::Counter(cell_voxels, benchmark::Counter::kIsRate);
    state.counters["ns_per_voxel"] =
        benchmark::Counter(cell_voxels, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
    state.counters["mean_cell"] = cell_voxels / double(state.iterations()) / double(queries.size());
  });
}

template <class Keys>
void bounded_case(benchmark::State& state, const std::string& name) {
  const auto& c = get_case(name);
  with_problem(c, [&](const auto& p) {
    const auto d = gv::voronoi(gv::seq, p, c.nodes);
    std::vector<float> radius(c.nodes.size(), 0.0f);
    for (gv::index_t v = 0; v < d.label.size(); ++v)
      if (d.label[v] != gv::no_label)
        radius[std::size_t(d.label[v])] = std::max(radius[std::size_t(d.label[v])], 2.0f * d.distance[v]);
    double reached = 0;
    for (auto _ : state) {
      eng::sparse_scratch<float, Keys> s;
      for (std::size_t i = 0; i < c.nodes.size(); i += 10) {
        const std::vector<gv::source<float>> src{{c.g.index(c.nodes[i]), 0.0f, 0}};
        const auto r = eng::bounded(p, s.keys, s.heap, src, radius[i]);
        reached += double(r.size());
        benchmark::DoNotOptimize(r.voxel.data());
      }
    }
    state.counters["voxels_per_second"] = benchmark::Counter(reached, benchmark::Counter::kIsRate);
    state.counters["ns_per_voxel"] =
        benchmark::Counter(reached, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  });
}

void dense_case(benchmark::State& state, const std::string& name) {
  const auto& c = get_case(name);
  with_problem(c, [&](const auto& p) {
    gv::index_t reached = 0;
    for (auto _ : state) {
      auto d = gv::voronoi(gv::seq, p, c.nodes);
      benchmark::DoNotOptimize(d.distance.data());
      if (reached == 0)
        for (gv::index_t v = 0; v < d.label.size(); ++v) reached += d.label[v] != gv::no_label;
    }
    // per voxel reached (the steak's background is never entered), as the sparse cases count
    const double voxels = double(reached) * double(state.iterations());
    state.counters["voxels_per_second"] = benchmark::Counter(voxels, benchmark::Counter::kIsRate);
    state.counters["ns_per_voxel"] =
        benchmark::Counter(voxels, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  });
}

/// Through the front end (validation included), with a fresh scratch per call (`seq`) or one
/// workspace for all calls (`seq(ws)`): what Distance Ratio's ~2 calls per node pay.
void bounded_api_case(benchmark::State& state, const std::string& name, bool workspace) {
  const auto& c = get_case(name);
  with_problem(c, [&](const auto& p) {
    const auto d = gv::voronoi(gv::seq, p, c.nodes);
    std::vector<float> radius(c.nodes.size(), 0.0f);
    for (gv::index_t v = 0; v < d.label.size(); ++v)
      if (d.label[v] != gv::no_label)
        radius[std::size_t(d.label[v])] = std::max(radius[std::size_t(d.label[v])], 2.0f * d.distance[v]);
    gv::seq_workspace ws;
    const auto policy = workspace ? gv::seq(ws) : gv::seq;
    double reached = 0;
    for (auto _ : state) {
      for (std::size_t i = 0; i < c.nodes.size(); i += 10) {
        const auto r = gv::single_source(policy, p, c.nodes[i], radius[i]);
        reached += double(r.size());
        benchmark::DoNotOptimize(r.voxel.data());
      }
    }
    state.counters["voxels_per_second"] = benchmark::Counter(reached, benchmark::Counter::kIsRate);
    state.counters["ns_per_voxel"] =
        benchmark::Counter(reached, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  });
}

/// insert_queries(seq, ...) through the front end in batches of 256 queries, with a fresh scratch
/// per call or one workspace.
void insert_api_case(benchmark::State& state, const std::string& name, bool workspace) {
  const auto& c = get_case(name);
  with_problem(c, [&](const auto& p) {
    const auto d = gv::voronoi(gv::seq, p, c.nodes);
    const auto queries = pick_queries(d, 2000);
    gv::seq_workspace ws;
    const auto policy = workspace ? gv::seq(ws) : gv::seq;
    double cell_voxels = 0;
    for (auto _ : state) {
      for (std::size_t b = 0; b < queries.size(); b += 256) {
        const std::vector<gv::index_t> batch(queries.begin() + std::ptrdiff_t(b),
                                             queries.begin() + std::ptrdiff_t(std::min(queries.size(), b + 256)));
        const auto out = gv::insert_queries(policy, p, d, batch);
        cell_voxels += double(out.voxel.size());
        benchmark::DoNotOptimize(out.voxel.data());
      }
    }
    state.counters["voxels_per_second"] = benchmark::Counter(cell_voxels, benchmark::Counter::kIsRate);
    state.counters["ns_per_voxel"] =
        benchmark::Counter(cell_voxels, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  });
}

template <class Keys>
void register_scratch(const std::string& scratch) {
  for (const char* name : {"table1", "steak"}) {
    const std::string n = name;
    benchmark::RegisterBenchmark(("sparse/insert/" + scratch + "/" + n).c_str(),
                                 [n](benchmark::State& s) { insert_case<Keys>(s, n); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Apply(geovoronoi::bench::min_time_1s);
  }
  benchmark::RegisterBenchmark(("sparse/bounded/" + scratch + "/128cube_100").c_str(),
                               [](benchmark::State& s) { bounded_case<Keys>(s, "128cube_100"); })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->Apply(geovoronoi::bench::min_time_1s);
}

/// Pages of 16 and of 64 voxels give the same cells and bounded solutions, bit for bit.
bool same_results() {
  const auto& c = get_case("table1");
  bool ok = true;
  with_problem(c, [&](const auto& p) {
    const auto d = gv::voronoi(gv::seq, p, c.nodes);
    const auto q = pick_queries(d, 300);
    eng::sparse_scratch<float, eng::paged_keys<float, 6>> a;
    eng::sparse_scratch<float, eng::paged_keys<float, 4>> b;
    gv::query_cells<float> ca, cb;
    eng::insert_queries(p, a.keys, a.heap, d, q.data(), q.size(), ca);
    eng::insert_queries(p, b.keys, b.heap, d, q.data(), q.size(), cb);
    ok = ok && ca.offsets == cb.offsets && ca.voxel == cb.voxel && ca.owner == cb.owner && ca.voxel.size() > 1000 &&
         std::equal(ca.distance.begin(), ca.distance.end(), cb.distance.begin(),
                    [](float x, float y) { return std::memcmp(&x, &y, sizeof x) == 0; });
    const std::vector<gv::source<float>> src{{c.g.index(c.nodes[3]), 0.0f, 0}};
    const auto ra = eng::bounded(p, a.keys, a.heap, src, 30.0f);
    const auto rb = eng::bounded(p, b.keys, b.heap, src, 30.0f);
    ok = ok && ra.voxel == rb.voxel && ra.label == rb.label && ra.size() > 1000;
  });
  return ok;
}

}  // namespace

GEOVORONOI_BENCH_CHECK(page_sizes_agree) { return same_results(); }

GEOVORONOI_BENCH_REGISTER(register_seq_sparse_cases) {
  register_scratch<eng::paged_keys<float, 4>>("paged16");
  register_scratch<eng::paged_keys<float, 5>>("paged32");
  register_scratch<eng::paged_keys<float, 6>>("paged64");
  register_scratch<eng::paged_keys<float, 7>>("paged128");
  for (const char* name : {"table1", "steak", "128cube_100"}) {
    const std::string n = name;
    benchmark::RegisterBenchmark(("sparse/dense/seq/" + n).c_str(), [n](benchmark::State& s) { dense_case(s, n); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Apply(geovoronoi::bench::min_time_1s);
  }
  for (const bool ws : {false, true}) {
    const std::string policy = ws ? "seq_ws" : "seq";
    benchmark::RegisterBenchmark(("sparse/bounded_api/" + policy + "/128cube_100").c_str(),
                                 [ws](benchmark::State& s) { bounded_api_case(s, "128cube_100", ws); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Apply(geovoronoi::bench::min_time_1s);
    benchmark::RegisterBenchmark(("sparse/insert_api/" + policy + "/steak").c_str(),
                                 [ws](benchmark::State& s) { insert_api_case(s, "steak", ws); })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->Apply(geovoronoi::bench::min_time_1s);
  }
}

GEOVORONOI_BENCH_MAIN()

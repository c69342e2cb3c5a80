// Thrust-specific checks, added to each system's suite: the default policy (THRUST_DEVICE_SYSTEM),
// tiny batches (many threshold raises, maximal re-queuing), the work counters, bad weights.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <doctest/doctest.h>

#include "support/oracle.hpp"

#include <atomic>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace gvthrust {
namespace gv = geovoronoi;

static_assert(std::is_trivially_copyable_v<gv::thrust::par_t>, "par_t is a small value type");

struct negative_weight {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T to) const noexcept {
    return to > T(1.5) ? -length : length;
  }
};

TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": batch sizes and the default policy agree with seq") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({23, 17, 11}, {1.0, 1.3, 0.8});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> u(0.5f, 4.0f);
  std::vector<float> f(g.size());
  for (auto& x : f) x = u(rng);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto seeds = gvtest::random_seeds(rng, p, 7);
  const auto ref = gv::voronoi(gv::seq, p, seeds);
  for (std::size_t batch : {std::size_t(1), std::size_t(7), std::size_t(100), std::size_t(1) << 20}) {
    gv::thrust::stats st;
    const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY().with_batch(batch).with_stats(&st), p, seeds);
    gvsuite::require_same_diagram(d, ref, "batch " + std::to_string(batch));
    CHECK(st.reached == std::uint64_t(g.size()));
    CHECK(st.expansions >= st.reached);
    CHECK(st.splits >= 1);
  }
  gv::thrust::stats st;
  const auto d = gv::voronoi(gv::thrust::par.with_stats(&st), p, seeds);
  gvsuite::require_same_diagram(d, ref, "thrust::par (THRUST_DEVICE_SYSTEM)");
  CHECK(st.expansions_per_voxel() >= 1.0);
}

// A field whose values span three decades, noisy, masked, anisotropic (an MRI): a window chosen by
// voxel count alone was thousands of edges deep in the stiff tissues and expanded each voxel 3.4 times
// here (7.5 at 221x271x69); the depth-limited window and the per-voxel admission keep it near 1.1.
// The bound is loose (work counters vary a little with thread timing); the result must equal seq's.
TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": few re-expansions on a heterogeneous MRI-like volume") {
  GV_SUITE_PREAMBLE();
  const auto f = gv::phantom::mri_like(gv::phantom::mri_like_grid(96));
  const auto p = gv::make_problem(f.geometry(), f, gv::min_stiffness{}, gv::connectivity<26>{});
  for (int count : {1, 20}) {
    const auto seeds = gv::phantom::random_seeds(f, count, 2016);
    const auto ref = gv::voronoi(gv::seq, p, seeds);
    gv::thrust::stats st;
    const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY().with_stats(&st), p, seeds);
    gvsuite::require_same_diagram(d, ref, std::to_string(count) + " seeds");
    INFO(count << " seeds: " << st.expansions_per_voxel() << " expansions per voxel, " << st.splits << " raises");
    CHECK(st.reached > 100000);
    CHECK(st.expansions_per_voxel() < 1.5);
  }
}

TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": a negative edge weight is an error") {
  GV_SUITE_PREAMBLE();
  const gv::grid<2> g({9, 9});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({6, 6})] = 2.0f;
  const auto p = gv::make_problem(g, f, negative_weight{}, gv::connectivity<8>{});
  CHECK_THROWS_AS(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, std::vector<gv::coord<2>>{{0, 0}}), gv::metric_error);
}

/// A label other than @p l among [0, count).
inline gv::label_t label_t_other(gv::label_t l, gv::label_t count) { return (l + 1) % count; }

// Grids where many path sums differ by an ulp: 26-connected, min_stiffness on {1, 2, 4} (or continuous)
// values, anisotropic spacing. There a neighbour's earlier, larger key can round to the same sum as its
// final one and propose a lower label than the tie rule gives; the engine must repair those labels.
// Dense, radius-bounded dense, and sparse bounded solves are compared with seq bit for bit, with
// batches from "almost Dijkstra" to "everything at once" (the most re-expansions).
TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": labels equal seq where stale proposals round to the same sum") {
  GV_SUITE_PREAMBLE();
  std::mt19937_64 rng(2026);
  int repaired = 0, bounded_repaired = 0;
  const std::size_t batches[] = {std::size_t(1) << 20, 64, 0};
  // every 40th grid is larger: the small ones run their steps on the calling thread
  for (int t = 0; t < 2000; ++t) {
    gv::coord<3> e{};
    for (auto& x : e) x = 3 + gv::index_t(rng() % 11);
    if (t % 40 == 39) e = {28, 24, 20};  // rounds large enough to run on several threads
    const gv::grid<3> g(e, {1.0, t % 2 ? 0.7 : 1.0, t % 3 ? 1.3 : 1.0}, {});
    const auto f = gvtest::random_field<float>(rng, g.size(), t % 4 != 3, t % 5 == 0 ? 0.1 : 0.0, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = gvtest::random_seeds(rng, p, 2 + int(rng() % 8));
    if (seeds.size() < 2) continue;
    auto src = gvtest::as_sources(p, seeds);
    if (t % 7 == 0) src[1].distance = 0.5f;  // initial distances too
    const std::size_t batch = batches[t % 3];
    const std::string what = "trial " + std::to_string(t) + ", batch " + std::to_string(batch);
    gv::thrust::stats st;
    const auto ref = gv::geodesic_solve(gv::seq, p, src);
    const auto got = gv::geodesic_solve(GEOVORONOI_TEST_POLICY().with_batch(batch).with_stats(&st), p, src);
    gvsuite::require_same_diagram(got, ref, what + ", dense");
    repaired += st.relabelled > 0;
    // a radius inside the diagram: some voxels in, some out
    float radius = 0;
    for (gv::index_t v = 0; v < g.size(); ++v)
      if (ref.label[v] != gv::no_label) radius = std::max(radius, ref.distance[v]);
    radius *= 0.6f;
    const auto sref = gv::bounded_solve(gv::seq, p, src, radius);
    const auto sgot = gv::bounded_solve(GEOVORONOI_TEST_POLICY().with_batch(batch).with_stats(&st), p, src, radius);
    bounded_repaired += st.relabelled > 0;
    INFO(what << ", bounded");
    REQUIRE(sgot.size() == sref.size());
    CHECK(sgot.voxel == sref.voxel);
    CHECK(sgot.label == sref.label);
    bool same_bits = true;
    for (std::size_t i = 0; i < sref.size(); ++i) same_bits = same_bits && gvtest::bits(sgot.distance[i]) == gvtest::bits(sref.distance[i]);
    CHECK(same_bits);
  }
  // The generator must actually exercise the repair, or the comparisons above prove little.
  MESSAGE("label repair changed labels in " << repaired << " dense and " << bounded_repaired << " bounded solves");
  CHECK(repaired > 0);
  CHECK(bounded_repaired > 0);
}

// The repair pass on its own (host code): labels of seq's diagram corrupted the way a stale proposal
// corrupts them (a wrong label at one voxel, inherited along the edges that realise the distances) are
// restored from that one voxel, in a dense diagram and in a sparse bounded solution.
TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": the label repair restores corrupted labels from the suspects") {
  namespace td = gv::thrust::detail;
  std::mt19937_64 rng(77);
  int corrupted = 0;
  for (int t = 0; t < 60; ++t) {
    const gv::grid<3> g({9 + t % 4, 8, 7}, {1.0, t % 2 ? 0.7 : 1.0, 1.3}, {});
    const auto f = gvtest::random_field<float>(rng, g.size(), t % 3 != 2, t % 4 == 0 ? 0.1 : 0.0, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = gvtest::random_seeds(rng, p, 3 + int(rng() % 4));
    if (seeds.size() < 2) continue;
    const auto src = gvtest::as_sources(p, seeds);
    const auto ref = gv::geodesic_solve(gv::seq, p, src);
    // corrupt: voxel x takes another label, and so does everything that inherited x's label from x
    auto corrupt = [&](std::vector<gv::label_t>& label, const std::vector<float>& dist, gv::index_t x) {
      const gv::label_t from = label[x], to = label_t_other(from, gv::label_t(seeds.size()));
      std::vector<gv::index_t> todo{x};
      label[x] = to;
      const gv::detail::search::stencil_walker<3> walk(p);
      while (!todo.empty()) {
        const gv::index_t u = todo.back();
        todo.pop_back();
        auto visit = [&](int k, gv::index_t y) {
          if (label[y] != from || !p.inside(y)) return;
          if (dist[u] + p.metric(p.edges.length[k], p.field[u], p.field[y]) != dist[y]) return;
          label[y] = to;
          todo.push_back(y);
        };
        walk.for_each_neighbour(p, u, visit);
      }
    };
    std::vector<gv::index_t> reached;
    for (gv::index_t v = 0; v < g.size(); ++v)
      if (ref.label[v] != gv::no_label) reached.push_back(v);
    const gv::index_t x = reached[rng() % reached.size()];
    // dense
    std::vector<float> dist(ref.distance.values().begin(), ref.distance.values().end());
    std::vector<gv::label_t> label(ref.label.values().begin(), ref.label.values().end());
    corrupt(label, dist, x);
    corrupted += label != std::vector<gv::label_t>(ref.label.values().begin(), ref.label.values().end());
    td::dense_labels<float> dense{dist.data(), label.data(), g.size()};
    CHECK(td::repair_labels(p, dense, src, {x}) >= 1);
    bool same = true;
    for (gv::index_t v = 0; v < g.size(); ++v) same = same && label[v] == ref.label[v];
    CHECK_MESSAGE(same, "dense, trial " << t);
    CHECK(td::repair_labels(p, dense, src, {}) == 0);
    // sparse: the voxels below a radius
    const float radius = dist[x] * 1.5f + 0.1f;
    auto sparse = gv::bounded_solve(gv::seq, p, src, radius);
    const auto expect = sparse.label;
    std::vector<float> sdist(g.size(), std::numeric_limits<float>::infinity());
    std::vector<gv::label_t> slabel(g.size(), gv::no_label);
    for (std::size_t i = 0; i < sparse.size(); ++i) {
      sdist[sparse.voxel[i]] = sparse.distance[i];
      slabel[sparse.voxel[i]] = sparse.label[i];
    }
    corrupt(slabel, sdist, x);
    for (std::size_t i = 0; i < sparse.size(); ++i) sparse.label[i] = slabel[sparse.voxel[i]];
    td::sparse_labels<float> store{sparse.voxel.data(), sparse.distance.data(), sparse.label.data(),
                                   gv::index_t(sparse.size())};
    td::repair_labels(p, store, src, {x});
    CHECK_MESSAGE(sparse.label == expect, "sparse, trial " << t);
  }
  CHECK(corrupted > 30);  // the corruption did change labels
}

TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": backend_host_parallel_for visits each index once, rethrows") {
  // host code only: runs with or without a device
  using gv::thrust::backend_host_parallel_for;
  for (const gv::index_t n : {gv::index_t(0), gv::index_t(1), gv::index_t(7), gv::index_t(10007)}) {
    std::vector<std::atomic<int>> hits(static_cast<std::size_t>(n));
    for (auto& h : hits) h.store(0);
    backend_host_parallel_for(GEOVORONOI_TEST_POLICY(), n, [&](gv::index_t i) { hits[static_cast<std::size_t>(i)]++; });
    bool once = true;
    for (auto& h : hits) once = once && h.load() == 1;
    CHECK_MESSAGE(once, "n = " << n);
  }
  // the default policy (THRUST_DEVICE_SYSTEM) too, through argument-dependent lookup
  std::atomic<long> sum{0};
  backend_host_parallel_for(gv::thrust::par, 1000, [&](gv::index_t i) { sum += long(i); });
  CHECK(sum.load() == 999L * 1000L / 2);
  // the first exception reaches the caller; the loop does not hang or terminate
  std::atomic<int> calls{0};
  auto boom = [&](gv::index_t i) {
    ++calls;
    if (i == 777) throw std::runtime_error("query 777 failed");
  };
  CHECK_THROWS_WITH_AS(backend_host_parallel_for(GEOVORONOI_TEST_POLICY(), 5000, boom), "query 777 failed",
                       std::runtime_error);
  CHECK(calls.load() >= 1);
  CHECK(calls.load() <= 5000);
  // every call throwing: one exception, still rethrown
  CHECK_THROWS_AS(backend_host_parallel_for(GEOVORONOI_TEST_POLICY(), 64, [](gv::index_t) { throw std::logic_error("x"); }),
                  std::logic_error);
}

}  // namespace gvthrust

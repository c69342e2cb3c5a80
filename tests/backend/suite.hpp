// The backend test suite, written once. A backend's test file defines
//   GEOVORONOI_TEST_BACKEND_NAME  "seq", "thrust_omp", ...
//   GEOVORONOI_TEST_POLICY()      an expression yielding the policy object
// (and optionally GEOVORONOI_TEST_SKIP_IF_NO_DEVICE() returning true to skip, and
// GEOVORONOI_TEST_REDUCED_MATRIX to run the oracle comparison on a reduced type/connectivity matrix:
// the Thrust CPP and TBB systems, whose code differs from the OpenMP suite's full matrix only in the
// Thrust system underneath) and includes this file.
// Every result is compared bit for bit: against the Bellman-Ford oracle, and for the other backends
// against the sequential backend.

#include <doctest/doctest.h>

#include "oracle.hpp"

#include <algorithm>
#include <random>
#include <string>

#ifndef GEOVORONOI_TEST_SKIP_IF_NO_DEVICE
#define GEOVORONOI_TEST_SKIP_IF_NO_DEVICE() false
#endif

namespace gvsuite {
namespace gv = geovoronoi;
using namespace gvtest;

#define GV_SUITE_PREAMBLE()                           \
  if (GEOVORONOI_TEST_SKIP_IF_NO_DEVICE()) {          \
    MESSAGE("no device: skipped");                    \
    return;                                           \
  }

template <class D1, class D2>
void require_same_diagram(const D1& a, const D2& b, const std::string& what) {
  REQUIRE(a.distance.size() == b.distance.size());
  gv::index_t bad = -1;
  for (gv::index_t v = 0; v < a.distance.size(); ++v)
    if (bits(a.distance[v]) != bits(b.distance[v]) || a.label[v] != b.label[v]) {
      bad = v;
      break;
    }
  INFO(what);
  if (bad >= 0) {
    INFO("first mismatch at voxel " << bad << ": " << a.distance[bad] << "/" << a.label[bad] << " vs "
                                    << b.distance[bad] << "/" << b.label[bad]);
    CHECK(bad < 0);
  }
  CHECK(bad < 0);
}

template <class T, int Dim, class Metric, int N>
void oracle_case(std::mt19937_64& rng, int trial, bool cost_metric) {
  const bool aniso = trial % 2 == 1, ties = trial % 3 != 2;
  const auto g = random_grid<Dim>(rng, aniso);
  const auto f = random_field<T>(rng, g.size(), ties, trial % 4 == 0 ? 0.0 : 0.2, cost_metric);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 1 + int(rng() % 5));
  if (seeds.empty()) return;
  const auto expect = oracle(p, as_sources(p, seeds));
  const auto got = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, gv::solve_options{true});
  require_same_diagram(got, expect,
                       std::string(GEOVORONOI_TEST_BACKEND_NAME) + " vs oracle, dim " + std::to_string(Dim) + ", N " +
                           std::to_string(N) + ", trial " + std::to_string(trial));
  // properties: zero at seeds with their own label; parent realises the key and carries the label
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    CHECK(got.distance(seeds[i]) == T(0));
    CHECK(got.label(seeds[i]) == gv::label_t(i));
    CHECK(got.parent(seeds[i]) == gv::no_index);
  }
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto par = got.parent[v];
    if (got.label[v] == gv::no_label) {
      CHECK(par == gv::no_index);
      CHECK(got.distance[v] == std::numeric_limits<T>::infinity());
      continue;
    }
    if (par == gv::no_index) continue;
    CHECK(got.label[par] == got.label[v]);
    CHECK(got.distance[par] <= got.distance[v]);
  }
}

template <class T, int Dim, int N>
void oracle_all_metrics(int trials) {
  std::mt19937_64 rng(1234 + 17 * N + 1000 * sizeof(T));
  for (int t = 0; t < trials; ++t) {
    oracle_case<T, Dim, gv::uniform, N>(rng, t, false);
    oracle_case<T, Dim, gv::min_stiffness, N>(rng, t, false);
    oracle_case<T, Dim, gv::mean_stiffness, N>(rng, t, false);
    oracle_case<T, Dim, gv::mean_cost, N>(rng, t, true);
    oracle_case<T, Dim, destination_cost, N>(rng, t, false);
  }
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": equals the Bellman-Ford oracle, 2D, every metric") {
  GV_SUITE_PREAMBLE();
#ifndef GEOVORONOI_TEST_REDUCED_MATRIX
  oracle_all_metrics<float, 2, 4>(60);
  oracle_all_metrics<double, 2, 8>(20);
#endif
  oracle_all_metrics<float, 2, 8>(60);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": equals the Bellman-Ford oracle, 3D, every metric") {
  GV_SUITE_PREAMBLE();
#ifndef GEOVORONOI_TEST_REDUCED_MATRIX
  oracle_all_metrics<float, 3, 6>(60);
  oracle_all_metrics<float, 3, 18>(60);
#endif
  oracle_all_metrics<float, 3, 26>(60);
  oracle_all_metrics<double, 3, 26>(20);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": exact ties go to the lowest seed index") {
  GV_SUITE_PREAMBLE();
  // A uniform line: the middle voxel is exactly as far from both ends, whatever their order.
  const gv::grid<3> g({9, 1, 1});
  const std::vector<float> f(9, 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<6>{});
  const auto a = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, std::vector<gv::coord<3>>{{0, 0, 0}, {8, 0, 0}});
  const auto b = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, std::vector<gv::coord<3>>{{8, 0, 0}, {0, 0, 0}});
  CHECK(a.distance({4, 0, 0}) == 4.0f);
  CHECK(a.label({4, 0, 0}) == 0);
  CHECK(b.label({4, 0, 0}) == 0);  // now the seed at x = 8 has index 0
  CHECK(a.label({3, 0, 0}) == 0);
  CHECK(a.label({5, 0, 0}) == 1);
  CHECK(b.label({3, 0, 0}) == 1);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": masked and unreachable voxels") {
  GV_SUITE_PREAMBLE();
  // A wall of zeros splits the grid; the right half has no seed.
  const gv::grid<2> g({7, 5});
  std::vector<float> f(g.size(), 1.0f);
  for (int y = 0; y < 5; ++y) f[g.index({3, y})] = 0.0f;
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, std::vector<gv::coord<2>>{{0, 0}});
  for (int y = 0; y < 5; ++y)
    for (int x = 3; x < 7; ++x) {
      CHECK(d.label({x, y}) == gv::no_label);
      CHECK(d.distance({x, y}) == std::numeric_limits<float>::infinity());
    }
  CHECK(d.label({2, 4}) == 0);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": insert-query equals a full recompute with the extra seed") {
  GV_SUITE_PREAMBLE();
  std::mt19937_64 rng(99);
  auto run = [&](auto dim_tag, auto n_tag, int trials) {
    constexpr int Dim = decltype(dim_tag)::value;
    constexpr int N = decltype(n_tag)::value;
    for (int t = 0; t < trials; ++t) {
      const auto g = random_grid<Dim>(rng, t % 2 == 1);
      const auto f = random_field<float>(rng, g.size(), t % 3 != 2, 0.15, false);
      const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<N>{});
      auto seeds = random_seeds(rng, p, 2 + int(rng() % 4));
      if (seeds.size() < 2) continue;
      // the last random voxel becomes the query; the others are the diagram's seeds
      const auto q = seeds.back();
      seeds.pop_back();
      const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds);
      // a few queries at once, including a seed (empty cell) and the random voxel
      std::vector<gv::coord<Dim>> queries{q, seeds[0]};
      const auto cells = gv::insert_queries(GEOVORONOI_TEST_POLICY(), p, d, queries);
      REQUIRE(cells.size() == 2);
      CHECK(cells.cell_size(1) == 0);
      auto with_q = seeds;
      with_q.push_back(q);
      const auto full = gv::voronoi(gv::seq, p, with_q);
      const gv::label_t qi = gv::label_t(seeds.size());
      std::vector<gv::index_t> expect;
      for (gv::index_t v = 0; v < g.size(); ++v)
        if (full.label[v] == qi) expect.push_back(v);
      REQUIRE(cells.cell_size(0) == expect.size());
      for (std::size_t i = 0; i < expect.size(); ++i) {
        CHECK(cells.voxel[i] == expect[i]);
        CHECK(bits(cells.distance[i]) == bits(full.distance[expect[i]]));
        CHECK(cells.owner[i] == d.label[expect[i]]);
        CHECK(cells.distance[i] < d.distance[expect[i]]);
      }
      // the single-query form agrees
      const auto one = gv::insert_query(GEOVORONOI_TEST_POLICY(), p, d, q);
      CHECK(one.voxel == std::vector<gv::index_t>(cells.voxel.begin(), cells.voxel.begin() + cells.offsets[1]));
      // outside the cell, the distances are the old ones
      for (gv::index_t v = 0; v < g.size(); ++v)
        if (full.label[v] != qi) CHECK(bits(full.distance[v]) == bits(d.distance[v]));
    }
  };
  run(std::integral_constant<int, 2>{}, std::integral_constant<int, 8>{}, 40);
  run(std::integral_constant<int, 3>{}, std::integral_constant<int, 6>{}, 40);
  run(std::integral_constant<int, 3>{}, std::integral_constant<int, 26>{}, 40);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": bounded and single-source solves") {
  GV_SUITE_PREAMBLE();
  std::mt19937_64 rng(7);
  for (int t = 0; t < 40; ++t) {
    const auto g = random_grid<3>(rng, true);
    const auto f = random_field<float>(rng, g.size(), t % 2 == 0, 0.1, false);
    const auto p = gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<18>{});
    const auto seeds = random_seeds(rng, p, 3);
    if (seeds.empty()) continue;
    auto src = as_sources(p, seeds);
    src[0].distance = 0.75f;  // non-zero initial distances, as Distance Ratio's frontier pass uses
    const auto dense = gv::geodesic_solve(GEOVORONOI_TEST_POLICY(), p, src);
    require_same_diagram(dense, oracle(p, src), "geodesic_solve with initial distances");
    const float radius = 2.5f;
    const auto sparse = gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, radius);
    std::size_t i = 0;
    for (gv::index_t v = 0; v < g.size(); ++v) {
      if (!(dense.distance[v] < radius)) continue;
      REQUIRE(i < sparse.size());
      CHECK(sparse.voxel[i] == v);
      CHECK(bits(sparse.distance[i]) == bits(dense.distance[v]));
      CHECK(sparse.label[i] == dense.label[v]);
      ++i;
    }
    CHECK(i == sparse.size());
    // dense with a radius bound: the same voxels, the rest unreached
    const auto capped = gv::geodesic_solve(GEOVORONOI_TEST_POLICY(), p, src, gv::solve_options{false, radius});
    for (gv::index_t v = 0; v < g.size(); ++v) {
      if (dense.distance[v] < radius)
        CHECK(bits(capped.distance[v]) == bits(dense.distance[v]));
      else
        CHECK(capped.label[v] == gv::no_label);
    }
    // a max_distance beyond float's range is +inf (the front end's one conversion), -huge is
    // below every distance: the whole diagram, then nothing
    const auto huge = gv::geodesic_solve(GEOVORONOI_TEST_POLICY(), p, src, gv::solve_options{false, 1e300});
    require_same_diagram(huge, dense, "max_distance 1e300");
    const auto none = gv::geodesic_solve(GEOVORONOI_TEST_POLICY(), p, src, gv::solve_options{false, -1e300});
    for (gv::index_t v = 0; v < g.size(); ++v) CHECK(none.label[v] == gv::no_label);
    const auto one = gv::single_source(GEOVORONOI_TEST_POLICY(), p, seeds[0]);
    const auto ref = oracle(p, {gv::source<float>{g.index(seeds[0]), 0.0f, 0}});
    std::size_t reached = 0;
    for (gv::index_t v = 0; v < g.size(); ++v) reached += ref.label[v] != gv::no_label;
    REQUIRE(one.size() == reached);
    for (std::size_t k = 0; k < one.size(); ++k) CHECK(bits(one.distance[k]) == bits(ref.distance[one.voxel[k]]));
  }
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": agrees with seq on a larger gradient volume") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({40, 33, 27}, {1.0, 0.7, 1.3});
  std::vector<float> f(g.size());
  for (gv::index_t v = 0; v < g.size(); ++v) f[v] = 1.0f + 9.0f * float(g.coords(v)[0]) / 39.0f;
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  std::mt19937_64 rng(5);
  const auto seeds = random_seeds(rng, p, 12);
  const auto a = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, gv::solve_options{true});
  const auto b = gv::voronoi(gv::seq, p, seeds, gv::solve_options{true});
  require_same_diagram(a, b, "vs seq");
  CHECK(a.parent.values() == b.parent.values());
}

}  // namespace gvsuite

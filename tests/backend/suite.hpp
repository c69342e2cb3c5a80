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

#include "support/oracle.hpp"

#include <geovoronoi/cut_from_mesh.hpp>

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

// ---- cut edges --------------------------------------------------------------------------------------

/// A problem with random cut edges against the oracle (which reads the cut table's plain lookup):
/// distances and labels bit for bit, parents realise the key over an edge that is not cut.
template <class T, int Dim, class Metric, int N>
void cut_case(std::mt19937_64& rng, int trial, bool cost_metric) {
  const bool aniso = trial % 2 == 1, ties = trial % 3 != 2;
  const auto g = random_grid<Dim>(rng, aniso);
  const auto f = random_field<T>(rng, g.size(), ties, trial % 4 == 0 ? 0.0 : 0.15, cost_metric);
  const auto p0 = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto cuts = random_cuts(rng, g, gv::connectivity<N>{}, trial % 5 == 0 ? 0.6 : 0.25);
  const gv::cut_table table(cuts);
  const auto p = gv::with_cuts(p0, table);
  static_assert(decltype(p)::has_cuts && !decltype(p0)::has_cuts);
  const auto seeds = random_seeds(rng, p, 1 + int(rng() % 5));
  if (seeds.empty()) return;
  const std::string what = std::string(GEOVORONOI_TEST_BACKEND_NAME) + " with cuts vs oracle, dim " +
                           std::to_string(Dim) + ", N " + std::to_string(N) + ", trial " + std::to_string(trial);
  const auto got = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, gv::solve_options{true});
  require_same_diagram(got, oracle(p, as_sources(p, seeds)), what);
  const auto ref = gv::voronoi(gv::seq, p, seeds, gv::solve_options{true});
  CHECK(got.parent.values() == ref.parent.values());
  constexpr auto offs = gv::connectivity<N>::offsets();
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto par = got.parent[v];
    if (par == gv::no_index) continue;
    int dir = -1;
    for (int k = 0; k < N; ++k) {
      auto c = g.coords(v);
      for (int a = 0; a < Dim; ++a) c[a] += offs[k][a];
      if (g.contains(c) && g.index(c) == par) dir = k;
    }
    REQUIRE(dir >= 0);
    CHECK_FALSE(cuts.cut(v, dir));
    CHECK(got.label[par] == got.label[v]);
    CHECK(bits(T(got.distance[par] + p.weight(par, v, dir))) == bits(got.distance[v]));
  }
  // with no edge cut the problem with cuts solves exactly like the one without
  const gv::cut_table none(gv::cut_set<Dim>(g, gv::connectivity<N>{}));
  require_same_diagram(gv::voronoi(GEOVORONOI_TEST_POLICY(), gv::with_cuts(p0, none), seeds),
                       gv::voronoi(GEOVORONOI_TEST_POLICY(), p0, seeds), what + ", empty cut");
}

template <class T, int Dim, int N>
void cut_all_metrics(int trials) {
  std::mt19937_64 rng(4321 + 31 * N + 1000 * sizeof(T));
  for (int t = 0; t < trials; ++t) {
    cut_case<T, Dim, gv::uniform, N>(rng, t, false);
    cut_case<T, Dim, gv::min_stiffness, N>(rng, t, false);
    cut_case<T, Dim, gv::mean_cost, N>(rng, t, true);
    cut_case<T, Dim, destination_cost, N>(rng, t, false);
  }
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": cut edges, 2D and 3D, against the oracle") {
  GV_SUITE_PREAMBLE();
#ifndef GEOVORONOI_TEST_REDUCED_MATRIX
  cut_all_metrics<float, 2, 4>(25);
  cut_all_metrics<float, 3, 6>(25);
  cut_all_metrics<float, 3, 18>(15);
#endif
  cut_all_metrics<float, 2, 8>(25);
  cut_all_metrics<double, 2, 8>(10);
  cut_all_metrics<float, 3, 26>(25);
  cut_all_metrics<double, 3, 26>(10);
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": a cut plane across the grid leaves the far side unreachable") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({10, 7, 6}, {1.0, 0.5, 2.0});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p0 = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  // two triangles covering the plane x = 4.5 (world = index here: origin 0, x spacing 1)
  gv::triangle_mesh m;
  m.vertices = {{4.5, -10, -10}, {4.5, 20, -10}, {4.5, 20, 40}, {4.5, -10, 40}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto cuts = gv::cut_from_mesh(g, gv::connectivity<26>{}, m);
  CHECK(cuts.size() == std::size_t(19 * 16));  // the 26-neighbour edges from x = 4 to x = 5
  const gv::cut_table table(cuts);
  const auto p = gv::with_cuts(p0, table);
  const std::vector<gv::coord<3>> seeds{{1, 3, 2}};
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, gv::solve_options{true});
  const auto d0 = gv::voronoi(GEOVORONOI_TEST_POLICY(), p0, seeds);
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    if (c[0] >= 5) {
      CHECK(d.label[v] == gv::no_label);
      CHECK(d.distance[v] == std::numeric_limits<float>::infinity());
      CHECK(d.parent[v] == gv::no_index);
    } else {
      CHECK(d.label[v] == 0);
      CHECK(d.distance[v] >= d0.distance[v]);  // paths near the plane may be longer; none shorter
    }
  }
  // a second seed on the far side takes it all
  const std::vector<gv::coord<3>> both{{1, 3, 2}, {8, 0, 0}};
  const auto e = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, both);
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(e.label[v] == (g.coords(v)[0] >= 5 ? 1 : 0));
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": insert-query and bounded solves honour cuts") {
  GV_SUITE_PREAMBLE();
  std::mt19937_64 rng(1313);
  auto run = [&](auto dim_tag, auto n_tag, int trials) {
    constexpr int Dim = decltype(dim_tag)::value;
    constexpr int N = decltype(n_tag)::value;
    for (int t = 0; t < trials; ++t) {
      const auto g = random_grid<Dim>(rng, t % 2 == 1);
      const auto f = random_field<float>(rng, g.size(), t % 3 != 2, 0.1, false);
      const auto p0 = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<N>{});
      const gv::cut_table table(random_cuts(rng, g, gv::connectivity<N>{}, 0.3));
      const auto p = gv::with_cuts(p0, table);
      auto seeds = random_seeds(rng, p, 3 + int(rng() % 3));
      if (seeds.size() < 2) continue;
      const auto q = seeds.back();
      seeds.pop_back();
      const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds);
      const auto cell = gv::insert_query(GEOVORONOI_TEST_POLICY(), p, d, q);
      auto with_q = seeds;
      with_q.push_back(q);
      const auto full = oracle(p, as_sources(p, with_q));
      std::vector<gv::index_t> expect;
      for (gv::index_t v = 0; v < g.size(); ++v)
        if (full.distance[v] < d.distance[v]) expect.push_back(v);
      CHECK(cell.voxel == expect);
      for (std::size_t i = 0; i < cell.voxel.size() && i < expect.size(); ++i)
        CHECK(bits(cell.distance[i]) == bits(full.distance[expect[i]]));
      const auto src = as_sources(p, seeds);
      const auto dense = oracle(p, src);
      const float radius = 3.0f;
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
    }
  };
  run(std::integral_constant<int, 2>{}, std::integral_constant<int, 8>{}, 30);
  run(std::integral_constant<int, 3>{}, std::integral_constant<int, 6>{}, 30);
  run(std::integral_constant<int, 3>{}, std::integral_constant<int, 26>{}, 30);
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

// ---- overflow, progress, cancellation, threads ------------------------------------------------------

/// A 2D strip, stiffness b everywhere (min_stiffness: every edge weighs length / b), seed at x = 0.
inline gv::problem<float, 2, gv::min_stiffness, 4> strip_problem(const std::vector<float>& f, const gv::grid<2>& g) {
  return gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{});
}

/// The message of the overflow_error @p f throws ("" when it throws none).
template <class F>
std::string overflow_message(F&& f) {
  try {
    f();
  } catch (const gv::overflow_error& e) {
    return e.what();
  }
  return "";
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": a float path sum that overflows throws overflow_error") {
  GV_SUITE_PREAMBLE();
  // edges of 1e37: the 35th voxel along the strip is beyond float's range (3.4e38)
  const gv::grid<2> g({48, 3});
  const std::vector<float> f(g.size(), 1e-37f);
  const auto p = strip_problem(f, g);
  const std::vector<gv::coord<2>> seeds{{0, 1}};
  const std::string got = overflow_message([&] { (void)gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds); });
  const std::string ref = overflow_message([&] { (void)gv::voronoi(gv::seq, p, seeds); });
  CHECK(ref.find("overflows float") != std::string::npos);
  CHECK(ref.find("double") != std::string::npos);
  CHECK(got == ref);  // the same voxel and values on every backend
  // the unbounded sparse solves too
  CHECK(overflow_message([&] { (void)gv::single_source(GEOVORONOI_TEST_POLICY(), p, seeds[0]); }) != "");
  CHECK(overflow_message([&] {
          (void)gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, {gv::source<float>{g.index(seeds[0]), 0.0f, 0}},
                                  std::numeric_limits<float>::infinity());
        }) != "");
  // a finite radius bound: the voxels beyond it are unreached by request, nothing is lost
  const auto capped = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, gv::solve_options{false, 1e38});
  CHECK(capped.label[g.index({5, 1})] == 0);
  CHECK(capped.label[g.index({40, 1})] == gv::no_label);
  // in double the same problem is fine: every voxel reached
  const std::vector<double> fd(g.size(), 1e-37);
  const auto pd = gv::make_problem(g, fd, gv::min_stiffness{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), pd, seeds);
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(d.label[v] == 0);
  require_same_diagram(d, gv::voronoi(gv::seq, pd, seeds), "double strip vs seq");
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": an edge weight of +inf from finite values is an overflow") {
  GV_SUITE_PREAMBLE();
  const gv::grid<2> g({6, 5});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({3, 2})] = std::numeric_limits<float>::denorm_min();  // 1 / 1.4e-45 is +inf in float
  const auto p = strip_problem(f, g);
  const std::vector<gv::coord<2>> seeds{{0, 0}};
  const std::string got = overflow_message([&] { (void)gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds); });
  CHECK(got.find("(3,2)") != std::string::npos);
  CHECK(got.find("edge weight") != std::string::npos);
  CHECK(got == overflow_message([&] { (void)gv::voronoi(gv::seq, p, seeds); }));
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": an infinite sum along one edge of a voxel reached along another is no error") {
  GV_SUITE_PREAMBLE();
  // the voxel (3,2) costs 2e38 to enter and as much to leave: leaving it overflows, but its
  // neighbours are all reached around it, so the float result is complete
  const gv::grid<2> g({7, 5});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({3, 2})] = 5e-39f;
  const auto p = strip_problem(f, g);
  const std::vector<gv::coord<2>> seeds{{0, 0}, {6, 4}};
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds);
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(d.label[v] != gv::no_label);
  require_same_diagram(d, gv::voronoi(gv::seq, p, seeds), "vs seq");
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": progress rises to 1; cancelling throws and leaves nothing behind") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({40, 36, 30});
  std::vector<float> f(g.size());
  for (gv::index_t v = 0; v < g.size(); ++v) f[v] = 1.0f + float(g.coords(v)[1] % 7);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> seeds{{1, 2, 3}, {30, 30, 20}, {10, 30, 5}};
  const auto ref = gv::voronoi(gv::seq, p, seeds);

  std::vector<double> seen;
  gv::solve_options opt;
  opt.progress = [&](double x) {
    seen.push_back(x);
    return true;
  };
  require_same_diagram(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, opt), ref, "with a progress callback");
  REQUIRE(seen.size() >= 2);
  CHECK(seen.front() == 0.0);
  CHECK(seen.back() == 1.0);
  CHECK(std::is_sorted(seen.begin(), seen.end()));
  for (double x : seen) CHECK((x >= 0.0 && x <= 1.0));

  // the bounded solve reports too
  seen.clear();
  const auto src = std::vector<gv::source<float>>{{g.index(seeds[0]), 0.0f, 0}};
  const auto b = gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, 20.0f, opt);
  CHECK(b.size() > 0);
  REQUIRE(seen.size() >= 2);
  CHECK(seen.back() == 1.0);
  CHECK(std::is_sorted(seen.begin(), seen.end()));

  // stop at the first call, then at the second: cancelled, and the next solve is right
  for (int stop_at : {1, 2}) {  // every backend calls at least twice (0 and 1)
    int calls = 0;
    gv::solve_options stop;
    stop.progress = [&](double) { return ++calls < stop_at; };
    CHECK_THROWS_AS(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, stop), gv::cancelled);
    CHECK(calls == stop_at);
    calls = 0;
    CHECK_THROWS_AS(gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, 20.0f, stop), gv::cancelled);
    require_same_diagram(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds), ref, "after a cancelled solve");
    const auto again = gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, 20.0f);
    CHECK(again.voxel == b.voxel);
    CHECK(again.distance == b.distance);
  }
}

TEST_CASE("backend " GEOVORONOI_TEST_BACKEND_NAME ": the thread count does not change a bit") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({44, 40, 32}, {1.0, 0.8, 1.2});
  std::vector<float> f(g.size());
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    f[v] = 1.0f + float((c[0] * 7 + c[1] * 3 + c[2]) % 11);
  }
  const auto p = gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<26>{});
  std::mt19937_64 rng(12);
  const auto seeds = random_seeds(rng, p, 9);
  gv::solve_options one, two;
  one.threads = 1;
  two.threads = 2;
  const auto a = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, one);
  const auto b = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, two);
  require_same_diagram(a, b, "threads 1 vs 2");
  require_same_diagram(a, gv::voronoi(gv::seq, p, seeds), "threads 1 vs seq");
  const auto src = std::vector<gv::source<float>>{{g.index(seeds[0]), 0.0f, 0}};
  const auto s1 = gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, 15.0f, one);
  const auto s2 = gv::bounded_solve(GEOVORONOI_TEST_POLICY(), p, src, 15.0f, two);
  CHECK(s1.voxel == s2.voxel);
  CHECK(s1.distance == s2.distance);
  CHECK(s1.label == s2.label);
}

}  // namespace gvsuite

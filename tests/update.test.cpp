// Incremental update after cuts (update.hpp): on many small random problems, a single cut and a
// sequence of cuts, the updated diagram equals a full solve of the cut problem bit for bit (distance
// bits, label, parent).
#include <doctest/doctest.h>

#include <geovoronoi/update.hpp>

#include "oracle.hpp"

#include <random>
#include <string>

namespace {
namespace gv = geovoronoi;
using namespace gvtest;

/// Voxels invalidated and updates that invalidated some, over all cases (the tests are not vacuous).
std::size_t total_invalidated = 0, nontrivial_updates = 0, total_updates = 0;

template <class D>
void require_identical(const D& a, const D& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.distance.size() == b.distance.size());
  REQUIRE(a.parent.size() == b.parent.size());
  gv::index_t bad = -1;
  for (gv::index_t v = 0; v < a.distance.size() && bad < 0; ++v)
    if (bits(a.distance[v]) != bits(b.distance[v]) || a.label[v] != b.label[v] || a.parent[v] != b.parent[v]) bad = v;
  if (bad >= 0)
    INFO("first mismatch at voxel " << bad << ": " << a.distance[bad] << "/" << a.label[bad] << "/" << a.parent[bad]
                                    << " vs " << b.distance[bad] << "/" << b.label[bad] << "/" << b.parent[bad]);
  CHECK(bad < 0);
}

/// Edges cut by a random "blade": those leaving voxels in a random box across a random axis-aligned
/// plane, plus a few random edges.
template <int Dim, int N>
gv::cut_set<Dim> random_blade(std::mt19937_64& rng, const gv::grid<Dim>& g, gv::connectivity<N> c) {
  gv::cut_builder<Dim> b(g, c);
  constexpr auto offs = gv::connectivity<N>::offsets();
  const int axis = int(rng() % Dim);
  const gv::index_t at = gv::index_t(rng() % std::uint64_t(g.extent(axis)));
  gv::coord<Dim> lo{}, hi{};
  for (int a = 0; a < Dim; ++a) {
    lo[a] = gv::index_t(rng() % std::uint64_t(g.extent(a)));
    hi[a] = lo[a] + gv::index_t(rng() % std::uint64_t(g.extent(a) + 1));
  }
  std::uniform_real_distribution<double> u(0, 1);
  const double sprinkle = u(rng) < 0.5 ? 0.0 : 0.05;
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto cv = g.coords(v);
    bool in_box = true;
    for (int a = 0; a < Dim; ++a) in_box = in_box && (a == axis || (cv[a] >= lo[a] && cv[a] <= hi[a]));
    for (int d = N / 2; d < N; ++d) {
      auto cu = cv;
      for (int a = 0; a < Dim; ++a) cu[a] += offs[d][a];
      if (!g.contains(cu)) continue;
      const bool crosses = cv[axis] <= at && cu[axis] > at;
      if ((in_box && crosses) || u(rng) < sprinkle) b.insert(v, d);
    }
  }
  return b.build();
}

template <class T, int Dim, class Metric, int N>
void update_case(std::mt19937_64& rng, int trial, bool cost, int steps) {
  const auto g = random_grid<Dim>(rng, trial % 2 == 1);
  const auto f = random_field<T>(rng, g.size(), trial % 3 != 2, trial % 4 == 0 ? 0.0 : 0.15, cost);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 1 + int(rng() % 5));
  if (seeds.empty()) return;
  // start from a problem that may already carry cuts
  gv::cut_set<Dim> all = trial % 3 == 0 ? random_cuts(rng, g, gv::connectivity<N>{}, 0.1)
                                        : gv::cut_set<Dim>(g, gv::connectivity<N>{});
  gv::cut_table table(all);
  auto d = gv::voronoi(gv::seq, gv::with_cuts(p, table), seeds, gv::solve_options{true});
  for (int s = 0; s < steps; ++s) {
    const auto added = trial % 2 == 0 ? random_blade(rng, g, gv::connectivity<N>{})
                                      : random_cuts(rng, g, gv::connectivity<N>{}, 0.08);
    all.merge(added);
    gv::cut_table next(all);
    const auto after = gv::with_cuts(p, next);
    const std::string what = "dim " + std::to_string(Dim) + " N " + std::to_string(N) + " trial " +
                             std::to_string(trial) + " step " + std::to_string(s);
    gv::update_stats stats;
    const auto updated = gv::update(gv::seq, after, d, added, &stats);
    const auto full = gv::voronoi(gv::seq, after, seeds, gv::solve_options{true});
    require_identical(updated, full, what);
    // the in-place form agrees
    auto again = d;
    gv::update_in_place(gv::seq, after, again, added);
    require_identical(again, full, what + " in place");
    CHECK(stats.invalidated <= std::size_t(g.size()));
    total_invalidated += stats.invalidated;
    nontrivial_updates += stats.invalidated > 0;
    ++total_updates;
    d = updated;
    table = std::move(next);
  }
}

template <class T, int Dim, int N>
void update_all_metrics(int trials, int steps) {
  std::mt19937_64 rng(777 + 13 * N + 100 * sizeof(T) + steps);
  for (int t = 0; t < trials; ++t) {
    update_case<T, Dim, gv::uniform, N>(rng, t, false, steps);
    update_case<T, Dim, gv::min_stiffness, N>(rng, t, false, steps);
    update_case<T, Dim, gv::mean_stiffness, N>(rng, t, false, steps);
    update_case<T, Dim, gv::mean_cost, N>(rng, t, true, steps);
    update_case<T, Dim, destination_cost, N>(rng, t, false, steps);
  }
}

}  // namespace

TEST_CASE("update after one cut equals a full recompute, bit for bit (distances, labels, parents)") {
  update_all_metrics<float, 2, 4>(60, 1);
  update_all_metrics<float, 2, 8>(60, 1);
  update_all_metrics<double, 2, 8>(30, 1);
  update_all_metrics<float, 3, 6>(60, 1);
  update_all_metrics<float, 3, 18>(40, 1);
  update_all_metrics<float, 3, 26>(60, 1);
  update_all_metrics<double, 3, 26>(30, 1);
  MESSAGE("updates: " << total_updates << ", of which " << nontrivial_updates << " invalidated voxels ("
                      << total_invalidated << " in all)");
  CHECK(nontrivial_updates > total_updates / 3);
}

TEST_CASE("update after a sequence of cuts equals a full recompute after each") {
  update_all_metrics<float, 2, 8>(30, 4);
  update_all_metrics<float, 3, 6>(30, 4);
  update_all_metrics<float, 3, 26>(30, 4);
  update_all_metrics<double, 3, 26>(15, 3);
}

TEST_CASE("update: a cut that crosses no tree edge changes nothing; bad input is refused") {
  const gv::grid<2> g({6, 1});
  const std::vector<float> f(6, 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const std::vector<gv::coord<2>> seeds{{0, 0}};
  const auto d = gv::voronoi(gv::seq, p, seeds, gv::solve_options{true});
  // cut the edge (3,0)-(4,0): everything beyond x = 3 becomes unreachable
  gv::cut_set<2> c(g, gv::connectivity<4>{});
  c.insert(g.index({3, 0}), 2);
  const gv::cut_table t(c);
  const auto pc = gv::with_cuts(p, t);
  gv::update_stats s;
  const auto u = gv::update(gv::seq, pc, gv::voronoi(gv::seq, p, seeds, gv::solve_options{true}), c, &s);
  CHECK(s.cut_tree_edges == 1);
  CHECK(s.invalidated == 2);
  CHECK(u.label[g.index({4, 0})] == gv::no_label);
  CHECK(u.label[g.index({3, 0})] == 0);
  CHECK(u.parent[g.index({5, 0})] == gv::no_index);
  // no parents: refused
  const auto bare = gv::voronoi(gv::seq, p, seeds);
  CHECK_THROWS_WITH_AS(gv::update(gv::seq, pc, bare, c), doctest::Contains("with_parent"), std::invalid_argument);
  // a change that the problem does not carry: refused
  gv::cut_set<2> other(g, gv::connectivity<4>{});
  other.insert(g.index({1, 0}), 2);
  CHECK_THROWS_WITH_AS(gv::update(gv::seq, pc, d, other), doctest::Contains("not cut in the problem"),
                       std::invalid_argument);
}

// Incremental update after cuts (update.hpp): on many small random problems, a single cut and a
// sequence of cuts, the updated diagram equals a full solve of the cut problem bit for bit (distance
// bits, label, parent).
#include <doctest/doctest.h>

#include <geovoronoi/update.hpp>

#include "support/oracle.hpp"

#include <algorithm>
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

namespace {

/// Carving: a random box of voxels (never a seed) leaves the domain; on a problem with or without
/// cuts, the update equals a full solve of the carved problem.
template <class T, int Dim, class Metric, int N>
void carve_case(std::mt19937_64& rng, int trial, bool cost, int steps) {
  const auto g = random_grid<Dim>(rng, trial % 2 == 1);
  auto f = random_field<T>(rng, g.size(), trial % 3 != 2, trial % 4 == 0 ? 0.0 : 0.1, cost);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 1 + int(rng() % 4));
  if (seeds.empty()) return;
  std::vector<gv::index_t> seed_voxels;
  for (const auto& s : seeds) seed_voxels.push_back(g.index(s));
  const gv::cut_table table(trial % 2 == 0 ? random_cuts(rng, g, gv::connectivity<N>{}, 0.1)
                                           : gv::cut_set<Dim>(g, gv::connectivity<N>{}));
  auto run = [&](const auto& problem_of) {
    auto d = gv::voronoi(gv::seq, problem_of(), seeds, gv::solve_options{true});
    for (int s = 0; s < steps; ++s) {
      gv::carving c;
      gv::coord<Dim> lo{}, ext{};
      for (int a = 0; a < Dim; ++a) {
        lo[a] = gv::index_t(rng() % std::uint64_t(g.extent(a)));
        ext[a] = 1 + gv::index_t(rng() % 3);
      }
      for (gv::index_t v = 0; v < g.size(); ++v) {
        const auto cv = g.coords(v);
        bool in = true;
        for (int a = 0; a < Dim; ++a) in = in && cv[a] >= lo[a] && cv[a] < lo[a] + ext[a];
        if (in && std::find(seed_voxels.begin(), seed_voxels.end(), v) == seed_voxels.end()) {
          f[std::size_t(v)] = cost ? T(-1) : T(0);
          c.voxels.push_back(v);
        }
      }
      const auto after = problem_of();
      const auto updated = gv::update(gv::seq, after, d, c);
      const auto full = gv::voronoi(gv::seq, after, seeds, gv::solve_options{true});
      require_identical(updated, full,
                        "carve dim " + std::to_string(Dim) + " N " + std::to_string(N) + " trial " +
                            std::to_string(trial) + " step " + std::to_string(s));
      d = updated;
    }
  };
  // the problems point at f, so they see each carving
  if (trial % 2 == 0)
    run([&] { return gv::with_cuts(gv::make_problem(g, f, Metric{}, gv::connectivity<N>{}), table); });
  else
    run([&] { return gv::make_problem(g, f, Metric{}, gv::connectivity<N>{}); });
}

template <class T, int Dim, int N>
void carve_all_metrics(int trials, int steps) {
  std::mt19937_64 rng(999 + 7 * N + 100 * sizeof(T));
  for (int t = 0; t < trials; ++t) {
    carve_case<T, Dim, gv::uniform, N>(rng, t, false, steps);
    carve_case<T, Dim, gv::min_stiffness, N>(rng, t, false, steps);
    carve_case<T, Dim, gv::mean_cost, N>(rng, t, true, steps);
    carve_case<T, Dim, destination_cost, N>(rng, t, false, steps);
  }
}

}  // namespace

TEST_CASE("update after carving voxels (with and without cuts) equals a full recompute, bit for bit") {
  carve_all_metrics<float, 2, 4>(40, 3);
  carve_all_metrics<float, 2, 8>(40, 3);
  carve_all_metrics<float, 3, 6>(40, 3);
  carve_all_metrics<float, 3, 26>(40, 3);
  carve_all_metrics<double, 3, 18>(20, 3);
}

TEST_CASE("update: a carving that keeps a voxel inside or removes a seed is refused") {
  const gv::grid<2> g({5, 1});
  std::vector<float> f(5, 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}}, gv::solve_options{true});
  CHECK_THROWS_WITH_AS(gv::update(gv::seq, p, d, gv::carving{{2}}), doctest::Contains("still inside"),
                       std::invalid_argument);
  f[0] = 0.0f;
  CHECK_THROWS_WITH_AS(gv::update(gv::seq, p, d, gv::carving{{0}}), doctest::Contains("seed 0"), std::invalid_argument);
  f[0] = 1.0f;
  f[3] = 0.0f;
  const auto u = gv::update(gv::seq, p, d, gv::carving{{3}});
  CHECK(u.label[3] == gv::no_label);
  CHECK(u.label[4] == gv::no_label);
  CHECK(u.parent[2] == 1);
}

// ---- field edits, added voxels, node edits, and all of them together (update_edits.hpp) ----------
#include "support/update_edits.hpp"

namespace {
template <class T, int Dim, int N>
void edits_everywhere(int trials, int steps, unsigned kinds) {
  gvtest::edit_all_metrics<T, Dim, N>(gv::seq, trials, steps, kinds);
}
void edits_all_connectivities(int trials, int steps, unsigned kinds) {
  edits_everywhere<float, 2, 4>(trials, steps, kinds);
  edits_everywhere<float, 2, 8>(trials, steps, kinds);
  edits_everywhere<double, 2, 8>(trials / 2, steps, kinds);
  edits_everywhere<float, 3, 6>(trials, steps, kinds);
  edits_everywhere<float, 3, 18>(trials, steps, kinds);
  edits_everywhere<float, 3, 26>(trials, steps, kinds);
  edits_everywhere<double, 3, 26>(trials / 2, steps, kinds);
}
}  // namespace

TEST_CASE("update after field edits (stiffer, softer, mixed, no-op) equals a full recompute, bit for bit") {
  const auto before = gvtest::totals();
  edits_all_connectivities(60, 1, gvtest::field_edit);
  const auto after = gvtest::totals();
  MESSAGE("updates " << after.updates - before.updates << ", invalidated " << after.invalidated - before.invalidated
                     << ", lowered " << after.lowered - before.lowered);
  CHECK(after.invalidated > before.invalidated);
  CHECK(after.lowered > before.lowered);
}

TEST_CASE("update after adding voxels to the domain equals a full recompute, bit for bit") {
  const auto before = gvtest::totals();
  edits_all_connectivities(30, 2, gvtest::add_edit);
  CHECK(gvtest::totals().lowered > before.lowered);
}

TEST_CASE("update after node edits (add, remove, move, reorder) equals a full solve with the new node list") {
  const auto before = gvtest::totals();
  edits_all_connectivities(40, 2, gvtest::node_edits);
  const auto after = gvtest::totals();
  CHECK(after.sources > before.sources);
  CHECK(after.removed > before.removed);
}

TEST_CASE("update after sequences of combined edits (cuts, carving, added, field, nodes) equals a full recompute") {
  edits_all_connectivities(40, 4, gvtest::field_edit | gvtest::carve_edit | gvtest::add_edit | gvtest::node_edits |
                                      gvtest::cut_edit);
  const auto& t = gvtest::totals();
  MESSAGE("all edit tests: " << t.updates << " updates, " << t.invalidated << " voxels invalidated, " << t.lowered
                             << " lowered, " << t.sources << " sources queued, " << t.removed << " nodes removed, " << t.repairs
                             << " repair rounds");
}

TEST_CASE("update: labels renumber as in a full solve with the new node list") {
  // a line of 9 voxels, nodes at x = 1 and x = 7
  const gv::grid<2> g({9, 1});
  std::vector<float> f(9, 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{1, 0}, {7, 0}}, gv::solve_options{true});
  CHECK(d.label[4] == 0);  // the tie at x = 4 goes to the lower label
  // insert a node at x = 4, position 0: the old labels move up by one; old ties keep their outcome
  gv::change<2> c;
  c.nodes = {gv::node_edit<2>::add({4, 0}, 0)};
  const auto u = gv::update(gv::seq, p, d, c);
  CHECK(u.seeds == std::vector<gv::index_t>{4, 1, 7});
  CHECK(u.label[0] == 1);
  CHECK(u.label[4] == 0);
  CHECK(u.label[8] == 2);
  CHECK(u.label[2] == 1);  // distance 1 to x = 1, 2 to x = 4
  // remove node 0 (x = 4) again: back to the first diagram
  gv::change<2> r;
  r.nodes = {gv::node_edit<2>::remove(0)};
  const auto back = gv::update(gv::seq, p, u, r);
  gvtest::require_same_diagram(back, d, "remove");
  // move node 1 (x = 7) to x = 5: its label stays 1
  gv::change<2> m;
  m.nodes = {gv::node_edit<2>::move(1, {5, 0})};
  gv::update_stats s;
  const auto moved = gv::update(gv::seq, p, d, m, &s);
  CHECK(moved.seeds == std::vector<gv::index_t>{1, 5});
  CHECK(moved.label[8] == 1);
  CHECK(moved.label[3] == 0);  // the tie at x = 3 goes to label 0
  CHECK(s.nodes_removed == 1);
  CHECK(s.sources_added == 1);
}

TEST_CASE("update: bad changes are refused with a message naming the voxel, node or edit") {
  const gv::grid<2> g({6, 2});
  std::vector<float> f(12, 1.0f);
  f[g.index({5, 1})] = 0.0f;
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {3, 1}}, gv::solve_options{true});
  auto refused = [&](const gv::change<2>& c, const char* text) {
    INFO(text);
    CHECK_THROWS_WITH_AS(gv::update(gv::seq, p, d, c), doctest::Contains(text), std::invalid_argument);
  };
  gv::change<2> c;
  c.added = {g.index({5, 1})};
  refused(c, "added voxel (5, 1) is outside the domain");
  c = {};
  c.restiffened = {12};
  refused(c, "restiffened voxel 12 is outside the grid");
  c = {};
  c.carved = {-1};
  refused(c, "carved voxel -1 is outside the grid");
  c = {};
  c.nodes = {gv::node_edit<2>::remove(2)};
  refused(c, "node edit 0 names node position 2");
  c.nodes = {gv::node_edit<2>::add({1, 0}), gv::node_edit<2>::move(5, {2, 0})};
  refused(c, "node edit 1 names node position 5");
  c.nodes = {gv::node_edit<2>::add({6, 0})};
  refused(c, "outside the grid");
  c.nodes = {gv::node_edit<2>::add({5, 1})};
  refused(c, "node 2 at (5, 1) (voxel 11) lies on a masked voxel");
  c.nodes = {gv::node_edit<2>::move(0, {3, 1})};
  refused(c, "share the voxel");
  c.nodes = {gv::node_edit<2>::remove(0), gv::node_edit<2>::remove(0)};
  refused(c, "node list is empty");
  // a node whose voxel leaves the domain must be removed, not restiffened or carved away
  f[g.index({3, 1})] = 0.0f;
  c = {};
  c.restiffened = {g.index({3, 1})};
  refused(c, "node 1 at (3, 1) (voxel 9) lies on a masked voxel");
  c = {};
  c.carved = {g.index({3, 1})};
  refused(c, "removes seed 1");
  // ... which works
  c.nodes = {gv::node_edit<2>::remove(1)};
  const auto u = gv::update(gv::seq, p, d, c);
  gvtest::require_same_diagram(u, gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}}, gv::solve_options{true}),
                               "carve a removed node");
  // a cut in a change applied to a problem without cuts
  f[g.index({3, 1})] = 1.0f;
  gv::cut_set<2> cut(g, gv::connectivity<8>{});
  constexpr auto offs = gv::connectivity<8>::offsets();
  for (int k = 0; k < 8; ++k)
    if (offs[k][0] == 1 && offs[k][1] == 0) cut.insert(0, k);
  c = {};
  c.cut = cut;
  refused(c, "not cut in the problem after it");
}

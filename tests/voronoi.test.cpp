// Tests of geovoronoi/voronoi.hpp: the front end's argument checks (every bad input the issue lists
// must throw std::invalid_argument naming the problem), metric errors raised by the sequential
// backend, properties of the diagrams it returns beyond the shared backend suite (parents realise
// the keys, seeds are exactly 0), and seeds_from_world's rounding.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>

#include "support/core_helpers.hpp"
#include "support/oracle.hpp"

#include <random>
#include <vector>

namespace {
namespace gv = geovoronoi;
using gvcore::inf_v;
using gvcore::nan_v;

template <int Dim>
using seeds_t = std::vector<gv::coord<Dim>>;

// ---- bad input --------------------------------------------------------------------------------------

TEST_CASE("voronoi: an empty seed list is rejected") {
  const gv::grid<2> g({4, 3});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<2>{}), "seed", "empty");
}

TEST_CASE("voronoi: a seed outside the grid is rejected and named") {
  const gv::grid<3> g({5, 4, 3});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{0, 0, 0}, {1, 1, 1}, {5, 0, 0}}), "seed 2", "outside", "(5, 0, 0)");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{-1, 0, 0}}), "seed 0", "outside");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{0, 0, 0}, {0, 4, 0}}), "seed 1", "outside");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{0, 0, 0}, {4, 3, 2}, {0, 0, -1}}), "seed 2", "outside");
  // the same seeds one step inside are fine
  CHECK_NOTHROW(gv::voronoi(gv::seq, p, seeds_t<3>{{0, 0, 0}, {4, 3, 2}}));
}

template <class Metric, class T>
void check_masked_seed(T bad_value) {
  const gv::grid<2> g({6, 5});
  std::vector<T> f(g.size(), T(1));
  f[g.index({3, 2})] = bad_value;
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<4>{});
  INFO("field value " << bad_value);
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<2>{{0, 0}, {3, 2}}), "seed 1", "masked", "(3, 2)");
  // moving the seed off the masked voxel makes the input valid
  CHECK_NOTHROW(gv::voronoi(gv::seq, p, seeds_t<2>{{0, 0}, {3, 3}}));
}

// a user metric without inside(): the stiffness rule applies
struct plain_user_metric {
  template <class T>
  T operator()(T length, T, T) const noexcept {
    return length + length;
  }
};

TEST_CASE("voronoi: a seed on a masked voxel is rejected for every metric's mask rule") {
  for (float bad : {0.0f, -0.0f, -1.0f, -1e30f, nan_v<float>, -inf_v<float>}) {
    check_masked_seed<gv::uniform>(bad);
    check_masked_seed<gv::min_stiffness>(bad);
    check_masked_seed<gv::mean_stiffness>(bad);
    check_masked_seed<plain_user_metric>(bad);
  }
  for (double bad : {0.0, -2.0, nan_v<double>}) check_masked_seed<gv::min_stiffness>(bad);
  for (float bad : {-1.0f, -1e-30f, nan_v<float>, inf_v<float>, -inf_v<float>}) check_masked_seed<gv::mean_cost>(bad);
  for (double bad : {-0.5, nan_v<double>, inf_v<double>}) check_masked_seed<gv::mean_cost>(bad);
  // a user metric with its own rule (0 < value < 100)
  check_masked_seed<gvtest::destination_cost>(100.0f);
  check_masked_seed<gvtest::destination_cost>(0.0f);
}

TEST_CASE("voronoi: values the mask rules keep inside are accepted as seeds") {
  // zero cost is inside the cost rule; +inf stiffness is inside the stiffness rule
  const gv::grid<2> g({4, 4});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({2, 2})] = 0.0f;
  CHECK_NOTHROW(gv::voronoi(gv::seq, gv::make_problem(g, f, gv::mean_cost{}, gv::connectivity<4>{}), seeds_t<2>{{2, 2}}));
  f[g.index({2, 2})] = inf_v<float>;
  CHECK_NOTHROW(gv::voronoi(gv::seq, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{}), seeds_t<2>{{2, 2}}));
}

TEST_CASE("voronoi: two seeds on one voxel are rejected, naming both") {
  const gv::grid<3> g({4, 4, 4});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<6>{});
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{1, 2, 3}, {0, 0, 0}, {1, 2, 3}}), "seeds 0 and 2", "share", "(1, 2, 3)");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<3>{{3, 3, 3}, {0, 1, 0}, {2, 2, 2}, {0, 1, 0}}), "seeds 1 and 3", "share");
}

TEST_CASE("voronoi: a field whose size does not match the grid is rejected") {
  const gv::grid<2> g({5, 4});
  const std::vector<float> small(19, 1.0f), big(21, 1.0f), empty;
  GV_CHECK_INVALID(gv::make_problem(g, small, gv::min_stiffness{}, gv::connectivity<8>{}), "field", "19", "20");
  GV_CHECK_INVALID(gv::make_problem(g, big, gv::min_stiffness{}, gv::connectivity<8>{}), "field", "21", "20");
  GV_CHECK_INVALID(gv::make_problem(g, empty, gv::min_stiffness{}, gv::connectivity<8>{}), "field");
  // the all-in-one overload checks too
  GV_CHECK_INVALID(gv::voronoi(gv::seq, g, small, seeds_t<2>{{0, 0}}, gv::uniform{}, gv::connectivity<4>{}), "field");
  // images and views over other extents (same voxel count, transposed)
  const gv::image<float, 2> transposed(gv::grid<2>({4, 5}), 1.0f);
  GV_CHECK_INVALID(gv::make_problem(g, transposed, gv::min_stiffness{}, gv::connectivity<8>{}), "field", "extents");
  GV_CHECK_INVALID(gv::make_problem(g, transposed.view(), gv::min_stiffness{}, gv::connectivity<8>{}), "field", "extents");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, g, transposed, seeds_t<2>{{0, 0}}, gv::uniform{}, gv::connectivity<4>{}), "extents");
  const gv::image<float, 2> right(g, 1.0f);
  CHECK_NOTHROW(gv::make_problem(g, right, gv::min_stiffness{}, gv::connectivity<8>{}));
}

TEST_CASE("geodesic_solve: bad sources are rejected and named") {
  const gv::grid<2> g({6, 6});
  std::vector<double> f(g.size(), 1.0);
  f[g.index({5, 5})] = 0.0;
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  using S = gv::source<double>;
  const gv::index_t a = g.index({1, 1}), b = g.index({4, 2});
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{}), "source", "empty");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {b, -1.0, 1}}), "source 1", "initial distance");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, inf_v<double>, 0}}), "source 0", "initial distance");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {b, nan_v<double>, 1}}), "source 1", "initial distance");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {b, 0.0, -3}}), "source 1", "negative label");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{b, 0.0, 0}, {a, 1.0, 1}, {b, 2.0, 2}}), "sources 0 and 2", "share");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {36, 0.0, 1}}), "source 1", "outside");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{-1, 0.0, 0}}), "source 0", "outside");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, std::vector<S>{{g.index({5, 5}), 0.0, 0}}), "source 0", "masked");
  // repeated labels and non-zero initial distances are allowed
  CHECK_NOTHROW(gv::geodesic_solve(gv::seq, p, std::vector<S>{{a, 2.5, 7}, {b, 0.0, 7}}));
  // the same checks guard the bounded solve
  GV_CHECK_INVALID(gv::bounded_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {b, -0.5, 1}}, 3.0), "source 1", "initial distance");
  GV_CHECK_INVALID(gv::bounded_solve(gv::seq, p, std::vector<S>{{a, 0.0, 0}, {a, 0.0, 1}}, 3.0), "share");
}

TEST_CASE("solvers: a NaN radius or NaN max_distance is rejected") {
  const gv::grid<2> g({5, 5});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<4>{});
  const std::vector<gv::source<float>> s{{0, 0.0f, 0}};
  GV_CHECK_INVALID(gv::bounded_solve(gv::seq, p, s, nan_v<float>), "radius", "NaN");
  GV_CHECK_INVALID(gv::single_source(gv::seq, p, gv::coord<2>{1, 1}, nan_v<float>), "radius", "NaN");
  GV_CHECK_INVALID(gv::single_source(gv::seq, p, gv::coord<2>{5, 1}), "source", "outside");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t<2>{{0, 0}}, gv::solve_options{false, nan_v<double>}), "max_distance");
  GV_CHECK_INVALID(gv::geodesic_solve(gv::seq, p, s, gv::solve_options{true, nan_v<double>}), "max_distance");
  // an infinite radius is the unbounded solve, not an error
  CHECK(gv::bounded_solve(gv::seq, p, s, inf_v<float>).size() == 25);
}

TEST_CASE("insert_queries: bad queries and foreign diagrams are rejected") {
  const gv::grid<3> g({4, 3, 3});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({2, 1, 1})] = -1.0f;
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<18>{});
  const auto d = gv::voronoi(gv::seq, p, seeds_t<3>{{0, 0, 0}});
  // by index
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, d, std::vector<gv::index_t>{5, g.size()}), "query 1", "outside");
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, d, std::vector<gv::index_t>{-1}), "query 0", "outside");
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, d, std::vector<gv::index_t>{0, 1, g.index({2, 1, 1})}), "query 2", "masked");
  // by coordinates
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, d, seeds_t<3>{{1, 1, 1}, {0, 3, 0}}), "query 1", "outside");
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, d, seeds_t<3>{{2, 1, 1}}), "query 0", "masked");
  GV_CHECK_INVALID(gv::insert_query(gv::seq, p, d, gv::coord<3>{2, 1, 1}), "masked");
  GV_CHECK_INVALID(gv::insert_query(gv::seq, p, d, gv::coord<3>{0, 0, -1}), "outside");
  // a diagram computed on another grid: other extents, other spacing, other origin, or empty
  const gv::grid<3> other_ext({3, 4, 3});
  const gv::grid<3> other_sp({4, 3, 3}, {1.0, 1.0, 2.0});
  const gv::grid<3> other_or({4, 3, 3}, {1.0, 1.0, 1.0}, {0.0, 0.5, 0.0});
  for (const auto& og : {other_ext, other_sp, other_or}) {
    const std::vector<float> of(og.size(), 1.0f);
    const auto op = gv::make_problem(og, of, gv::min_stiffness{}, gv::connectivity<18>{});
    const auto od = gv::voronoi(gv::seq, op, seeds_t<3>{{0, 0, 0}});
    GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, od, std::vector<gv::index_t>{1}), "another grid");
    GV_CHECK_INVALID(gv::insert_query(gv::seq, p, od, gv::coord<3>{1, 0, 0}), "another grid");
  }
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, gv::diagram<float, 3>{}, std::vector<gv::index_t>{1}), "another grid");
  // a diagram whose label image does not match its distance image
  auto broken = d;
  broken.label = gv::image<gv::label_t, 3>(other_ext, 0);
  GV_CHECK_INVALID(gv::insert_queries(gv::seq, p, broken, std::vector<gv::index_t>{1}), "another grid");
  // and the valid call works
  CHECK(gv::insert_queries(gv::seq, p, d, std::vector<gv::index_t>{1, 0}).size() == 2);
}

// ---- metric errors ------------------------------------------------------------------------------------

// A user metric that returns a negative weight on edges towards higher field values.
struct negative_uphill {
  template <class T>
  T operator()(T length, T from, T to) const noexcept {
    return to > from ? -length : length;
  }
};
// A user metric that returns NaN on every edge touching a voxel of value 3.
struct nan_on_three {
  template <class T>
  T operator()(T length, T from, T to) const noexcept {
    return (from == T(3) || to == T(3)) ? std::numeric_limits<T>::quiet_NaN() : length;
  }
};

template <class Metric>
void check_metric_error() {
  const gv::grid<2> g({8, 6});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({5, 3})] = 3.0f;  // positive: inside the (default) stiffness domain
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<8>{});
  CHECK_THROWS_AS(gv::voronoi(gv::seq, p, seeds_t<2>{{0, 0}}), gv::metric_error);
  CHECK_THROWS_AS(gv::voronoi(gv::seq, p, seeds_t<2>{{7, 5}, {0, 0}}, gv::solve_options{true}), gv::metric_error);
  CHECK_THROWS_AS(gv::single_source(gv::seq, p, gv::coord<2>{2, 2}), gv::metric_error);
  CHECK_THROWS_AS(gv::bounded_solve(gv::seq, p, std::vector<gv::source<float>>{{0, 0.0f, 0}}, 100.0f), gv::metric_error);
  // insert a query into a diagram built with a sound metric: the query's search meets the bad edge
  const auto good = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, good, seeds_t<2>{{0, 0}});
  CHECK_THROWS_AS(gv::insert_query(gv::seq, p, d, gv::coord<2>{5, 2}), gv::metric_error);
  // metric_error is a geovoronoi::error and says what went wrong
  try {
    gv::voronoi(gv::seq, p, seeds_t<2>{{0, 0}});
  } catch (const gv::error& e) {
    CHECK(gvcore::contains(e.what(), "weight"));
  }
}

TEST_CASE("seq: a user metric returning a negative or NaN weight throws metric_error") {
  check_metric_error<negative_uphill>();
  check_metric_error<nan_on_three>();
}

// ---- properties of the diagrams ------------------------------------------------------------------------

// Checks, independently of the library's parent computation: each reached non-source voxel's
// parent is a neighbour under the connectivity, has the same label, reproduces the distance exactly
// (fl(d(parent) + w(parent -> v)) with the metric evaluated on the stencil length), and is the
// lowest such neighbour; no neighbour offers a strictly smaller key (local optimality).
template <class P>
void check_parents(const P& p, const std::vector<gv::source<typename P::value_type>>& src,
                   const gv::diagram<typename P::value_type, P::dim>& d) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim;
  const auto& g = p.geometry;
  REQUIRE(d.parent.size() == g.size());
  CHECK(d.parent.geometry() == g);
  std::vector<char> is_src(static_cast<std::size_t>(g.size()), 0);
  for (const auto& s : src)
    if (d.label[s.voxel] == s.label && d.distance[s.voxel] == s.distance) is_src[s.voxel] = 1;
  constexpr auto offs = gv::connectivity<P::neighbours>::offsets();
  auto stencil_index = [&](const gv::coord<Dim>& from, const gv::coord<Dim>& to) {
    for (int k = 0; k < P::neighbours; ++k) {
      bool same = true;
      for (int a = 0; a < Dim; ++a) same = same && to[a] - from[a] == offs[k][a];
      if (same) return k;
    }
    return -1;
  };
  int failures = 0;
  for (gv::index_t v = 0; v < g.size() && failures < 5; ++v) {
    const gv::index_t u = d.parent[v];
    if (d.label[v] == gv::no_label || is_src[v]) {
      if (u != gv::no_index) ++failures;
      CHECK(u == gv::no_index);
      continue;
    }
    INFO("voxel " << v << " parent " << u);
    REQUIRE(u >= 0);
    REQUIRE(u < g.size());
    const auto cv = g.coords(v), cu = g.coords(u);
    const int k = stencil_index(cu, cv);
    REQUIRE(k >= 0);
    CHECK(d.label[u] == d.label[v]);
    const T w = p.metric(p.edges.length[k], p.field[u], p.field[v]);
    const T nd = d.distance[u] + w;
    if (gvtest::bits(nd) != gvtest::bits(d.distance[v])) ++failures;
    CHECK(gvtest::bits(nd) == gvtest::bits(d.distance[v]));
    // every neighbour: no strictly better key, and none of lower index realising the same key
    for (int j = 0; j < P::neighbours; ++j) {
      gv::coord<Dim> cn = cv;
      for (int a = 0; a < Dim; ++a) cn[a] -= offs[j][a];  // cn -> v uses offset j
      if (!g.contains(cn)) continue;
      const gv::index_t n = g.index(cn);
      if (d.label[n] == gv::no_label) continue;
      const T nw = p.metric(p.edges.length[j], p.field[n], p.field[v]);
      const T cand = d.distance[n] + nw;
      const bool better = cand < d.distance[v] || (cand == d.distance[v] && d.label[n] < d.label[v]);
      CHECK_FALSE(better);
      if (n < u && cand == d.distance[v] && d.label[n] == d.label[v]) {
        ++failures;
        CHECK(n >= u);  // the parent is the lowest-index realising neighbour
      }
    }
  }
  CHECK(failures == 0);
}

template <class T, int Dim, class Metric, int N>
void property_trials(std::uint64_t seed, int trials, bool cost) {
  std::mt19937_64 rng(seed);
  for (int t = 0; t < trials; ++t) {
    const auto g = gvtest::random_grid<Dim>(rng, t % 2 == 0);
    const auto f = gvtest::random_field<T>(rng, g.size(), t % 3 == 0, 0.15, cost);
    const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
    const auto seeds = gvtest::random_seeds(rng, p, 1 + int(rng() % 4));
    if (seeds.empty()) continue;
    const auto d = gv::voronoi(gv::seq, p, seeds, gv::solve_options{true});
    // seeds: distance exactly +0, own label, no parent; seeds list kept in order
    REQUIRE(d.seeds.size() == seeds.size());
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      CHECK(d.seeds[i] == g.index(seeds[i]));
      CHECK(gvtest::bits(d.distance(seeds[i])) == gvtest::bits(T(0)));
      CHECK(d.label(seeds[i]) == gv::label_t(i));
      CHECK(d.parent(seeds[i]) == gv::no_index);
    }
    check_parents(p, gvtest::as_sources(p, seeds), d);
    // asking for parents changes nothing else; not asking leaves the parent image empty
    const auto plain = gv::voronoi(gv::seq, p, seeds);
    CHECK(plain.parent.size() == 0);
    CHECK(plain.label.values() == d.label.values());
    bool same = true;
    for (gv::index_t v = 0; v < g.size(); ++v) same = same && gvtest::bits(plain.distance[v]) == gvtest::bits(d.distance[v]);
    CHECK(same);
  }
}

TEST_CASE("voronoi with_parent: parents carry the label and reproduce the distance exactly") {
  property_trials<float, 2, gv::min_stiffness, 8>(11, 25, false);
  property_trials<float, 2, gvtest::destination_cost, 4>(12, 25, false);  // asymmetric: checks the edge direction
  property_trials<double, 2, gv::mean_stiffness, 8>(13, 15, false);
  property_trials<float, 3, gv::mean_cost, 6>(14, 20, true);
  property_trials<float, 3, gvtest::destination_cost, 18>(15, 20, false);
  property_trials<double, 3, gv::min_stiffness, 26>(16, 15, false);
}

TEST_CASE("geodesic_solve with_parent: a source overtaken by a nearer one gets a parent") {
  const gv::grid<2> g({5, 1});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const std::vector<gv::source<float>> src{{1, 10.0f, 0}, {3, 0.0f, 1}};
  const auto d = gv::geodesic_solve(gv::seq, p, src, gv::solve_options{true});
  CHECK(d.distance[1] == 2.0f);
  CHECK(d.label[1] == 1);
  CHECK(d.parent[1] == 2);
  CHECK(d.parent[3] == gv::no_index);
  CHECK(d.parent[0] == 1);
  check_parents(p, src, d);
  // labels may repeat: the nearest source's label wins, ties to the lower label
  const std::vector<gv::source<float>> same{{0, 0.0f, 4}, {4, 0.0f, 2}};
  const auto e = gv::geodesic_solve(gv::seq, p, same, gv::solve_options{true});
  CHECK(e.label.values() == std::vector<gv::label_t>{4, 4, 2, 2, 2});
  check_parents(p, same, e);
}

TEST_CASE("geodesic_solve: an initial distance of -0 behaves exactly like +0") {
  // -0.0 passes the ">= 0" check; its bit pattern must not be used as a huge key
  const gv::grid<2> g({7, 3});
  const std::vector<float> f(g.size(), 2.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const std::vector<gv::source<float>> pos{{g.index({1, 1}), 0.0f, 0}, {g.index({5, 1}), 0.0f, 1}};
  const std::vector<gv::source<float>> neg{{g.index({1, 1}), -0.0f, 0}, {g.index({5, 1}), 0.0f, 1}};
  const auto a = gv::geodesic_solve(gv::seq, p, pos, gv::solve_options{true});
  const auto b = gv::geodesic_solve(gv::seq, p, neg, gv::solve_options{true});
  CHECK(a.label.values() == b.label.values());
  bool same = true;
  for (gv::index_t v = 0; v < g.size(); ++v) same = same && gvtest::bits(a.distance[v]) == gvtest::bits(b.distance[v]);
  CHECK(same);
  CHECK(a.parent.values() == b.parent.values());
  const auto sa = gv::bounded_solve(gv::seq, p, pos, 1.2f), sb = gv::bounded_solve(gv::seq, p, neg, 1.2f);
  CHECK(sa.voxel == sb.voxel);
  CHECK(sa.label == sb.label);
}

TEST_CASE("voronoi: the all-in-one overload equals the problem overload") {
  const gv::grid<3> g({6, 5, 4}, {1.0, 0.5, 2.0});
  std::mt19937_64 rng(3);
  const auto f = gvtest::random_field<float>(rng, g.size(), false, 0.1, false);
  const auto p = gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<18>{});
  const auto seeds = gvtest::random_seeds(rng, p, 3);
  REQUIRE(seeds.size() == 3);
  const auto a = gv::voronoi(gv::seq, p, seeds);
  const auto b = gv::voronoi(gv::seq, g, f, seeds, gv::mean_stiffness{}, gv::connectivity<18>{});
  const gv::image<float, 3> img(g, f);
  const auto c = gv::voronoi(gv::seq, g, img, seeds, gv::mean_stiffness{}, gv::connectivity<18>{});
  CHECK(a.label.values() == b.label.values());
  CHECK(a.label.values() == c.label.values());
  CHECK(a.distance.values() == b.distance.values());
  CHECK(a.distance.values() == c.distance.values());
  // and a different metric gives a different diagram (so the comparison above can fail)
  const auto e = gv::voronoi(gv::seq, g, f, seeds, gv::min_stiffness{}, gv::connectivity<18>{});
  CHECK(e.distance.values() != a.distance.values());
}

// ---- seeds_from_world ----------------------------------------------------------------------------------

TEST_CASE("seeds_from_world: rounds to the nearest voxel centre, halves up; outside is an error naming the point") {
  // power-of-two spacing and origin so that the halves are exact
  const gv::grid<2> g({4, 3}, {0.5, 2.0}, {10.0, -4.0});
  const std::vector<gv::point<2>> pts{
      {10.0, -4.0},    // voxel 0 centre
      {11.5, 0.0},     // (3, 2) centre
      {10.24, -3.1},   // just below the half: (0, 0)
      {10.25, -3.0},   // exactly halfway in x and y: rounds up to (1, 1)
      {9.75, -5.0},    // halfway below voxel 0: rounds up to (0, 0)
      {9.74, -5.01},   // past the half: (-1, -1), outside
      {11.75, 1.0},    // (4, 3), outside
      {nan_v<double>, 0.0},
      {1e300, -1e300},
      {1e30, 0.0},
  };
  const auto c = gv::seeds_from_world(g, std::vector<gv::point<2>>(pts.begin(), pts.begin() + 5));
  REQUIRE(c.size() == 5);
  CHECK(c[0] == gv::coord<2>{0, 0});
  CHECK(c[1] == gv::coord<2>{3, 2});
  CHECK(c[2] == gv::coord<2>{0, 0});
  CHECK(c[3] == gv::coord<2>{1, 1});
  CHECK(c[4] == gv::coord<2>{0, 0});
  // world() of a voxel maps back to it
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(gv::seeds_from_world(g, {g.world(g.coords(v))})[0] == g.coords(v));
  // a point whose voxel is not in the grid: the message names the seed and the point as given (a
  // clamped voxel such as (-1, 0) would say nothing about 1e30)
  GV_CHECK_INVALID(gv::seeds_from_world(g, {pts[0], pts[5]}), "seed 1", "world point (9.74, -5.01)", "outside");
  GV_CHECK_INVALID(gv::seeds_from_world(g, {pts[6]}), "seed 0", "world point (11.75, 1)", "index 4 along x");
  GV_CHECK_INVALID(gv::seeds_from_world(g, {pts[7]}), "seed 0", "world point (nan, 0)", "not a finite");
  GV_CHECK_INVALID(gv::seeds_from_world(g, {pts[8]}), "world point (1e+300, -1e+300)");
  GV_CHECK_INVALID(gv::seeds_from_world(g, {pts[0], pts[1], pts[9]}), "seed 2", "world point (1e+30, 0)");
  // the solvers take the rest; two points rounding to one voxel are two seeds on one voxel
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  CHECK_NOTHROW(gv::voronoi(gv::seq, p, gv::seeds_from_world(g, {pts[0], pts[1], pts[3]})));
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, gv::seeds_from_world(g, {pts[0], pts[2]})), "share");
}

TEST_CASE("seeds_from_world: 3D with an anisotropic grid") {
  const gv::grid<3> g({5, 6, 7}, {0.25, 1.0, 4.0}, {-1.0, 2.0, 8.0});
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> off(-0.49, 0.49);
  for (int t = 0; t < 200; ++t) {
    const gv::coord<3> c{gv::index_t(rng() % 5), gv::index_t(rng() % 6), gv::index_t(rng() % 7)};
    auto w = g.world(c);
    for (int a = 0; a < 3; ++a) w[a] += off(rng) * g.spacing(a);
    CHECK(gv::seeds_from_world(g, {w})[0] == c);
  }
  CHECK(gv::seeds_from_world(g, {{-1.125, 2.5, 10.0}})[0] == gv::coord<3>{0, 1, 1});  // halves up on every axis
}

TEST_CASE("seeds_from_world: a rotated grid (the direction matrix) and a diagram that keeps it") {
  // index x along world -z, index y along world +x, index z along world -y (a reflection-free rotation)
  const gv::grid<3> g({5, 6, 7}, {0.25, 1.0, 4.0}, {-1.0, 2.0, 8.0}, {0, 1, 0, 0, 0, -1, -1, 0, 0});
  std::mt19937_64 rng(9);
  std::uniform_real_distribution<double> off(-0.49, 0.49);
  for (int t = 0; t < 200; ++t) {
    const gv::coord<3> c{gv::index_t(rng() % 5), gv::index_t(rng() % 6), gv::index_t(rng() % 7)};
    gv::point<3> u{};  // an offset within the voxel, in index axes, turned into world axes
    for (int a = 0; a < 3; ++a) u[a] = off(rng) * g.spacing(a);
    auto w = g.world(c);
    for (int r = 0; r < 3; ++r)
      for (int a = 0; a < 3; ++a) w[r] += g.direction(r, a) * u[a];
    CHECK(gv::seeds_from_world(g, {w})[0] == c);
  }
  CHECK(g.world({1, 0, 0}) == gv::point<3>{-1.0, 2.0, 7.75});
  CHECK(g.world({0, 0, 1}) == gv::point<3>{-1.0, -2.0, 8.0});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<6>{});
  const auto d = gv::voronoi(gv::seq, p, gv::seeds_from_world(g, {{-1.0, 2.0, 7.75}}));
  CHECK(d.seeds[0] == g.index({1, 0, 0}));
  CHECK(d.geometry() == g);  // the direction travels into the results
  CHECK(d.distance.geometry().direction() == g.direction());
}

}  // namespace

// The sequential backend's sparse searches (bounded solve, insert-query) on grids larger than the
// shared suite's, where searches cross many pages of the paged scratch: paged scratch with pages of
// 64 and of 4 voxels against a label-correcting oracle of the pruned search, the dense solve and a
// full recompute, bit for bit;
// a workspace reused across calls, grids, value types and an exception; scratch memory that follows
// the search, not the grid.

#include <doctest/doctest.h>

#include "support/oracle.hpp"

#include <geovoronoi.hpp>

#include <algorithm>
#include <deque>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace eng = gv::detail::search;
using namespace gvtest;

template <class T, class Keys>
using scratch = eng::sparse_scratch<T, Keys>;

template <int Dim>
gv::grid<Dim> larger_grid(std::mt19937_64& rng) {
  gv::coord<Dim> e{};
  gv::point<Dim> s{};
  const int hi[3] = {Dim == 2 ? 150 : 70, Dim == 2 ? 60 : 20, 9};
  for (int a = 0; a < Dim; ++a) {
    e[a] = 1 + gv::index_t(rng() % std::uint64_t(hi[a]));
    s[a] = 0.5 + double(rng() % 4) * 0.25;
  }
  return gv::grid<Dim>(e, s, {});
}

template <class C1, class C2>
void require_same_cells(const C1& a, const C2& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.query == b.query);
  REQUIRE(a.offsets == b.offsets);
  CHECK(a.voxel == b.voxel);
  CHECK(a.owner == b.owner);
  bool same = a.distance.size() == b.distance.size();
  for (std::size_t i = 0; same && i < a.distance.size(); ++i) same = bits(a.distance[i]) == bits(b.distance[i]);
  CHECK(same);
}

template <class T>
void require_same_solution(const gv::sparse_solution<T>& a, const gv::sparse_solution<T>& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.voxel == b.voxel);
  CHECK(a.label == b.label);
  bool same = true;
  for (std::size_t i = 0; same && i < a.size(); ++i) same = bits(a.distance[i]) == bits(b.distance[i]);
  CHECK(same);
}

/// Reference for one query's new cell: a label-correcting search (FIFO work list, relaxed until
/// nothing changes) from q over the grid, entering v only with a distance below d(v). Written with
/// coordinates, independently of the engine's neighbour walk and scratch. Sorted by voxel.
template <class P>
std::vector<std::pair<gv::index_t, typename P::value_type>> pruned_cell(const P& p, const typename P::value_type* bound,
                                                                        gv::index_t q) {
  using T = typename P::value_type;
  const auto& g = p.geometry;
  constexpr auto offs = gv::connectivity<P::neighbours>::offsets();
  std::vector<T> dq(std::size_t(g.size()), std::numeric_limits<T>::infinity());
  std::deque<gv::index_t> work;
  if (T(0) < bound[q]) {
    dq[std::size_t(q)] = T(0);
    work.push_back(q);
  }
  while (!work.empty()) {
    const gv::index_t u = work.front();
    work.pop_front();
    const auto cu = g.coords(u);
    for (int k = 0; k < P::neighbours; ++k) {
      gv::coord<P::dim> cv = cu;
      for (int a = 0; a < P::dim; ++a) cv[a] += offs[k][a];
      if (!g.contains(cv)) continue;
      const gv::index_t v = g.index(cv);
      if (!p.inside(v)) continue;
      const T nd = dq[std::size_t(u)] + p.metric(p.edges.length[k], p.field[u], p.field[v]);
      if (nd < bound[v] && nd < dq[std::size_t(v)]) {
        dq[std::size_t(v)] = nd;
        work.push_back(v);
      }
    }
  }
  std::vector<std::pair<gv::index_t, T>> cell;
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (dq[std::size_t(v)] < std::numeric_limits<T>::infinity()) cell.push_back({v, dq[std::size_t(v)]});
  return cell;
}

/// Every cell of @p c against pruned_cell, bit for bit, with owners from @p d.
template <class P, class D>
void require_oracle_cells(const P& p, const D& d, const gv::query_cells<typename P::value_type>& c,
                          const std::string& what) {
  INFO(what);
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto expect = pruned_cell(p, d.distance.data(), c.query[i]);
    REQUIRE(c.cell_size(i) == expect.size());
    bool same = true;
    for (std::size_t j = 0; same && j < expect.size(); ++j) {
      const std::size_t at = c.offsets[i] + j;
      same = c.voxel[at] == expect[j].first && bits(c.distance[at]) == bits(expect[j].second) &&
             c.owner[at] == d.label[expect[j].first];
    }
    CHECK(same);
  }
}

/// Inside voxels in random order, the diagram's seeds first (their cells are empty).
template <class P>
std::vector<gv::index_t> some_queries(std::mt19937_64& rng, const P& p, const std::vector<gv::coord<P::dim>>& seeds,
                                      std::size_t count) {
  std::vector<gv::index_t> q;
  for (const auto& s : seeds) q.push_back(p.geometry.index(s));
  std::vector<gv::index_t> in;
  for (gv::index_t v = 0; v < p.geometry.size(); ++v)
    if (p.inside(v)) in.push_back(v);
  std::shuffle(in.begin(), in.end(), rng);
  for (std::size_t i = 0; i < count && i < in.size(); ++i) q.push_back(in[i]);
  return q;
}

template <class T, int Dim, class Metric, int N>
void insert_case(std::mt19937_64& rng, int trial) {
  const auto g = larger_grid<Dim>(rng);
  const auto f = random_field<T>(rng, g.size(), trial % 2 == 0, trial % 3 == 0 ? 0.0 : 0.15, false);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 1 + int(rng() % 6));
  if (seeds.empty()) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  const auto q = some_queries(rng, p, seeds, 30);
  gv::query_cells<T> a, b;
  scratch<T, eng::paged_keys<T, 6>> s64;
  scratch<T, eng::paged_keys<T, 2>> s4;
  eng::insert_queries(p, s64.keys, s64.heap, d, q.data(), q.size(), a);
  eng::insert_queries(p, s4.keys, s4.heap, d, q.data(), q.size(), b);
  const std::string what = "insert, dim " + std::to_string(Dim) + ", N " + std::to_string(N) + ", trial " +
                           std::to_string(trial) + ", grid of " + std::to_string(g.size());
  require_oracle_cells(p, d, a, what + ": pages of 64 vs the oracle");
  require_same_cells(b, a, what + ": pages of 4 vs pages of 64");
  require_same_cells(gv::insert_queries(gv::seq, p, d, q), a, what + ": front end vs pages of 64");
  for (std::size_t i = 0; i < seeds.size(); ++i) CHECK(a.cell_size(i) == 0);
  // the first non-seed query against a full recompute with it as an extra seed
  const std::size_t i = seeds.size();
  if (i >= q.size()) return;
  auto with_q = seeds;
  with_q.push_back(g.coords(q[i]));
  const auto full = gv::voronoi(gv::seq, p, with_q);
  std::vector<gv::index_t> expect;
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (full.label[v] == gv::label_t(seeds.size())) expect.push_back(v);
  REQUIRE(a.cell_size(i) == expect.size());
  for (std::size_t j = 0; j < expect.size(); ++j) {
    CHECK(a.voxel[a.offsets[i] + j] == expect[j]);
    CHECK(bits(a.distance[a.offsets[i] + j]) == bits(full.distance[expect[j]]));
  }
}

template <class T, int Dim, class Metric, int N>
void bounded_case(std::mt19937_64& rng, int trial) {
  const auto g = larger_grid<Dim>(rng);
  const auto f = random_field<T>(rng, g.size(), trial % 2 == 1, trial % 3 == 1 ? 0.0 : 0.1, false);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  auto src = as_sources(p, random_seeds(rng, p, 1 + int(rng() % 4)));
  if (src.empty()) return;
  for (auto& s : src) s.distance = T(rng() % 3) * T(0.5);  // initial distances, as Distance Ratio's frontier
  const T radius = T(0.5) + T(rng() % 12);
  scratch<T, eng::paged_keys<T, 6>> s64;
  scratch<T, eng::paged_keys<T, 2>> s4;
  const auto a = eng::bounded(p, s64.keys, s64.heap, src, radius);
  const auto b = eng::bounded(p, s4.keys, s4.heap, src, radius);
  const std::string what = "bounded, dim " + std::to_string(Dim) + ", trial " + std::to_string(trial);
  require_same_solution(b, a, what + ": pages of 4 vs pages of 64");
  // against the dense solve: exactly the voxels below the radius
  const auto dense = gv::geodesic_solve(gv::seq, p, src);
  std::size_t i = 0;
  for (gv::index_t v = 0; v < g.size(); ++v) {
    if (!(dense.distance[v] < radius)) continue;
    REQUIRE(i < a.size());
    CHECK(a.voxel[i] == v);
    CHECK(bits(a.distance[i]) == bits(dense.distance[v]));
    CHECK(a.label[i] == dense.label[v]);
    ++i;
  }
  CHECK(i == a.size());
}

TEST_CASE("seq sparse: insert-query with paged scratch equals the pruned-search oracle and a full recompute") {
  std::mt19937_64 rng(31);
  for (int t = 0; t < 12; ++t) {
    insert_case<float, 3, gv::min_stiffness, 26>(rng, t);
    insert_case<float, 3, gv::mean_stiffness, 6>(rng, t);
    insert_case<float, 2, gv::min_stiffness, 8>(rng, t);
    insert_case<double, 3, gv::min_stiffness, 18>(rng, t);
  }
}

TEST_CASE("seq sparse: bounded solve with pages of 4 and 64 equals the dense solve") {
  std::mt19937_64 rng(32);
  for (int t = 0; t < 12; ++t) {
    bounded_case<float, 3, gv::min_stiffness, 26>(rng, t);
    bounded_case<float, 2, gv::mean_stiffness, 4>(rng, t);
    bounded_case<double, 3, gv::min_stiffness, 6>(rng, t);
  }
}

TEST_CASE("seq sparse: a foreign diagram's -0, negative and NaN distances admit no voxel, as in the oracle") {
  std::mt19937_64 rng(34);
  for (int t = 0; t < 10; ++t) {
    const auto g = larger_grid<3>(rng);
    const auto f = random_field<float>(rng, g.size(), true, 0.0, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = random_seeds(rng, p, 2);
    auto d = gv::voronoi(gv::seq, p, seeds);
    const float odd[] = {-0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(), 0.0f};
    for (gv::index_t v = 0; v < g.size(); ++v)
      if (rng() % 5 == 0) d.distance[v] = odd[rng() % 4];
    std::vector<gv::index_t> q;
    for (gv::index_t v = 0; v < g.size(); v += 1 + gv::index_t(rng() % 97)) q.push_back(v);
    gv::query_cells<float> a;
    scratch<float, eng::paged_keys<float>> paged;
    eng::insert_queries(p, paged.keys, paged.heap, d, q.data(), q.size(), a);
    require_oracle_cells(p, d, a, "odd distances, trial " + std::to_string(t));
    CHECK(!a.voxel.empty());
  }
}

/// A metric that fails on one field value, to interrupt a search half-way.
struct fails_on_seven {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T to) const {
    return to == T(7) ? T(-1) : length;
  }
};

TEST_CASE("seq sparse: one workspace across calls, grids, value types and an exception") {
  std::mt19937_64 rng(33);
  gv::seq_workspace ws;
  for (int t = 0; t < 8; ++t) {
    // float insert-query on one grid, double bounded solve on another, float again on a third
    const auto g1 = larger_grid<3>(rng);
    const auto f1 = random_field<float>(rng, g1.size(), true, 0.1, false);
    const auto p1 = gv::make_problem(g1, f1, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto s1 = random_seeds(rng, p1, 3);
    if (!s1.empty()) {
      const auto d1 = gv::voronoi(gv::seq, p1, s1);
      const auto q1 = some_queries(rng, p1, s1, 10);
      require_same_cells(gv::insert_queries(gv::seq(ws), p1, d1, q1), gv::insert_queries(gv::seq, p1, d1, q1),
                         "workspace, float insert");
    }
    const auto g2 = larger_grid<2>(rng);
    const auto f2 = random_field<double>(rng, g2.size(), false, 0.1, false);
    const auto p2 = gv::make_problem(g2, f2, gv::mean_stiffness{}, gv::connectivity<8>{});
    const auto src2 = as_sources(p2, random_seeds(rng, p2, 2));
    if (!src2.empty()) {
      require_same_solution(gv::bounded_solve(gv::seq(ws), p2, src2, 6.0), gv::bounded_solve(gv::seq, p2, src2, 6.0),
                            "workspace, double bounded");
      const auto c = p2.geometry.coords(src2[0].voxel);
      require_same_solution(gv::single_source(gv::seq(ws), p2, c), gv::single_source(gv::seq, p2, c),
                            "workspace, double single source");
    }
    // a search stopped by an exception leaves the workspace usable
    const gv::grid<3> g3({30, 7, 5});
    std::vector<float> f3(std::size_t(g3.size()), 1.0f);
    f3[std::size_t(g3.index({20, 3, 2}))] = 7.0f;
    const auto p3 = gv::make_problem(g3, f3, fails_on_seven{}, gv::connectivity<6>{});
    CHECK_THROWS_AS(gv::bounded_solve(gv::seq(ws), p3, {{g3.index({18, 3, 2}), 0.0f, 0}}, 10.0f), gv::metric_error);
    if (!s1.empty()) {
      const auto d1 = gv::voronoi(gv::seq, p1, s1);
      const auto q1 = some_queries(rng, p1, s1, 10);
      require_same_cells(gv::insert_queries(gv::seq(ws), p1, d1, q1), gv::insert_queries(gv::seq, p1, d1, q1),
                         "workspace after an exception");
    }
  }
  CHECK(ws.bytes() > 0);
  ws.release();
  CHECK(ws.bytes() == 0);
}

TEST_CASE("seq sparse: scratch memory follows the search, not the grid") {
  // 4 Mi voxels; a diagram at distance 3 everywhere, so a query's cell is a small ball
  const gv::grid<3> g({256, 256, 64});
  const auto field = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, field, gv::uniform{}, gv::connectivity<26>{});
  gv::diagram<float, 3> d;
  d.distance = gv::image<float, 3>(g, 3.0f);
  d.label = gv::image<gv::label_t, 3>(g, 0);
  gv::seq_workspace ws;
  const auto cells = gv::insert_queries(gv::seq(ws), p, d, std::vector<gv::coord<3>>{{128, 128, 32}, {0, 0, 0}});
  CHECK(cells.cell_size(0) > 50);
  CHECK(cells.cell_size(0) < 400);
  const std::size_t table = std::size_t(g.size() / 64) * sizeof(void*);  // the per-grid allocation: 512 KiB
  const std::size_t grid_keys = std::size_t(g.size()) * 8;  // what a dense scratch would take: 32 MiB
  CHECK(ws.bytes() >= table);
  CHECK(ws.bytes() < table + 256 * 1024);
  CHECK(ws.bytes() < grid_keys / 32);
  const auto ball = gv::bounded_solve(gv::seq(ws), p, {{g.index({10, 250, 60}), 0.0f, 0}}, 4.0f);
  CHECK(ball.size() > 100);
  CHECK(ws.bytes() < table + 256 * 1024);
}

}  // namespace

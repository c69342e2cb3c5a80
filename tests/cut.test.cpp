// cut.hpp: the cut-edge set, its builder and its hash view, against a plain std::set of edges.
#include <geovoronoi/cut.hpp>

#include <doctest/doctest.h>

#include <random>
#include <set>
#include <type_traits>
#include <utility>

namespace gv = geovoronoi;

static_assert(std::is_trivially_copyable_v<gv::cut_view>, "cut_view goes to kernels by value");

namespace {

template <int Dim>
gv::grid<Dim> small_grid();
template <>
gv::grid<2> small_grid<2>() { return gv::grid<2>({5, 4}); }
template <>
gv::grid<3> small_grid<3>() { return gv::grid<3>({4, 3, 5}); }

/// Every edge of the grid as (u, d, v), d any direction.
template <int Dim, int N>
std::vector<std::array<gv::index_t, 3>> all_edges(const gv::grid<Dim>& g) {
  std::vector<std::array<gv::index_t, 3>> out;
  constexpr auto offs = gv::connectivity<N>::offsets();
  for (gv::index_t u = 0; u < g.size(); ++u)
    for (int d = 0; d < N; ++d) {
      auto c = g.coords(u);
      for (int a = 0; a < Dim; ++a) c[a] += offs[d][a];
      if (g.contains(c)) out.push_back({u, d, g.index(c)});
    }
  return out;
}

template <int N>
void check_connectivity() {
  constexpr int Dim = gv::connectivity<N>::dim;
  CAPTURE(N);
  constexpr auto offs = gv::connectivity<N>::offsets();
  // the numbering the cut set relies on: opposite = N - 1 - d, forward = the second half, whose
  // last non-zero coordinate is +1
  for (int d = 0; d < N; ++d) {
    for (int a = 0; a < Dim; ++a) CHECK(offs[gv::opposite_direction(d, N)][a] == -offs[d][a]);
    int last = 0;
    for (int a = 0; a < Dim; ++a)
      if (offs[d][a] != 0) last = offs[d][a];
    CHECK(gv::is_forward_direction(d, N) == (last > 0));
  }

  const auto g = small_grid<Dim>();
  const auto edges = all_edges<Dim, N>(g);
  std::mt19937 rng(1234 + N);
  for (int trial = 0; trial < 20; ++trial) {
    gv::cut_set<Dim> set(g, gv::connectivity<N>{});
    gv::cut_builder<Dim> builder(g, gv::connectivity<N>{});
    std::set<std::pair<gv::index_t, gv::index_t>> truth;  // unordered pairs (min, max)
    const std::size_t k = rng() % (edges.size() / 2 + 1);
    for (std::size_t i = 0; i < k; ++i) {
      const auto& e = edges[rng() % edges.size()];
      set.insert(e[0], int(e[1]));
      builder.insert(e[0], int(e[1]));
      truth.insert({std::min(e[0], e[2]), std::max(e[0], e[2])});
    }
    const gv::cut_set<Dim> built = builder.build();
    CHECK(built == set);
    CHECK(set.size() == truth.size());
    CHECK(set.empty() == truth.empty());
    const gv::cut_table table(set);
    const gv::cut_view view = table.view();
    for (const auto& e : edges) {
      const int d = int(e[1]);
      const bool want = truth.count({std::min(e[0], e[2]), std::max(e[0], e[2])}) > 0;
      CHECK(set.cut(e[0], d) == want);
      CHECK(set.cut(e[2], gv::opposite_direction(d, N)) == want);  // symmetry
      CHECK(view.cut(e[0], d) == want);
      CHECK(view.cut(e[2], gv::opposite_direction(d, N)) == want);
    }
    // iteration visits each edge once, in its forward direction
    std::size_t seen = 0;
    set.for_each_edge([&](gv::index_t u, int d) {
      CHECK(gv::is_forward_direction(d, N));
      CHECK(truth.count({std::min(u, set.neighbour(u, d)), std::max(u, set.neighbour(u, d))}) == 1);
      ++seen;
    });
    CHECK(seen == truth.size());
    gv::index_t prev = -1;
    for (const auto& en : set) {
      CHECK(en.voxel > prev);
      CHECK(en.forward != 0);
      CHECK(en.forward < (gv::cut_mask_t(1) << (N / 2)));
      prev = en.voxel;
    }
    // view of voxels without cut edges
    std::size_t incident_voxels = 0;
    for (gv::index_t u = 0; u < g.size(); ++u) incident_voxels += view.incident(u) != 0;
    CHECK(gv::index_t(incident_voxels) == view.count);
  }
}

}  // namespace

TEST_CASE("cut_set: symmetric edges, builder, view, for every connectivity") {
  check_connectivity<4>();
  check_connectivity<8>();
  check_connectivity<6>();
  check_connectivity<18>();
  check_connectivity<26>();
}

TEST_CASE("cut_set: merge is the union") {
  const gv::grid<3> g({4, 4, 4});
  gv::cut_set<3> a(g, gv::connectivity<26>{}), b(g, gv::connectivity<26>{}), both(g, gv::connectivity<26>{});
  const auto edges = all_edges<3, 26>(g);
  std::mt19937 rng(7);
  for (int i = 0; i < 200; ++i) {
    const auto& e = edges[rng() % edges.size()];
    (i % 2 ? a : b).insert(e[0], int(e[1]));
    both.insert(e[0], int(e[1]));
  }
  gv::cut_set<3> m = a;
  m.merge(b);
  CHECK(m == both);
  m.merge(gv::cut_set<3>(g, gv::connectivity<26>{}));
  CHECK(m == both);
  gv::cut_set<3> e(g, gv::connectivity<26>{});
  e.merge(a);
  CHECK(e == a);
  CHECK_THROWS_AS(m.merge(gv::cut_set<3>(g, gv::connectivity<6>{})), std::invalid_argument);
  CHECK_THROWS_AS(m.merge(gv::cut_set<3>(gv::grid<3>({4, 4, 5}), gv::connectivity<26>{})), std::invalid_argument);
}

TEST_CASE("cut_set: bad edges are refused with a message") {
  const gv::grid<2> g({3, 3});
  gv::cut_set<2> s(g, gv::connectivity<4>{});
  // direction 2 of connectivity<4> is (+1, 0): from x = 2 it leaves the grid
  CHECK_THROWS_WITH_AS(s.insert(g.index({2, 1}), 2), doctest::Contains("leaves the grid"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(s.insert(9, 0), doctest::Contains("outside the grid"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(s.insert(0, 4), doctest::Contains("direction 4"), std::invalid_argument);
  CHECK_THROWS_AS(s.cut(-1, 0), std::invalid_argument);
  CHECK(s.empty());
  CHECK(s.voxel_count() == 0);
}

TEST_CASE("cut_set: memory follows the cut's area, not the volume") {
  // the same 8 x 8 plane of x-edges (between x = 3 and 4) in grids 8 and 1024 voxels deep
  auto plane = [](gv::index_t depth) {
    const gv::grid<3> g({8, 8, depth});
    gv::cut_builder<3> b(g, gv::connectivity<26>{});
    for (gv::index_t y = 0; y < 8; ++y)
      for (gv::index_t z = 0; z < 8; ++z) b.insert(g.index({3, y, z}), 13);  // (+1, 0, 0)
    return b.build();
  };
  const auto small = plane(8), big = plane(1024);
  CHECK(small.size() == 64);
  CHECK(big.size() == 64);
  CHECK(small.voxel_count() == 64);
  CHECK(small.memory_bytes() == big.memory_bytes());
  CHECK(small.memory_bytes() <= 64 * sizeof(gv::cut_set<3>::entry));
  const gv::cut_table ts(small), tb(big);
  CHECK(ts.memory_bytes() == tb.memory_bytes());
  CHECK(ts.view().count == 128);  // both ends of each edge
  CHECK(ts.memory_bytes() <= 4 * 128 * (sizeof(gv::index_t) + sizeof(gv::cut_mask_t)));
  CHECK(gv::cut_table(gv::cut_set<3>(gv::grid<3>({512, 512, 512}), gv::connectivity<6>{})).memory_bytes() == 0);
}

TEST_CASE("cut_table: copies and moves keep a working view") {
  const gv::grid<2> g({4, 4});
  gv::cut_set<2> s(g, gv::connectivity<8>{});
  s.insert(g.index({1, 1}), 7);  // (+1, +1)
  gv::cut_table a(s);
  gv::cut_table b = a;
  gv::cut_table c = std::move(a);
  gv::cut_table d;
  d = b;
  for (const gv::cut_table* t : {&b, &c, &d}) {
    CHECK(t->view().cut(g.index({1, 1}), 7));
    CHECK(t->view().cut(g.index({2, 2}), 0));
    CHECK_FALSE(t->view().cut(g.index({2, 2}), 1));
  }
  CHECK(a.view().empty());
  CHECK(a.view().incident(5) == 0);
}

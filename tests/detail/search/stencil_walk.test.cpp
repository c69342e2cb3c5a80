// Tests of geovoronoi/detail/search/stencil_walk.hpp: the neighbours it visits (interior fast path and
// border path) are exactly the in-grid voxels at the connectivity's offsets, with the right stencil
// index, on random small grids including one-voxel-thick ones.

#include <doctest/doctest.h>

#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/problem.hpp>

#include <algorithm>
#include <random>
#include <utility>
#include <vector>

namespace {
namespace gv = geovoronoi;

template <int Dim, int N>
void check_walk(std::mt19937_64& rng) {
  gv::coord<Dim> e{};
  for (int a = 0; a < Dim; ++a) e[a] = 1 + gv::index_t(rng() % 6);
  const gv::grid<Dim> g(e);
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<N>{});
  const gv::detail::search::stencil_walker<Dim> walk(p);
  constexpr auto offs = gv::connectivity<N>::offsets();
  for (gv::index_t v = 0; v < g.size(); ++v) {
    std::vector<std::pair<int, gv::index_t>> got, want;
    walk.for_each_neighbour(p, v, [&](int k, gv::index_t u) { got.push_back({k, u}); });
    const auto c = g.coords(v);
    for (int k = 0; k < N; ++k) {
      gv::coord<Dim> n = c;
      for (int a = 0; a < Dim; ++a) n[a] += offs[k][a];
      if (g.contains(n)) want.push_back({k, g.index(n)});
    }
    std::sort(got.begin(), got.end());
    CAPTURE(v);
    CHECK(got == want);
  }
}

TEST_CASE("stencil_walker: visits exactly the in-grid neighbours") {
  std::mt19937_64 rng(4);
  for (int t = 0; t < 30; ++t) {
    check_walk<2, 4>(rng);
    check_walk<2, 8>(rng);
    check_walk<3, 6>(rng);
    check_walk<3, 18>(rng);
    check_walk<3, 26>(rng);
  }
}

}  // namespace

// The translation-invariant shortcut of the shape functions (detail/shape/translation_invariant.hpp):
// which problems qualify, and the claim it rests on — the distance from any voxel q equals the table
// computed once from voxel 0, at the absolute offset, bit for bit — checked against a search from
// every q on small grids with anisotropic (also very anisotropic) spacing, every connectivity, 2D and
// 3D, float and double. Its use inside Sibson / Laplace / Distance Ratio is checked against the
// brute-force definition by the shape suite (tests/backend/shape/suite.hpp).
#include <doctest/doctest.h>
#include <geovoronoi.hpp>

#include "support/oracle.hpp"

#include <random>
#include <string>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace sh = geovoronoi::detail::shape;
using gvtest::bits;

/// A metric whose weight is not monotone in the length: diagonal steps are cheaper than face steps,
/// so clamping a path can make it longer and the shortcut must not be taken.
struct inverse_length {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T) const noexcept {
    return T(1) / length;
  }
};

template <int Dim>
gv::grid<Dim> random_grid(std::mt19937_64& rng, int trial) {
  gv::coord<Dim> e{};
  gv::point<Dim> sp{};
  const double extreme[] = {1.0, 0.01, 1.0 / 3.0, 1000.0, 0.7};
  for (int a = 0; a < Dim; ++a) {
    e[a] = 2 + gv::index_t(rng() % (Dim == 2 ? 14 : 7));
    sp[a] = trial % 3 == 0 ? 1.0 : trial % 3 == 1 ? 0.25 + 0.25 * double(rng() % 7) : extreme[rng() % 5];
  }
  return gv::grid<Dim>(e, sp);
}

/// For every q: a single-source search from q equals the table at |v - q| for every v.
template <class T, int Dim, int N, class Metric>
long check_table(std::mt19937_64& rng, int trial, Metric metric, bool varying_field) {
  const auto g = random_grid<Dim>(rng, trial);
  std::vector<T> f(std::size_t(g.size()), T(2.5));
  if (varying_field)
    for (auto& x : f) x = T(0.5 + double(rng() % 5));
  const auto p = gv::make_problem(g, f, metric, gv::connectivity<N>{});
  REQUIRE(sh::translation_invariant(p));
  const sh::offset_table<decltype(p)> tab(gv::seq, p);
  long checked = 0;
  for (gv::index_t q = 0; q < g.size(); ++q) {
    const auto s = gv::single_source(gv::seq, p, g.coords(q));
    REQUIRE(s.size() == std::size_t(g.size()));  // everything is reachable
    gv::index_t qc[3], vc[3];
    tab.coords(q, qc);
    for (std::size_t j = 0; j < s.size(); ++j) {
      tab.coords(s.voxel[j], vc);
      const T t = tab.distance(vc, qc);
      if (bits(t) != bits(s.distance[j])) {
        FAIL("dim " << Dim << " N " << N << " trial " << trial << ": from voxel " << q << " to " << s.voxel[j]
                    << " the search gives " << s.distance[j] << ", the table " << t);
      }
      ++checked;
    }
  }
  return checked;
}

TEST_CASE("translation invariance: the offset table equals a search from every voxel, bit for bit") {
  std::mt19937_64 rng(4711);
  long checked = 0;
  for (int trial = 0; trial < 6; ++trial) {
    checked += check_table<float, 2, 4>(rng, trial, gv::uniform{}, true);
    checked += check_table<float, 2, 8>(rng, trial, gv::min_stiffness{}, false);
    checked += check_table<double, 2, 8>(rng, trial, gv::mean_cost{}, false);
    checked += check_table<float, 3, 6>(rng, trial, gv::mean_stiffness{}, false);
    checked += check_table<float, 3, 18>(rng, trial, gv::uniform{}, true);
    checked += check_table<float, 3, 26>(rng, trial, gv::min_stiffness{}, false);
    checked += check_table<double, 3, 26>(rng, trial, gv::uniform{}, false);
  }
  MESSAGE("pairs checked: " << checked);
  CHECK(checked > 100000);
}

TEST_CASE("translation invariance: which problems qualify") {
  const gv::grid<3> g({6, 5, 4}, {1.0, 0.5, 2.0});
  std::vector<float> f(std::size_t(g.size()), 3.0f);
  auto ti = [&](auto metric) { return sh::translation_invariant(gv::make_problem(g, f, metric, gv::connectivity<26>{})); };
  CHECK(ti(gv::uniform{}));
  CHECK(ti(gv::min_stiffness{}));
  CHECK(ti(gv::mean_stiffness{}));
  CHECK(ti(gv::mean_cost{}));
  CHECK_FALSE(ti(inverse_length{}));  // a face step would weigh more than a diagonal one
  f[17] = 4.0f;                       // a field that varies: only the field-free metric qualifies
  CHECK(ti(gv::uniform{}));
  CHECK_FALSE(ti(gv::min_stiffness{}));
  CHECK_FALSE(ti(gv::mean_cost{}));
  f[17] = 3.0f;
  f[5] = 0.0f;  // a masked voxel breaks invariance for every metric
  CHECK_FALSE(ti(gv::uniform{}));
  CHECK_FALSE(ti(gv::min_stiffness{}));
  f[5] = -0.0f;  // masked for stiffness, inside for cost; and not the same bits as the rest
  CHECK_FALSE(ti(gv::min_stiffness{}));
  CHECK_FALSE(ti(gv::mean_cost{}));
}

TEST_CASE("translation invariance: the ball equals a bounded solve") {
  std::mt19937_64 rng(99);
  for (int trial = 0; trial < 20; ++trial) {
    const auto g = random_grid<3>(rng, trial);
    const auto f = gv::phantom::constant(g);
    const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<18>{});
    const sh::offset_table<decltype(p)> tab(gv::seq, p);
    const gv::index_t q = gv::index_t(rng() % std::uint64_t(g.size()));
    const float radius = float(0.5 + double(rng() % 40) * 0.25);
    const auto a = tab.ball(q, radius);
    const auto b = gv::bounded_solve(gv::seq, p, std::vector<gv::source<float>>{{q, 0.0f, 0}}, radius);
    REQUIRE(a.size() == b.size());
    for (std::size_t j = 0; j < a.size(); ++j) {
      CHECK(a.voxel[j] == b.voxel[j]);
      CHECK(bits(a.distance[j]) == bits(b.distance[j]));
      CHECK(a.label[j] == b.label[j]);
    }
  }
}

}  // namespace

// Tests of geovoronoi/problem.hpp: make_problem from vectors, images and views (size checks),
// the trivially copyable problem type and its members, inside() and weight().

#include <doctest/doctest.h>

#include <geovoronoi/problem.hpp>

#include "support/core_helpers.hpp"

#include <type_traits>
#include <vector>

namespace {
namespace gv = geovoronoi;

struct user_metric {
  template <class T>
  T operator()(T length, T from, T to) const noexcept {
    return length * (to - from > T(0) ? to - from : from - to) + length;
  }
};

template <class T, int Dim, class M, int N>
constexpr bool copyable = std::is_trivially_copyable_v<gv::problem<T, Dim, M, N>>;
static_assert(copyable<float, 3, gv::uniform, 6> && copyable<float, 3, gv::min_stiffness, 26> &&
              copyable<float, 3, gv::mean_stiffness, 18> && copyable<float, 3, gv::mean_cost, 26>);
static_assert(copyable<double, 2, gv::uniform, 4> && copyable<double, 2, gv::min_stiffness, 8> &&
              copyable<double, 2, gv::mean_stiffness, 8> && copyable<double, 2, gv::mean_cost, 4>);
static_assert(copyable<float, 3, user_metric, 26>);

using P = decltype(gv::make_problem(std::declval<const gv::grid<3>&>(), std::declval<const std::vector<double>&>(),
                                    gv::mean_cost{}, gv::connectivity<18>{}));
static_assert(std::is_same_v<P, gv::problem<double, 3, gv::mean_cost, 18>>);
static_assert(std::is_same_v<P::value_type, double> && P::dim == 3 && P::neighbours == 18);
static_assert(std::is_same_v<P::metric_type, gv::mean_cost>);
static_assert(std::is_same_v<P::connectivity_type, gv::connectivity<18>>);
// defaults: min_stiffness, 26 neighbours in 3D, 8 in 2D
using D3 = decltype(gv::make_problem(std::declval<const gv::grid<3>&>(), std::declval<const std::vector<float>&>()));
using D2 = decltype(gv::make_problem(std::declval<const gv::grid<2>&>(), std::declval<const gv::image<float, 2>&>()));
static_assert(std::is_same_v<D3, gv::problem<float, 3, gv::min_stiffness, 26>>);
static_assert(std::is_same_v<D2, gv::problem<float, 2, gv::min_stiffness, 8>>);
// views of const and non-const values give a problem over the value type
using V = decltype(gv::make_problem(std::declval<const gv::grid<2>&>(), std::declval<gv::image_view<const float, 2>>(),
                                    gv::uniform{}, gv::connectivity<4>{}));
static_assert(std::is_same_v<V, gv::problem<float, 2, gv::uniform, 4>>);

TEST_CASE("make_problem: from a vector, an image and views") {
  const gv::grid<3> g({4, 3, 2}, {1.0, 2.0, 0.5});
  std::vector<float> f(g.size());
  for (gv::index_t v = 0; v < g.size(); ++v) f[v] = float(v) - 3.0f;  // voxels 0..3 masked
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<6>{});
  CHECK(p.geometry == g);
  CHECK(p.field == f.data());  // not copied
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(p.inside(v) == (v > 3));
  const gv::image<float, 3> img(g, f);
  const auto q = gv::make_problem(g, img, gv::min_stiffness{}, gv::connectivity<6>{});
  CHECK(q.field == img.data());
  gv::image<float, 3> mut(g, f);
  const auto r = gv::make_problem(g, mut.view(), gv::uniform{}, gv::connectivity<26>{});
  CHECK(r.field == mut.data());
  const auto s = gv::make_problem(g, static_cast<gv::image_view<const float, 3>>(mut), gv::uniform{}, gv::connectivity<18>{});
  CHECK(s.field == mut.data());
  // the stencil is resolved against the grid
  const gv::stencil<float, 3, 6> st(g);
  for (int k = 0; k < 6; ++k) {
    CHECK(p.edges.delta[k] == st.delta[k]);
    CHECK(p.edges.length[k] == st.length[k]);
  }
}

/// make_problem with a field that lives until the call returns: a temporary is rejected at compile
/// time (tests/compile_fail), and these checks only need the call to run.
template <int Dim, class Field>
void make_from(const gv::grid<Dim>& g, const Field& field) {
  (void)gv::make_problem(g, field);
}

TEST_CASE("make_problem: size mismatches are rejected") {
  const gv::grid<2> g({3, 3});
  GV_CHECK_INVALID(make_from(g, std::vector<float>(8, 1.0f)), "field", "8", "9");
  GV_CHECK_INVALID(make_from(g, std::vector<double>(10, 1.0)), "field", "10", "9");
  GV_CHECK_INVALID(make_from(g, gv::image<float, 2>(gv::grid<2>({9, 1}), 1.0f)), "field", "extents");
  GV_CHECK_INVALID(make_from(g, gv::image<float, 2>(gv::grid<2>({3, 4}), 1.0f)), "field", "extents");
  gv::image<float, 2> other(gv::grid<2>({1, 9}), 1.0f);
  GV_CHECK_INVALID(gv::make_problem(g, other.view()), "field", "extents");
  GV_CHECK_INVALID(make_from(gv::grid<2>(), std::vector<float>{}), "empty");
  // a spacing valid in double whose edge lengths underflow or overflow the distance type
  GV_CHECK_INVALID(make_from(gv::grid<2>({2, 2}, {1e-50, 1e-50}), std::vector<float>(4, 1.0f)), "spacing", "length");
  GV_CHECK_INVALID(make_from(gv::grid<2>({2, 2}, {1e39, 1.0}), std::vector<float>(4, 1.0f)), "spacing", "length");
  GV_CHECK_INVALID(make_from(gv::grid<3>({2, 2, 2}, {1e300, 1e300, 1.0}), std::vector<double>(8, 1.0)), "spacing");
  CHECK_NOTHROW(make_from(gv::grid<2>({2, 2}, {1e-50, 1e-50}), std::vector<double>(4, 1.0)));
  CHECK_NOTHROW(make_from(gv::grid<2>({2, 2}, {1e30, 1e30}), std::vector<float>(4, 1.0f)));
  // an image over a grid with other spacing but the same extents is accepted: only the layout matters
  CHECK_NOTHROW(make_from(g, gv::image<float, 2>(gv::grid<2>({3, 3}, {2.0, 2.0}), 1.0f)));
}

TEST_CASE("problem: weight() applies the metric to the stencil length and both field values, in order") {
  const gv::grid<2> g({3, 2}, {3.0, 4.0});
  const std::vector<double> f{1.0, 2.0, 4.0, 8.0, 16.0, 32.0};
  const auto p = gv::make_problem(g, f, user_metric{}, gv::connectivity<8>{});
  constexpr auto offs = gv::connectivity<8>::offsets();
  for (int k = 0; k < 8; ++k) {
    const double len = offs[k][0] != 0 && offs[k][1] != 0 ? 5.0 : offs[k][0] != 0 ? 3.0 : 4.0;
    CHECK(p.edges.length[k] == len);
    // from voxel 0 (value 1) to voxel 4 (value 16), as if through neighbour k
    CHECK(p.weight(0, 4, k) == len * 15.0 + len);
    CHECK(p.weight(4, 0, k) == len * 15.0 + len);
  }
  const auto m = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{});
  CHECK(m.weight(1, 2, 2) == 3.0 / 2.0);
  CHECK(m.weight(5, 2, 3) == 4.0 / 4.0);
  const auto c = gv::make_problem(g, f, gv::mean_cost{}, gv::connectivity<4>{});
  CHECK(c.weight(0, 3, 3) == 4.0 * 4.5);
}

TEST_CASE("problem: inside() follows the metric's mask rule") {
  const gv::grid<2> g({6, 1});
  const std::vector<float> f{1.0f, 0.0f, -1.0f, gvcore::nan_v<float>, gvcore::inf_v<float>, 0.5f};
  const auto st = gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<4>{});
  const auto co = gv::make_problem(g, f, gv::mean_cost{}, gv::connectivity<4>{});
  const bool stiff[] = {true, false, false, false, true, true};
  const bool cost[] = {true, true, false, false, false, true};
  for (gv::index_t v = 0; v < 6; ++v) {
    CAPTURE(v);
    CHECK(st.inside(v) == stiff[v]);
    CHECK(co.inside(v) == cost[v]);
  }
}

}  // namespace

// Tests of geovoronoi/image.hpp: construction and fill, adopting values (with the size check),
// element access by index and by coordinates, views and their conversion to const views.

#include <doctest/doctest.h>

#include <geovoronoi/image.hpp>

#include "support/core_helpers.hpp"

#include <numeric>
#include <type_traits>
#include <vector>

namespace {
namespace gv = geovoronoi;

static_assert(std::is_trivially_copyable_v<gv::image_view<float, 3>>);
static_assert(std::is_trivially_copyable_v<gv::image_view<const double, 2>>);
static_assert(std::is_trivially_copyable_v<gv::image_view<gv::label_t, 3>>);
// const-correct conversions: non-const -> const only, never across value types
static_assert(std::is_convertible_v<gv::image_view<float, 3>, gv::image_view<const float, 3>>);
static_assert(!std::is_convertible_v<gv::image_view<const float, 3>, gv::image_view<float, 3>>);
static_assert(!std::is_constructible_v<gv::image_view<float, 3>, gv::image_view<const float, 3>>);
static_assert(!std::is_convertible_v<gv::image_view<double, 3>, gv::image_view<const float, 3>>);
static_assert(!std::is_convertible_v<gv::image_view<float, 2>, gv::image_view<const float, 3>>);
static_assert(std::is_convertible_v<const gv::image<float, 2>&, gv::image_view<const float, 2>>);
static_assert(!std::is_convertible_v<const gv::image<float, 2>&, gv::image_view<float, 2>>);
static_assert(std::is_same_v<decltype(std::declval<const gv::image<float, 2>&>().view()), gv::image_view<const float, 2>>);
static_assert(std::is_same_v<decltype(std::declval<gv::image<float, 2>&>().view()), gv::image_view<float, 2>>);
static_assert(std::is_same_v<gv::image_view<const float, 2>::value_type, float>);

TEST_CASE("image: construction and fill") {
  const gv::grid<3> g({4, 3, 2}, {0.5, 1.0, 2.0});
  const gv::image<float, 3> a(g, 2.5f);
  CHECK(a.size() == 24);
  CHECK_FALSE(a.empty());
  CHECK(a.geometry() == g);
  for (float x : a) CHECK(x == 2.5f);
  const gv::image<gv::label_t, 3> b(g);
  CHECK(b.values() == std::vector<gv::label_t>(24, 0));  // value-initialised
  const gv::image<double, 2> e;
  CHECK(e.empty());
  CHECK(e.size() == 0);
}

TEST_CASE("image: adopting values checks their count") {
  const gv::grid<2> g({3, 2});
  std::vector<int> v(6);
  std::iota(v.begin(), v.end(), 10);
  const int* before = v.data();
  gv::image<int, 2> a(g, std::move(v));
  CHECK(a.data() == before);  // adopted, not copied
  CHECK(a[0] == 10);
  CHECK(a[5] == 15);
  CHECK(a({2, 1}) == 15);
  CHECK(a({0, 1}) == 13);
  GV_CHECK_INVALID((gv::image<int, 2>(g, std::vector<int>(5))), "5", "6");
  GV_CHECK_INVALID((gv::image<int, 2>(g, std::vector<int>(7))), "7", "6");
  GV_CHECK_INVALID((gv::image<float, 2>(g, std::vector<float>{})), "0", "6");
}

TEST_CASE("image: element access by index and coordinates agree with the grid") {
  const gv::grid<3> g({5, 4, 3});
  gv::image<gv::index_t, 3> a(g, -1);
  for (gv::index_t z = 0; z < 3; ++z)
    for (gv::index_t y = 0; y < 4; ++y)
      for (gv::index_t x = 0; x < 5; ++x) a({x, y, z}) = x + 5 * (y + 4 * z);
  for (gv::index_t v = 0; v < a.size(); ++v) CHECK(a[v] == v);
  a.values()[7] = 100;
  CHECK(a({2, 1, 0}) == 100);
  const auto& c = a;
  CHECK(c({2, 1, 0}) == 100);
  CHECK(c.data()[7] == 100);
}

TEST_CASE("image: views share the data and convert to const views") {
  const gv::grid<2> g({4, 4});
  gv::image<float, 2> a(g, 1.0f);
  gv::image_view<float, 2> v = a.view();
  CHECK(v.geometry() == g);
  CHECK(v.size() == 16);
  CHECK(v.data() == a.data());
  v({1, 2}) = 9.0f;
  CHECK(a({1, 2}) == 9.0f);
  v[0] = -3.0f;
  CHECK(a[0] == -3.0f);
  CHECK(v.end() - v.begin() == 16);
  // a mutable view converts to a read-only view of the same data
  gv::image_view<const float, 2> r = v;
  CHECK(r.data() == a.data());
  CHECK(r({1, 2}) == 9.0f);
  CHECK(r.geometry() == g);
  // an image converts implicitly to a read-only view
  const gv::image_view<const float, 2> r2 = static_cast<const gv::image<float, 2>&>(a);
  CHECK(r2.data() == a.data());
  CHECK(r2.size() == a.size());
  // views are cheap copies pointing at the same storage
  const auto copy = v;
  CHECK(copy.data() == v.data());
  // a default view is empty
  const gv::image_view<float, 3> none;
  CHECK(none.data() == nullptr);
  CHECK(none.size() == 0);
  // a view of external storage
  std::vector<double> raw(12, 0.5);
  const gv::image_view<double, 3> ext(gv::grid<3>({2, 3, 2}), raw.data());
  ext({1, 2, 1}) = 4.0;
  CHECK(raw[11] == 4.0);
}

}  // namespace

// Tests of geovoronoi/connectivity.hpp: the offset tables (sizes, no zero offset, no duplicates,
// symmetric, exactly the offsets allowed by max_order), checked at compile time and at run time,
// and the stencil built from a grid (offsets, index deltas, edge lengths).

#include <doctest/doctest.h>

#include <geovoronoi/connectivity.hpp>

#include <cmath>
#include <random>
#include <type_traits>

namespace {
namespace gv = geovoronoi;

// ---- compile-time properties of the tables ----------------------------------------------------------

template <int N>
constexpr int order_of(const typename gv::connectivity<N>::offset_type& o) {
  int n = 0;
  for (int x : o) n += x != 0;
  return n;
}

template <int N>
constexpr bool same_offset(const typename gv::connectivity<N>::offset_type& a,
                           const typename gv::connectivity<N>::offset_type& b) {
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i] != b[i]) return false;
  return true;
}

template <int N>
constexpr bool components_in_range() {
  for (const auto& o : gv::connectivity<N>::offsets())
    for (int x : o)
      if (x < -1 || x > 1) return false;
  return true;
}

template <int N>
constexpr bool no_zero_offset() {
  for (const auto& o : gv::connectivity<N>::offsets())
    if (order_of<N>(o) == 0) return false;
  return true;
}

template <int N>
constexpr bool no_duplicates() {
  constexpr auto t = gv::connectivity<N>::offsets();
  for (int i = 0; i < N; ++i)
    for (int j = i + 1; j < N; ++j)
      if (same_offset<N>(t[i], t[j])) return false;
  return true;
}

template <int N>
constexpr bool symmetric() {
  constexpr auto t = gv::connectivity<N>::offsets();
  for (int i = 0; i < N; ++i) {
    auto neg = t[i];
    for (auto& x : neg) x = -x;
    bool found = false;
    for (int j = 0; j < N; ++j) found = found || same_offset<N>(t[j], neg);
    if (!found) return false;
  }
  return true;
}

template <int N>
constexpr bool orders_within_max() {
  for (const auto& o : gv::connectivity<N>::offsets())
    if (order_of<N>(o) > gv::connectivity<N>::max_order) return false;
  return true;
}

// the number of non-zero offsets of order <= m in Dim dimensions: sum over k of C(Dim, k) 2^k
constexpr int expected_count(int dim, int m) {
  int n = 0, binom = 1;
  for (int k = 1; k <= m; ++k) {
    binom = binom * (dim - k + 1) / k;
    n += binom * (1 << k);
  }
  return n;
}

template <int N, int Dim, int MaxOrder>
constexpr bool table_ok() {
  using C = gv::connectivity<N>;
  return C::dim == Dim && C::size == N && C::max_order == MaxOrder && int(C::offsets().size()) == N &&
         int(C::offsets()[0].size()) == Dim && expected_count(Dim, MaxOrder) == N && components_in_range<N>() &&
         no_zero_offset<N>() && no_duplicates<N>() && symmetric<N>() && orders_within_max<N>();
}

static_assert(table_ok<4, 2, 1>(), "connectivity<4>: 2D faces");
static_assert(table_ok<8, 2, 2>(), "connectivity<8>: 2D faces and corners");
static_assert(table_ok<6, 3, 1>(), "connectivity<6>: 3D faces");
static_assert(table_ok<18, 3, 2>(), "connectivity<18>: 3D faces and edges");
static_assert(table_ok<26, 3, 3>(), "connectivity<26>: 3D faces, edges and corners");
static_assert(std::is_trivially_copyable_v<gv::connectivity<26>>);
static_assert(std::is_trivially_copyable_v<gv::connectivity<4>>);
static_assert(std::is_empty_v<gv::connectivity<6>>);
static_assert(std::is_trivially_copyable_v<gv::stencil<float, 3, 26>>);
static_assert(std::is_trivially_copyable_v<gv::stencil<double, 2, 8>>);
static_assert(gv::detail::is_connectivity<gv::connectivity<18>>::value);
static_assert(!gv::detail::is_connectivity<int>::value);

// ---- the same properties at run time (so a failure reports the offending offset) --------------------

template <int N>
void check_table() {
  using C = gv::connectivity<N>;
  const auto t = C::offsets();
  CAPTURE(N);
  REQUIRE(int(t.size()) == N);
  int by_order[4] = {0, 0, 0, 0};
  for (int i = 0; i < N; ++i) {
    const int ord = order_of<N>(t[i]);
    CHECK(ord >= 1);
    CHECK(ord <= C::max_order);
    by_order[ord]++;
    int found_neg = 0, found_same = 0;
    for (int j = 0; j < N; ++j) {
      bool neg = true, same = true;
      for (int a = 0; a < C::dim; ++a) {
        neg = neg && t[j][a] == -t[i][a];
        same = same && t[j][a] == t[i][a];
      }
      found_neg += neg;
      found_same += same;
    }
    CHECK(found_neg == 1);
    CHECK(found_same == 1);
  }
  // every offset of order <= max_order is present: 2*dim faces, then edges, then corners
  CHECK(by_order[1] == 2 * C::dim);
  CHECK(by_order[2] == (C::max_order >= 2 ? (C::dim == 2 ? 4 : 12) : 0));
  CHECK(by_order[3] == (C::max_order >= 3 ? 8 : 0));
}

TEST_CASE("connectivity: offset tables") {
  check_table<4>();
  check_table<8>();
  check_table<6>();
  check_table<18>();
  check_table<26>();
  CHECK(gv::connectivity<4>::size == 4);
  CHECK(gv::connectivity<26>::dim == 3);
  CHECK(gv::connectivity<8>::dim == 2);
}

TEST_CASE("connectivity: documented order, z outermost and x innermost") {
  constexpr auto t = gv::connectivity<4>::offsets();
  CHECK(t[0] == std::array<int, 2>{0, -1});
  CHECK(t[1] == std::array<int, 2>{-1, 0});
  CHECK(t[2] == std::array<int, 2>{1, 0});
  CHECK(t[3] == std::array<int, 2>{0, 1});
  constexpr auto u = gv::connectivity<26>::offsets();
  CHECK(u[0] == std::array<int, 3>{-1, -1, -1});
  CHECK(u[25] == std::array<int, 3>{1, 1, 1});
}

// ---- stencils ---------------------------------------------------------------------------------------

template <class T, int Dim, int N>
void check_stencil(const gv::grid<Dim>& g) {
  const gv::stencil<T, Dim, N> s(g, gv::connectivity<N>{});
  constexpr auto t = gv::connectivity<N>::offsets();
  CHECK(s.size == N);
  // a reference voxel away from the border, to measure index differences
  gv::coord<Dim> mid{};
  for (int a = 0; a < Dim; ++a) mid[a] = g.extent(a) / 2;
  for (int k = 0; k < N; ++k) {
    CAPTURE(k);
    long double len2 = 0;
    for (int a = 0; a < 3; ++a) CHECK(s.offset[k][a] == (a < Dim ? t[k][a] : 0));
    gv::coord<Dim> nb = mid;
    for (int a = 0; a < Dim; ++a) {
      nb[a] += t[k][a];
      const long double c = (long double)t[k][a] * (long double)g.spacing(a);
      len2 += c * c;
    }
    if (g.contains(nb)) CHECK(s.delta[k] == g.index(nb) - g.index(mid));
    // delta from the strides, whether or not the grid is big enough for a full neighbourhood
    gv::index_t d = t[k][0] + t[k][1] * g.extent(0);
    if constexpr (Dim == 3) d += t[k][2] * g.extent(0) * g.extent(1);
    CHECK(s.delta[k] == d);
    // length: sqrt of the squared physical offset, rounded to T. The library evaluates it in double:
    // a float length is then the correctly rounded value (half an ulp, up to the double rounding
    // error), a double length within two ulps of the exact value.
    const long double exact = std::sqrt(len2);
    const T len = s.length[k];
    CHECK(len > T(0));
    const long double ulp = (long double)(std::nextafter(len, std::numeric_limits<T>::infinity()) - len);
    const long double tol = std::is_same_v<T, float> ? 0.5L * ulp * (1 + 1e-6L) : 2 * ulp;
    CHECK(std::fabs((long double)len - exact) <= tol);
    // the opposite edge has the identical length (symmetric weights need symmetric lengths)
    for (int j = 0; j < N; ++j) {
      bool opposite = true;
      for (int a = 0; a < Dim; ++a) opposite = opposite && t[j][a] == -t[k][a];
      if (opposite) {
        CHECK(s.length[j] == s.length[k]);
        CHECK(s.delta[j] == -s.delta[k]);
      }
    }
  }
}

TEST_CASE("stencil: offsets, index deltas and lengths from the grid") {
  check_stencil<float, 2, 4>(gv::grid<2>({5, 7}));
  check_stencil<float, 2, 8>(gv::grid<2>({5, 7}, {0.3, 1.7}));
  check_stencil<double, 2, 8>(gv::grid<2>({9, 4}, {2.5, 0.1}));
  check_stencil<float, 3, 6>(gv::grid<3>({4, 5, 6}, {1.0, 2.0, 3.0}));
  check_stencil<float, 3, 18>(gv::grid<3>({4, 5, 6}, {0.7, 0.2, 1.3}));
  check_stencil<float, 3, 26>(gv::grid<3>({3, 3, 3}));
  check_stencil<double, 3, 26>(gv::grid<3>({6, 2, 5}, {0.11, 3.0, 0.5}));
  check_stencil<float, 3, 26>(gv::grid<3>({1, 1, 1}, {1e-3, 1e3, 1.0}));
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> sp(0.05, 20.0);
  for (int t = 0; t < 20; ++t) {
    const gv::grid<3> g({3 + gv::index_t(rng() % 5), 3 + gv::index_t(rng() % 5), 3 + gv::index_t(rng() % 5)},
                        {sp(rng), sp(rng), sp(rng)});
    check_stencil<float, 3, 26>(g);
    check_stencil<double, 3, 18>(g);
  }
}

TEST_CASE("stencil: sample lengths") {
  const gv::stencil<float, 3, 26> s(gv::grid<3>({3, 3, 3}, {3.0, 4.0, 12.0}));
  constexpr auto t = gv::connectivity<26>::offsets();
  for (int k = 0; k < 26; ++k) {
    const int ord = (t[k][0] != 0) + (t[k][1] != 0) + (t[k][2] != 0);
    if (ord == 3) CHECK(s.length[k] == 13.0f);                                  // 3-4-12-13
    if (ord == 2 && t[k][2] == 0) CHECK(s.length[k] == 5.0f);                  // 3-4-5
    if (ord == 1 && t[k][2] != 0) CHECK(s.length[k] == 12.0f);
  }
  const gv::stencil<double, 2, 8> u(gv::grid<2>({2, 2}));
  CHECK(u.length[0] == std::sqrt(2.0));
  CHECK(u.length[1] == 1.0);
}

}  // namespace

// Tests of geovoronoi/metric.hpp: each builtin's weight on sample values against hand-evaluated
// results and against the DESIGN.md formula in extended precision, the domain rules (0, negatives,
// NaN, infinities) and the defaults for user metrics.

#include <doctest/doctest.h>

#include <geovoronoi/metric.hpp>

#include "support/core_helpers.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

namespace {
namespace gv = geovoronoi;
using gvcore::inf_v;
using gvcore::nan_v;

static_assert(std::is_trivially_copyable_v<gv::uniform> && std::is_empty_v<gv::uniform>);
static_assert(std::is_trivially_copyable_v<gv::min_stiffness>);
static_assert(std::is_trivially_copyable_v<gv::mean_stiffness>);
static_assert(std::is_trivially_copyable_v<gv::mean_cost>);
static_assert(gv::detail::is_metric_v<gv::min_stiffness, float>);
static_assert(gv::detail::is_metric_v<gv::mean_cost, double>);
static_assert(!gv::detail::is_metric_v<int, float>);
static_assert(gv::detail::has_inside<gv::mean_cost, float>::value);
static_assert(gv::detail::has_inside<gv::uniform, double>::value);

struct no_rule {
  template <class T>
  T operator()(T length, T, T) const noexcept {
    return length;
  }
};
struct own_rule {
  template <class T>
  T operator()(T length, T, T) const noexcept {
    return length;
  }
  static bool inside(float v) noexcept { return v == 7.0f; }
};
static_assert(!gv::detail::has_inside<no_rule, float>::value);
static_assert(gv::detail::has_inside<own_rule, float>::value);
static_assert(gv::detail::is_metric_v<no_rule, float>);

TEST_CASE("metric: builtin weights on hand-evaluated samples") {
  // uniform: the length, whatever the field
  CHECK(gv::uniform{}(1.5f, 3.0f, 100.0f) == 1.5f);
  CHECK(gv::uniform{}(2.0, 0.001, 7.0) == 2.0);
  // min_stiffness: l / min(b_u, b_v)
  CHECK(gv::min_stiffness{}(2.0f, 4.0f, 8.0f) == 0.5f);
  CHECK(gv::min_stiffness{}(2.0f, 8.0f, 4.0f) == 0.5f);
  CHECK(gv::min_stiffness{}(3.0, 0.5, 10.0) == 6.0);
  CHECK(gv::min_stiffness{}(1.0f, 2.0f, 2.0f) == 0.5f);
  // mean_stiffness: 2 l / (b_u + b_v)
  CHECK(gv::mean_stiffness{}(3.0f, 1.0f, 2.0f) == 2.0f);
  CHECK(gv::mean_stiffness{}(1.0, 4.0, 12.0) == 0.125);
  CHECK(gv::mean_stiffness{}(5.0f, 10.0f, 10.0f) == 0.5f);
  // mean_cost: l (c_u + c_v) / 2
  CHECK(gv::mean_cost{}(2.0f, 1.0f, 3.0f) == 4.0f);
  CHECK(gv::mean_cost{}(0.5, 6.0, 0.0) == 1.5);
  CHECK(gv::mean_cost{}(3.0f, 0.0f, 0.0f) == 0.0f);  // zero cost: zero-weight edge
  // stiffness +inf (inside the stiffness rule): min picks the finite neighbour, mean goes to 0
  CHECK(gv::min_stiffness{}(1.0f, inf_v<float>, 4.0f) == 0.25f);
  CHECK(gv::mean_stiffness{}(1.0f, inf_v<float>, 4.0f) == 0.0f);
  // the steak's contrast: bone against meat is governed by the meat
  CHECK(gv::min_stiffness{}(1.0f, 1.5e10f, 2.0e4f) == 1.0f / 2.0e4f);
}

template <class T>
void formula_check(std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> len(0.1, 3.0), val(1e-3, 1e3);
  for (int t = 0; t < 2000; ++t) {
    const T l = T(len(rng)), a = T(val(rng)), b = T(val(rng));
    const long double L = l, A = a, B = b;
    auto close = [](T got, long double want) {
      // one rounding or two of T: well within 3 ulps
      const long double ulp = (long double)(std::nextafter(got, inf_v<T>) - got);
      return std::fabs((long double)got - want) <= 3 * ulp;
    };
    CHECK(close(gv::min_stiffness{}(l, a, b), L / std::min(A, B)));
    CHECK(close(gv::mean_stiffness{}(l, a, b), 2 * L / (A + B)));
    CHECK(close(gv::mean_cost{}(l, a, b), L * (A + B) / 2));
    CHECK(gv::uniform{}(l, a, b) == l);
    // the stiffness and cost weights are symmetric in the two field values, bit for bit
    CHECK(gvcore::bits_of(gv::min_stiffness{}(l, a, b)) == gvcore::bits_of(gv::min_stiffness{}(l, b, a)));
    CHECK(gvcore::bits_of(gv::mean_stiffness{}(l, a, b)) == gvcore::bits_of(gv::mean_stiffness{}(l, b, a)));
    CHECK(gvcore::bits_of(gv::mean_cost{}(l, a, b)) == gvcore::bits_of(gv::mean_cost{}(l, b, a)));
    // and non-negative
    CHECK(gv::mean_cost{}(l, a, b) >= T(0));
  }
}

TEST_CASE("metric: builtin weights follow the DESIGN formulas, float and double") {
  formula_check<float>(1);
  formula_check<double>(2);
}

template <class T>
void domain_rules() {
  CAPTURE(sizeof(T));
  // stiffness rule (uniform, min_stiffness, mean_stiffness): inside iff > 0
  for (auto in : {gv::detail::inside<gv::uniform, T>, gv::detail::inside<gv::min_stiffness, T>,
                  gv::detail::inside<gv::mean_stiffness, T>, gv::detail::inside<no_rule, T>}) {
    CHECK(in(T(1)));
    CHECK(in(T(1e-30)));
    CHECK(in(std::numeric_limits<T>::denorm_min()));
    CHECK(in(T(1.5e10)));
    CHECK(in(inf_v<T>));
    CHECK_FALSE(in(T(0)));
    CHECK_FALSE(in(-T(0)));
    CHECK_FALSE(in(T(-1)));
    CHECK_FALSE(in(-inf_v<T>));
    CHECK_FALSE(in(nan_v<T>));
    CHECK_FALSE(in(-nan_v<T>));
  }
  // cost rule (mean_cost): inside iff >= 0 and finite
  const auto cost = gv::detail::inside<gv::mean_cost, T>;
  CHECK(cost(T(0)));
  CHECK(cost(-T(0)));
  CHECK(cost(T(2)));
  CHECK(cost(std::numeric_limits<T>::max()));
  CHECK_FALSE(cost(-std::numeric_limits<T>::denorm_min()));
  CHECK_FALSE(cost(T(-1)));
  CHECK_FALSE(cost(inf_v<T>));
  CHECK_FALSE(cost(-inf_v<T>));
  CHECK_FALSE(cost(nan_v<T>));
  // the policy classes expose the same rules directly
  CHECK(gv::stiffness_domain::inside(T(3)));
  CHECK_FALSE(gv::stiffness_domain::inside(T(0)));
  CHECK(gv::cost_domain::inside(T(0)));
  CHECK_FALSE(gv::cost_domain::inside(inf_v<T>));
}

TEST_CASE("metric: domain rules") {
  domain_rules<float>();
  domain_rules<double>();
}

TEST_CASE("metric: a user metric's own inside() replaces the default") {
  CHECK(gv::detail::inside<own_rule>(7.0f));
  CHECK_FALSE(gv::detail::inside<own_rule>(1.0f));  // positive, yet outside under its own rule
  CHECK(gv::detail::inside<no_rule>(1.0f));
  CHECK_FALSE(gv::detail::inside<no_rule>(0.0f));
}

}  // namespace

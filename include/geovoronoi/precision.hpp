#pragma once
/// @file precision.hpp
/// @brief Whether float is enough: values that survive the conversion to a distance type, and a
///        bound on a problem's distances that says when a solve in float could overflow.
///
/// The solvers compute distances in the field's type T and throw geovoronoi::overflow_error when a
/// distance overflows T (docs/errors.md, "Overflow"). These helpers let a caller choose T before
/// solving: `needs_double()` is what the command line's `--precision auto` asks.
///
/// @code
/// std::vector<double> field = ...;   // read in double
/// if (geovoronoi::needs_double(g, field.data(), field.size(), geovoronoi::min_stiffness{}, geovoronoi::connectivity<26>{}))
///   solve_in<double>(...);
/// else
///   solve_in<float>(...);
/// @endcode

#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/metric.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <type_traits>

namespace geovoronoi {

/**
 * @brief Whether @p x keeps its kind when converted to T: a finite non-zero value stays finite and
 *        non-zero (it neither overflows to +-inf nor underflows to 0); 0, +-inf and NaN stay what
 *        they are and count as fitting. Subnormal results fit (they are not 0), with fewer digits.
 */
template <class T>
bool fits_in(double x) noexcept {
  static_assert(std::is_floating_point_v<T>, "fits_in<T>: T must be a floating-point type");
  if (!(x == x) || x == 0 || std::isinf(x)) return true;
  const double a = std::fabs(x);
  return a <= double(std::numeric_limits<T>::max()) && static_cast<T>(a) != T(0);
}

/**
 * @brief Whether @p x is 0, not finite, or within T's normal range ([min, max] in magnitude): the
 *        values a field in T can hold at full precision.
 */
template <class T>
bool normal_in(double x) noexcept {
  if (!(x == x) || x == 0 || std::isinf(x)) return true;
  const double a = std::fabs(x);
  return a <= double(std::numeric_limits<T>::max()) && a >= double(std::numeric_limits<T>::min());
}

/// What precision needs to know of a field: its domain's smallest and largest value and size.
struct field_range {
  double smallest = std::numeric_limits<double>::infinity();  ///< smallest value inside the domain
  double largest = -std::numeric_limits<double>::infinity();  ///< largest value inside the domain
  index_t inside = 0;                                          ///< voxels inside the domain
};

/// @brief The range of the @p n values of @p field inside @p Metric's domain (computed in double).
template <class Metric, class U>
field_range range_of(const U* field, std::size_t n, Metric = {}) {
  field_range r;
  for (std::size_t i = 0; i < n; ++i) {
    const double x = double(field[i]);
    if (!detail::inside<Metric>(x)) continue;
    r.smallest = std::min(r.smallest, x);
    r.largest = std::max(r.largest, x);
    ++r.inside;
  }
  return r;
}

/**
 * @brief An upper bound (in double) of every finite geodesic distance of a problem: the largest
 *        edge weight times the longest simple path (the domain's voxels - 1 edges).
 *
 * The largest weight is taken over the metric at the longest stencil edge and the pairs of the
 * domain's extreme values, which bounds the built-in metrics (monotone in each value) and any user
 * metric monotone in its arguments. Seeds start at distance 0. +inf when the bound itself overflows
 * double. Far from tight (a real path is much shorter): a bound below T's largest value proves a
 * solve in T cannot overflow; a bound above says only that it might.
 */
template <class Metric, int Dim, int N, class U>
double distance_bound(const grid<Dim>& g, const U* field, std::size_t n, Metric m = {}, connectivity<N> = {}) {
  static_assert(connectivity<N>::dim == Dim, "distance_bound: the connectivity's dimension differs from the grid's");
  static_assert(detail::is_metric_v<Metric, double>, "distance_bound: the metric must be callable with double values");
  const field_range r = range_of<Metric>(field, n);
  if (r.inside <= 1) return 0;
  constexpr auto offs = connectivity<N>::offsets();
  double longest = 0;
  for (int k = 0; k < N; ++k) {
    double len2 = 0;
    for (int a = 0; a < Dim; ++a) {
      const double c = offs[k][a] * g.spacing(a);
      len2 += c * c;
    }
    longest = std::max(longest, std::sqrt(len2));
  }
  double w = 0;
  for (double a : {r.smallest, r.largest})
    for (double b : {r.smallest, r.largest}) {
      const double x = m(longest, a, b);
      if (x == x) w = std::max(w, x);
    }
  return w * double(r.inside - 1);
}

/**
 * @brief Whether a solve in T might overflow or lose the field: some value inside the domain is
 *        outside T's normal range (it would round to 0 or +-inf, or lose digits), an edge length is
 *        not a normal T, or distance_bound() exceeds T's largest value.
 */
template <class T, class Metric, int Dim, int N, class U>
bool may_overflow(const grid<Dim>& g, const U* field, std::size_t n, Metric m = {}, connectivity<N> c = {}) {
  const field_range r = range_of<Metric>(field, n);
  if (r.inside > 0 && (!normal_in<T>(r.smallest) || !normal_in<T>(r.largest))) return true;
  for (int a = 0; a < Dim; ++a)
    if (!normal_in<T>(g.spacing(a)) || !normal_in<T>(g.spacing(a) * 2)) return true;
  return !(distance_bound(g, field, n, m, c) <= double(std::numeric_limits<T>::max()));
}

/// @brief may_overflow<float>: whether a problem should be solved in double (`--precision auto`).
template <class Metric, int Dim, int N, class U>
bool needs_double(const grid<Dim>& g, const U* field, std::size_t n, Metric m = {}, connectivity<N> c = {}) {
  return may_overflow<float>(g, field, n, m, c);
}

}  // namespace geovoronoi

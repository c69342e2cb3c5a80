#pragma once
/// @file voronoi.hpp
/// @brief The solver entry points. Each takes a backend policy first (geovoronoi::seq,
///        geovoronoi::thrust::par, geovoronoi::cuda::par), checks and normalises its arguments once,
///        and hands them to the backend through detail/dispatch.hpp. A first argument that is not a
///        policy (is_backend_policy), or a backend that lacks an operation, is a compile error.

#include <geovoronoi/detail/dispatch.hpp>
#include <geovoronoi/detail/overflow.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/validate.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi {

namespace detail {
/// Makes a parameter a non-deduced context (std::type_identity before C++20).
template <class T>
struct same_type {
  using type = T;
};

template <class P, class Seeds>
std::vector<source<typename P::value_type>> seeds_to_sources(const P& p, const Seeds& seeds) {
  std::vector<source<typename P::value_type>> s;
  label_t i = 0;
  for (const auto& c : seeds) {
    if (i == std::numeric_limits<label_t>::max()) throw std::invalid_argument("geovoronoi: too many seeds for 32-bit labels");
    s.push_back({checked_voxel(p, coord<P::dim>(c), "seed", std::size_t(i)), typename P::value_type(0), i});
    ++i;
  }
  return s;
}

/// Sources with an initial distance of -0 replaced by +0. -0 passes the ">= 0" check, but its sign
/// bit would make its packed (distance, label) key larger than every positive distance's.
template <class T>
std::vector<source<T>> without_negative_zero(std::vector<source<T>> s) {
  for (auto& x : s)
    if (x.distance == T(0)) x.distance = T(0);
  return s;
}
template <class T>
bool has_negative_zero(const std::vector<source<T>>& s) {
  for (const auto& x : s)
    if (x.distance == T(0) && std::signbit(x.distance)) return true;
  return false;
}

/// solve_options::max_distance as a radius in T: NaN is an error, beyond T's range is +inf (a plain
/// cast would be undefined there). The one conversion every backend sees.
template <class T>
T checked_radius(const solve_options& opt) {
  if (opt.max_distance != opt.max_distance)
    throw std::invalid_argument("geovoronoi: solve_options::max_distance is NaN");
  const T r = radius_in<T>(opt.max_distance);
  // a positive bound that rounds to 0 would silently reach nothing but the sources at 0 (a bound
  // beyond T's range is +inf: no finite distance in T reaches it anyway, the same result)
  if (opt.max_distance > 0 && r == T(0))
    throw std::invalid_argument("geovoronoi: solve_options::max_distance " + detail::short_number(opt.max_distance) +
                                " rounds to 0 in the distance type (" +
                                (std::is_same_v<T, float> ? "float" : "double") +
                                "); use a double field or rescale the field or the spacing");
  return r;
}
template <class T>
T checked_radius(T radius, const char* who) {
  if (radius != radius) throw std::invalid_argument(std::string("geovoronoi: ") + who + " radius is NaN");
  return radius;
}
}  // namespace detail

/**
 * @brief Geodesic Voronoi diagram of @p seeds: every voxel's distance to its nearest seed and that
 *        seed's index, ties going to the lowest index.
 *
 * @param policy backend, e.g. geovoronoi::seq.
 * @param p      the problem (make_problem()).
 * @param seeds  a range of voxel coordinates (coord<Dim>); label i is the i-th seed.
 * @param opt    parent image, radius bound, progress callback, host threads.
 * @return the diagram; bitwise identical for every backend (and for every opt.threads).
 * @throws std::invalid_argument if the list is empty, or a seed lies outside the grid, on a masked
 *         voxel, or on the same voxel as another seed (the message names the seed).
 * @throws geovoronoi::overflow_error if, with no radius bound, a distance overflows T (a voxel that
 *         a path reaches would come out unreachable); the message names the voxel and the value.
 * @throws geovoronoi::cancelled when opt.progress returns false.
 *
 * @code
 * auto p = geovoronoi::make_problem(g, stiffness, geovoronoi::min_stiffness{}, geovoronoi::connectivity<26>{});
 * auto d = geovoronoi::voronoi(geovoronoi::seq, p, std::vector<geovoronoi::coord<3>>{{0, 0, 0}, {9, 9, 9}});
 * float far = d.distance({5, 5, 5});  int owner = d.label({5, 5, 5});
 * @endcode
 */
template <class Policy, class P, class Seeds>
diagram<typename P::value_type, P::dim> voronoi(const Policy& policy, const P& p, const Seeds& seeds,
                                                const solve_options& opt = {}) {
  detail::require_policy<Policy>();
  const auto s = detail::seeds_to_sources(p, seeds);
  detail::validate_sources(p, s);
  return detail::with_threads(policy, opt.threads, [&] {
    return detail::dispatch::solve(policy, p, s, detail::checked_radius<typename P::value_type>(opt), opt.with_parent,
                                   detail::solve_control::of(opt));
  });
}

/// @brief The same, building the problem from its parts:
///        `voronoi(seq, grid, field, seeds, min_stiffness{}, connectivity<26>{})`.
template <class Policy, int Dim, class Field, class Seeds, class Metric, int N>
auto voronoi(const Policy& policy, const grid<Dim>& g, const Field& field, const Seeds& seeds, Metric metric,
             connectivity<N> conn, const solve_options& opt = {}) {
  detail::require_policy<Policy>();
  return voronoi(policy, make_problem(g, field, metric, conn), seeds, opt);
}

/**
 * @brief General multi-source solve: each source starts at its own initial distance and spreads its
 *        own label (labels may repeat, voxels may not).
 * @throws std::invalid_argument on an empty list, a bad voxel, a duplicate voxel, a negative label or
 *         a negative or non-finite initial distance.
 */
template <class Policy, class P>
diagram<typename P::value_type, P::dim> geodesic_solve(const Policy& policy, const P& p,
                                                       const std::vector<source<typename P::value_type>>& sources,
                                                       const solve_options& opt = {}) {
  detail::require_policy<Policy>();
  detail::validate_sources(p, sources, "source");
  const auto radius = detail::checked_radius<typename P::value_type>(opt);
  const auto ctl = detail::solve_control::of(opt);
  return detail::with_threads(policy, opt.threads, [&] {
    if (detail::has_negative_zero(sources))
      return detail::dispatch::solve(policy, p, detail::without_negative_zero(sources), radius, opt.with_parent, ctl);
    return detail::dispatch::solve(policy, p, sources, radius, opt.with_parent, ctl);
  });
}

/**
 * @brief Bounded solve: the voxels whose distance from the sources is < @p radius, as a sparse list
 *        sorted by voxel index. Scratch memory grows with the voxels reached, not with the grid.
 * @param opt progress callback and threads (its max_distance and with_parent are not used here).
 * @throws geovoronoi::overflow_error when @p radius is +inf and a distance overflows T;
 *         geovoronoi::cancelled when the progress callback asks to stop.
 */
template <class Policy, class P>
sparse_solution<typename P::value_type> bounded_solve(const Policy& policy, const P& p,
                                                      const std::vector<source<typename P::value_type>>& sources,
                                                      typename P::value_type radius, const solve_options& opt = {}) {
  detail::require_policy<Policy>();
  detail::validate_sources(p, sources, "source");
  detail::checked_radius(radius, "bounded_solve");
  const auto ctl = detail::solve_control::of(opt);
  return detail::with_threads(policy, opt.threads, [&] {
    if (detail::has_negative_zero(sources))
      return detail::dispatch::bounded(policy, p, detail::without_negative_zero(sources), radius, ctl);
    return detail::dispatch::bounded(policy, p, sources, radius, ctl);
  });
}

/// @brief Single-source solve from voxel @p s, bounded by @p radius (default: unbounded), sparse;
///        @p opt as for bounded_solve().
template <class Policy, class P>
sparse_solution<typename P::value_type> single_source(
    const Policy& policy, const P& p, const coord<P::dim>& s,
    typename P::value_type radius = std::numeric_limits<typename P::value_type>::infinity(),
    const solve_options& opt = {}) {
  using T = typename P::value_type;
  detail::require_policy<Policy>();
  const index_t v = detail::checked_voxel(p, s, "source");
  detail::checked_radius(radius, "single_source");
  const auto ctl = detail::solve_control::of(opt);
  return detail::with_threads(policy, opt.threads, [&] {
    return detail::dispatch::bounded(policy, p, std::vector<source<T>>{{v, T(0), 0}}, radius, ctl);
  });
}

/**
 * @brief New cells of many query voxels, each inserted alone into @p d (which is not modified).
 *
 * For query q: the voxels v with d_q(v) < d.distance(v), d_q the geodesic distance from q under the
 * same problem, each with d_q(v) and its owner in @p d. See query_cells. Scratch memory per query is
 * proportional to its cell.
 * @throws std::invalid_argument if @p d was computed on another grid, or a query lies outside the grid
 *         or on a masked voxel.
 */
template <class Policy, class P>
query_cells<typename P::value_type> insert_queries(const Policy& policy, const P& p,
                                                   const diagram<typename P::value_type, P::dim>& d,
                                                   const std::vector<index_t>& queries) {
  detail::require_policy<Policy>();
  detail::check_diagram(p, d);
  for (std::size_t i = 0; i < queries.size(); ++i) detail::checked_voxel(p, queries[i], "query", i);
  return detail::dispatch::insert_queries(policy, p, d, queries);
}

/// @brief The same with voxel coordinates.
template <class Policy, class P>
query_cells<typename P::value_type> insert_queries(const Policy& policy, const P& p,
                                                   const diagram<typename P::value_type, P::dim>& d,
                                                   const std::vector<coord<P::dim>>& queries) {
  detail::require_policy<Policy>();
  detail::check_diagram(p, d);
  std::vector<index_t> q;
  q.reserve(queries.size());
  for (std::size_t i = 0; i < queries.size(); ++i) q.push_back(detail::checked_voxel(p, queries[i], "query", i));
  return detail::dispatch::insert_queries(policy, p, d, q);
}

/// @brief New cell of one query voxel @p q (see insert_queries).
template <class Policy, class P>
query_cell<typename P::value_type> insert_query(const Policy& policy, const P& p,
                                                const diagram<typename P::value_type, P::dim>& d,
                                                const coord<P::dim>& q) {
  detail::require_policy<Policy>();
  auto cells = insert_queries(policy, p, d, std::vector<coord<P::dim>>{q});
  query_cell<typename P::value_type> c;
  c.query = cells.query[0];
  c.voxel = std::move(cells.voxel);
  c.distance = std::move(cells.distance);
  c.owner = std::move(cells.owner);
  return c;
}

/// @brief Voxel coordinates of world points, each rounded to the nearest voxel centre
///        (grid::nearest_voxel).
/// @throws std::invalid_argument naming the seed and the world point as given when a point is not
///         finite or its voxel lies outside the grid (grid::checked_nearest_voxel).
template <int Dim>
std::vector<coord<Dim>> seeds_from_world(const grid<Dim>& g,
                                         const typename detail::same_type<std::vector<point<Dim>>>::type& points) {
  // Dim is deduced from the grid only: deducing it from std::array<double, Dim> would fail, since
  // std::array's size parameter is a std::size_t and Dim an int.
  std::vector<coord<Dim>> out;
  out.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    try {
      out.push_back(g.checked_nearest_voxel(points[i]));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("geovoronoi::seeds_from_world: seed " + std::to_string(i) + ": " + e.what());
    }
  }
  return out;
}

}  // namespace geovoronoi

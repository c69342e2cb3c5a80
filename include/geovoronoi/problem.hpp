#pragma once
/// @file problem.hpp
/// @brief A geodesic problem: the grid, the field, the metric and the connectivity, bundled into one
///        trivially copyable view that every backend (and every kernel) takes.

#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/metric.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi {

/// The cut policy of a problem without cuts: every edge of the stencil exists. An empty tag, so a
/// problem without cuts has the same size and layout as before cuts existed, and every cut test
/// folds to a constant.
struct no_cuts {};

namespace detail {
/// Base of problem that holds its cuts: nothing for no_cuts (empty base optimisation), a cut_view
/// otherwise.
template <class Cuts>
struct cut_holder;
template <>
struct cut_holder<no_cuts> {
  static constexpr bool has_cuts = false;
  /// No direction is ever cut.
  GEOVORONOI_HOST_DEVICE static constexpr cut_mask_t cut_mask(index_t) noexcept { return 0; }
};
template <>
struct cut_holder<cut_view> {
  static constexpr bool has_cuts = true;
  cut_view cuts{};  ///< the cut edges (the table it views must outlive the problem)
  /// Mask of the cut stencil directions at voxel @p v (bit k: the edge to neighbour k is cut).
  GEOVORONOI_HOST_DEVICE cut_mask_t cut_mask(index_t v) const noexcept { return cuts.incident(v); }
};
}  // namespace detail

/**
 * @brief Everything that defines the weighted grid graph: grid, per-voxel field (stiffness or cost,
 *        not owned), metric and connectivity resolved into a stencil.
 *
 * @tparam T      field and distance type: float or double.
 * @tparam Dim    2 or 3.
 * @tparam Metric edge-weight policy (see metric.hpp).
 * @tparam N      connectivity (4, 8 in 2D; 6, 18, 26 in 3D).
 * @tparam Cuts   no_cuts (the default: every stencil edge exists) or cut_view (the edges of a
 *                cut_table are removed from the graph, both directions; see with_cuts()).
 *
 * The field (and the cut table, if any) must outlive the problem. Build one with make_problem().
 */
template <class T, int Dim, class Metric, int N, class Cuts = no_cuts>
struct problem : detail::cut_holder<Cuts> {
  static_assert(std::is_same_v<T, float> || std::is_same_v<T, double>,
                "geovoronoi::problem: the field/distance type must be float or double");
  static_assert(connectivity<N>::dim == Dim,
                "geovoronoi::problem: connectivity<4|8> needs a 2D grid, connectivity<6|18|26> a 3D grid");
  static_assert(detail::is_metric_v<Metric, T>,
                "geovoronoi::problem: Metric must be callable as T(T length, T from, T to) const");
  static_assert(std::is_trivially_copyable_v<Metric>, "geovoronoi::problem: Metric must be trivially copyable");

  using value_type = T;
  using metric_type = Metric;
  using connectivity_type = connectivity<N>;
  using cuts_type = Cuts;
  static_assert(std::is_same_v<Cuts, no_cuts> || std::is_same_v<Cuts, cut_view>,
                "geovoronoi::problem: Cuts must be no_cuts or cut_view");
  static constexpr int dim = Dim;
  static constexpr int neighbours = N;

  grid<Dim> geometry{};
  const T* field = nullptr;
  Metric metric{};
  stencil<T, Dim, N> edges{};

  /// Whether voxel @p v belongs to the domain under the metric's mask rule.
  GEOVORONOI_HOST_DEVICE bool inside(index_t v) const noexcept { return detail::inside<Metric>(field[v]); }
  /// Weight of the edge from @p from to its neighbour number @p n, @p to.
  GEOVORONOI_HOST_DEVICE T weight(index_t from, index_t to, int n) const noexcept {
    return detail::search::edge_weight(metric, edges.length[n], field[from], field[to]);
  }
};

namespace detail {
template <class T>
struct field_ref {
  const T* data;
  std::size_t size;
};
template <class T, int Dim>
field_ref<T> as_field(const image<T, Dim>& f, const grid<Dim>& g) {
  if (f.geometry().extents() != g.extents())
    throw std::invalid_argument("geovoronoi: the field image's extents differ from the grid's");
  return {f.data(), static_cast<std::size_t>(f.size())};
}
template <class T, int Dim>
field_ref<std::remove_const_t<T>> as_field(const image_view<T, Dim>& f, const grid<Dim>& g) {
  if (f.geometry().extents() != g.extents())
    throw std::invalid_argument("geovoronoi: the field view's extents differ from the grid's");
  return {f.data(), static_cast<std::size_t>(f.size())};
}
template <class T, class A, int Dim>
field_ref<T> as_field(const std::vector<T, A>& f, const grid<Dim>&) {
  return {f.data(), f.size()};
}

/// Every edge length of connectivity<N> on @p g must be finite and non-zero once rounded to T:
/// a spacing that is valid in double can still underflow to 0 or overflow to +inf in float, which
/// would make all distances 0 or every voxel unreachable. Checked in double, before the cast.
template <class T, int Dim, int N>
void check_edge_lengths(const grid<Dim>& g) {
  constexpr auto offs = connectivity<N>::offsets();
  for (int n = 0; n < N; ++n) {
    double len2 = 0;
    for (int a = 0; a < Dim; ++a) {
      const double c = offs[n][a] * g.spacing(a);
      len2 += c * c;
    }
    const double len = std::sqrt(len2);
    if (!(len <= double(std::numeric_limits<T>::max())) || !(static_cast<T>(len) > T(0)))
      throw std::invalid_argument("geovoronoi: the grid's spacing gives an edge of length " + std::to_string(len) +
                                  ", which is 0 or infinite in the distance type; rescale the spacing");
  }
}
}  // namespace detail

/**
 * @brief Bundle a grid, a field, a metric and a connectivity into a problem.
 *
 * @param g      the grid.
 * @param field  g.size() values, x fastest: a std::vector<T>, an image<T, Dim> or an image_view.
 * @param metric edge-weight policy, e.g. geovoronoi::min_stiffness{}.
 * @param conn   e.g. geovoronoi::connectivity<26>{}.
 * @throws std::invalid_argument if the field's size does not match the grid.
 *
 * @code
 * std::vector<float> stiffness(g.size(), 1.0f);
 * auto p = geovoronoi::make_problem(g, stiffness, geovoronoi::min_stiffness{}, geovoronoi::connectivity<26>{});
 * @endcode
 */
template <int Dim, class Field, class Metric = min_stiffness, int N = (Dim == 2 ? 8 : 26)>
auto make_problem(const grid<Dim>& g, const Field& field, Metric metric = {}, connectivity<N> conn = {}) {
  const auto f = detail::as_field(field, g);
  using T = std::remove_const_t<std::remove_pointer_t<decltype(f.data)>>;
  static_assert(connectivity<N>::dim == Dim,
                "geovoronoi::make_problem: connectivity<4|8> needs a 2D grid, connectivity<6|18|26> a 3D grid");
  if (static_cast<index_t>(f.size) != g.size())
    throw std::invalid_argument("geovoronoi: the field has " + std::to_string(f.size) + " values but the grid has " +
                                std::to_string(g.size()) + " voxels");
  if (g.size() == 0) throw std::invalid_argument("geovoronoi: the grid is empty");
  detail::check_edge_lengths<T, Dim, N>(g);
  problem<T, Dim, Metric, N> p;
  p.geometry = g;
  p.field = f.data;
  p.metric = metric;
  p.edges = stencil<T, Dim, N>(g, conn);
  return p;
}

/**
 * @brief The problem @p p with the edges of @p cuts removed from its graph (both directions of each
 *        cut edge). The table must have been built from a cut_set of @p p's grid and connectivity,
 *        and must outlive the result.
 *
 * A problem with cuts is a distinct type (problem<..., cut_view>): code that never calls with_cuts
 * compiles exactly as before.
 * @throws std::invalid_argument if @p p already carries cuts (merge the cut_sets instead).
 *
 * @code
 * geovoronoi::cut_table table(cut_set);
 * auto pc = geovoronoi::with_cuts(p, table);
 * auto d = geovoronoi::voronoi(geovoronoi::seq, pc, seeds);
 * @endcode
 */
template <class T, int Dim, class Metric, int N>
problem<T, Dim, Metric, N, cut_view> with_cuts(const problem<T, Dim, Metric, N>& p, const cut_table& cuts) {
  problem<T, Dim, Metric, N, cut_view> q;
  q.geometry = p.geometry;
  q.field = p.field;
  q.metric = p.metric;
  q.edges = p.edges;
  q.cuts = cuts.view();
  return q;
}
/// The cut table must outlive the problem: a temporary would dangle.
template <class T, int Dim, class Metric, int N>
void with_cuts(const problem<T, Dim, Metric, N>&, cut_table&&) = delete;

/// The problem @p p without its cuts (the same grid, field, metric and connectivity).
template <class T, int Dim, class Metric, int N, class C>
problem<T, Dim, Metric, N> without_cuts(const problem<T, Dim, Metric, N, C>& p) {
  problem<T, Dim, Metric, N> q;
  q.geometry = p.geometry;
  q.field = p.field;
  q.metric = p.metric;
  q.edges = p.edges;
  return q;
}

/// @brief A temporary field would be destroyed at the end of the statement while the problem still
///        points at it: make_problem takes a field that outlives the problem (a named vector or image,
///        or an image_view), never a temporary owner.
template <int Dim, class T, class A, class... Rest>
void make_problem(const grid<Dim>&, std::vector<T, A>&&, Rest&&...) = delete;
/// @copydoc make_problem(const grid<Dim>&, std::vector<T, A>&&, Rest&&...)
template <int Dim, class T, class A, class... Rest>
void make_problem(const grid<Dim>&, const std::vector<T, A>&&, Rest&&...) = delete;
/// @copydoc make_problem(const grid<Dim>&, std::vector<T, A>&&, Rest&&...)
template <int Dim, class T, class... Rest>
void make_problem(const grid<Dim>&, image<T, Dim>&&, Rest&&...) = delete;
/// @copydoc make_problem(const grid<Dim>&, std::vector<T, A>&&, Rest&&...)
template <int Dim, class T, class... Rest>
void make_problem(const grid<Dim>&, const image<T, Dim>&&, Rest&&...) = delete;

}  // namespace geovoronoi

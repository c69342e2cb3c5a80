#pragma once
/// @file shape_update.hpp
/// @brief Shape functions after a change of the problem (cuts, carving, added or restiffened voxels,
///        node edits): only the rows whose weights can change are recomputed, and the result is
///        bitwise identical to shape_functions() (or shape_functions_at()) on the changed problem.
///
/// Why the recomputed set is sufficient is written down in docs/shape-functions.md ("After a
/// change"); detail/shape/update_rows.hpp holds the searches that find it.

#include <geovoronoi/shape_functions.hpp>
#include <geovoronoi/detail/shape/update_rows.hpp>
#include <geovoronoi/update.hpp>

#include <cstddef>
#include <vector>

namespace geovoronoi {

/// What an update of shape functions did.
struct shape_update_stats {
  /// Rows of the weights (voxels of the grid, or points).
  std::size_t rows = 0;
  /// Rows recomputed; every other row was copied (with its node indices renumbered after node edits).
  std::size_t recomputed = 0;
  /// Recomputed rows whose weights differ from the row before (after renumbering).
  std::size_t changed = 0;
  /// Voxels whose distance, label or field changed, or that end a newly cut edge (the set X of
  /// docs/shape-functions.md).
  std::size_t changed_voxels = 0;
  /// Voxels of the grid whose rows are recomputed (R of docs/shape-functions.md): X and the voxels a
  /// change can reach; `recomputed` counts the rows (points) that fall in it.
  std::size_t region_voxels = 0;
  /// Distance Ratio: nodes whose contribution can change (their per-node solves are redone).
  std::size_t nodes_affected = 0;
  /// True when every row was recomputed because no smaller set could be proven sufficient (see
  /// docs/shape-functions.md: a grid too large for the rounding bound, or node edits that reorder
  /// the surviving nodes).
  bool full = false;
};

/**
 * @brief Updates the shape functions @p w of the problem before a change, in place, into those of
 *        @p after: afterwards @p w equals `shape_functions(policy, after, d_after, opt)` bit for bit.
 *
 * @param after    the problem after the change (as for geovoronoi::update()).
 * @param d_before the diagram @p w was computed on (the problem before the change).
 * @param d_after  the diagram of @p after, e.g. `update(policy, after, d_before, c)` or a full solve;
 *                 its node list must be d_before's with the change's node edits applied.
 * @param w        shape functions computed by shape_functions() on d_before with the same @p opt
 *                 (method and K): the method is not stored in the weights, so it cannot be checked.
 * @param c        the change: a geovoronoi::change, a cut_set of newly cut edges or a carving.
 * @param opt      the options @p w was computed with; progress and stats refer to the recomputed rows.
 * @return what the update did: rows recomputed, rows changed, voxels changed.
 * @throws std::invalid_argument as shape_functions(), and when @p w or @p d_before does not belong
 *         to @p after's grid, @p w's K or node count does not match, a voxel of @p c lies outside the
 *         grid, or d_after's nodes are not d_before's with the node edits applied.
 */
template <class Policy, class P, class Change>
shape_update_stats update_shape_functions_in_place(const Policy& policy, const P& after,
                                                   const diagram<typename P::value_type, P::dim>& d_before,
                                                   const diagram<typename P::value_type, P::dim>& d_after,
                                                   shape_weights<typename P::value_type, P::dim>& w, const Change& c,
                                                   const shape_options& opt = {}) {
  detail::require_policy<Policy>();
  detail::shape::validate(after, d_after, opt);
  if (!(w.geometry == after.geometry) || w.node.size() != std::size_t(after.geometry.size()) * std::size_t(w.k) ||
      w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::update_shape_functions: the weights were computed on another grid");
  const auto chg = detail::shape::as_change<P::dim>(c);
  shape_update_stats s;
  detail::shape::update_rows(policy, after, d_before, d_after, chg, opt, w.k, w.nodes, nullptr, w.node, w.weight, s,
                             &w.update_state);
  return s;
}

/**
 * @brief The shape functions of @p after from those before a change: a copy of @p w_before updated by
 *        update_shape_functions_in_place(). @p stats, when given, receives what the update did.
 */
template <class Policy, class P, class Change>
shape_weights<typename P::value_type, P::dim> update_shape_functions(
    const Policy& policy, const P& after, const diagram<typename P::value_type, P::dim>& d_before,
    const diagram<typename P::value_type, P::dim>& d_after, const shape_weights<typename P::value_type, P::dim>& w_before,
    const Change& c, const shape_options& opt = {}, shape_update_stats* stats = nullptr) {
  auto w = w_before;
  const auto s = update_shape_functions_in_place(policy, after, d_before, d_after, w, c, opt);
  if (stats) *stats = s;
  return w;
}

/**
 * @brief Updates weights at chosen points (shape_functions_at()) after a change, in place: afterwards
 *        @p w equals `shape_functions_at(policy, after, d_after, points, opt)` bit for bit, the points
 *        being those @p w was evaluated at (w.voxel). Same parameters and errors as
 *        update_shape_functions_in_place(); the rows are the points.
 */
template <class Policy, class P, class Change>
shape_update_stats update_shape_functions_at_in_place(const Policy& policy, const P& after,
                                                      const diagram<typename P::value_type, P::dim>& d_before,
                                                      const diagram<typename P::value_type, P::dim>& d_after,
                                                      point_weights<typename P::value_type>& w, const Change& c,
                                                      const shape_options& opt = {}) {
  detail::require_policy<Policy>();
  detail::shape::validate(after, d_after, opt);
  if (w.voxel.size() != w.points || w.node.size() != w.points * std::size_t(w.k) || w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::update_shape_functions_at: the point weights' arrays do not hold points * k entries");
  for (std::size_t i = 0; i < w.points; ++i)
    if (w.voxel[i] < 0 || w.voxel[i] >= after.geometry.size())
      throw std::invalid_argument("geovoronoi::update_shape_functions_at: point " + std::to_string(i) +
                                  " has voxel index " + std::to_string(w.voxel[i]) + ", outside the grid");
  const auto chg = detail::shape::as_change<P::dim>(c);
  shape_update_stats s;
  detail::shape::update_rows(policy, after, d_before, d_after, chg, opt, w.k, w.nodes, &w.voxel, w.node, w.weight, s);
  return s;
}

/// @brief A copy of @p w_before updated by update_shape_functions_at_in_place().
template <class Policy, class P, class Change>
point_weights<typename P::value_type> update_shape_functions_at(
    const Policy& policy, const P& after, const diagram<typename P::value_type, P::dim>& d_before,
    const diagram<typename P::value_type, P::dim>& d_after, const point_weights<typename P::value_type>& w_before,
    const Change& c, const shape_options& opt = {}, shape_update_stats* stats = nullptr) {
  auto w = w_before;
  const auto s = update_shape_functions_at_in_place(policy, after, d_before, d_after, w, c, opt);
  if (stats) *stats = s;
  return w;
}

}  // namespace geovoronoi

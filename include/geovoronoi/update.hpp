#pragma once
/// @file update.hpp
/// @brief Incremental update of a Voronoi diagram after a change of its problem — cut edges, voxels
///        carved out of or added to the domain, field values changed, nodes added, removed or moved —
///        bitwise identical to a full solve of the changed problem (distances, labels and parents,
///        ties included), in work proportional to the region whose keys or parents change.
///
/// Why it is exact (docs/cuts.md, "Incremental update"): a voxel is kept ("valid") when every edge
/// of its parent chain to its node still exists and still yields a key no larger than the old one;
/// its old key is then an upper bound that a path of the new graph reaches. The other voxels (the
/// subtrees below a cut or heavier tree edge, a carved voxel, a removed node) are invalidated. The
/// old keys satisfy key(v) <= key(u) + w(u, v) on every unchanged edge, so a Dijkstra that may lower
/// any key, started from the invalidated voxels (seeded by their valid neighbours), the changed
/// voxels and the new sources, reaches the least fixed point of the new problem: the full solve's.
/// Parents are recomputed, with the library's rule (the lowest-index neighbour that realises the
/// key), wherever a key or an incident edge changed and next to it: nowhere else can the set of
/// realising neighbours change. A key that rounding left without any realiser (see apply()) is
/// re-solved with its subtree; once every reached voxel has a realiser, the keys are the unique
/// solution the full solve computes.

#include <geovoronoi/change.hpp>
#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/update/apply.hpp>
#include <geovoronoi/detail/update/node_list.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <vector>

namespace geovoronoi {

/**
 * @brief Updates diagram @p d, in place, after the edges of @p added were cut: afterwards it equals
 *        `voronoi(policy, after, seeds, {with_parent = true})` bit for bit (distances, labels,
 *        parents), where seeds are the diagram's own.
 *
 * @param after the problem after the change: it must carry cuts (with_cuts()) that include every
 *              edge of @p added, and otherwise be the problem @p d was solved on.
 * @param d     a diagram of voronoi() on the problem before the change, computed with parents
 *              (solve_options::with_parent); the update follows its shortest-path tree.
 * @param added the newly cut edges (a cut_set of the same grid and connectivity).
 * @return what the update did. Work: the invalidated subtrees and their neighbours (times the
 *         connectivity, plus a radix-heap Dijkstra over them) and one bit per voxel of scratch.
 *
 * Every backend policy runs the same host algorithm (the diagram is host memory); its result is
 * what every backend's full solve returns.
 * @throws std::invalid_argument when @p d has no parents, grids or connectivities differ, or an
 *         edge of @p added is not cut in @p after.
 */
template <class Policy, class P>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const cut_set<P::dim>& added) {
  detail::require_policy<Policy>();
  static_assert(P::has_cuts, "geovoronoi::update: the problem after a cut must carry its cuts (with_cuts)");
  detail::update::edit_refs<P::dim> e;
  e.cut = &added;
  return detail::update::apply(after, d, e);
}

/**
 * @brief Updates diagram @p d, in place, after the voxels @p carved were removed from the domain
 *        (their field values made outside values in @p after): afterwards it equals
 *        `voronoi(policy, after, seeds, {with_parent = true})` bit for bit. Same contract and work
 *        bound as the cut form; a carved voxel is one more root (its whole subtree is re-solved).
 * @throws std::invalid_argument as the cut form, and when a carved voxel is outside the grid, still
 *         inside the domain of @p after, or a seed.
 */
template <class Policy, class P>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const carving& carved) {
  detail::require_policy<Policy>();
  detail::update::edit_refs<P::dim> e;
  e.carved = &carved.voxels;
  return detail::update::apply(after, d, e);
}

/**
 * @brief Updates diagram @p d, in place, after the change @p c (cuts, carved, added and
 *        restiffened voxels, node edits, in any combination): afterwards it equals
 *        `voronoi(policy, after, nodes, {with_parent = true})` bit for bit (distances, labels,
 *        parents), where nodes is the diagram's node list with the edits of @p c applied, and
 *        `d.seeds` is that list.
 *
 * Labels are positions in the new node list, exactly as in a full solve: inserting a node at
 * position i moves the labels >= i up by one, removing node i moves those > i down by one, moving a
 * node keeps its label. Old nodes keep their relative order unless the edits reorder them, so old
 * ties keep their outcome; a node whose order relative to the others changes is treated as removed
 * and added again. When labels move, every voxel's label is rewritten (one linear pass over the
 * label image); otherwise nothing outside the affected region is read.
 *
 * @param after the problem after the change (see change for what must differ).
 * @param d     a diagram of voronoi() on the problem before the change, with parents.
 * @param c     the change.
 * @return what the update did. Work: the invalidated subtrees, the voxels whose key decreased, the
 *         changed voxels, and their neighbours (times the connectivity, plus a radix-heap Dijkstra
 *         over the voxels whose key changes), plus three bits per voxel of scratch.
 * @throws std::invalid_argument when @p d has no parents or belongs to another grid; a cut edge is
 *         not cut in @p after; a listed voxel is outside the grid; a carved voxel is inside the domain
 *         or a node; an added voxel is outside the domain; a node edit names a position beyond the
 *         list or a voxel outside the grid; or the new node list has a node on a masked voxel or two
 *         nodes on one voxel (each message names the voxel, node or edit).
 *
 * @code
 * geovoronoi::change<3> c;
 * c.restiffened = {v1, v2};                                      // after field[v1], field[v2] changed
 * c.nodes = {geovoronoi::node_edit<3>::move(4, {10, 20, 5})};    // node 4 moves
 * geovoronoi::update_in_place(geovoronoi::seq, problem, d, c);   // d.seeds: the new node list
 * @endcode
 */
template <class Policy, class P>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const change<P::dim>& c) {
  detail::require_policy<Policy>();
  detail::update::edit_refs<P::dim> e;
  if (c.cut) e.cut = &*c.cut;
  e.carved = &c.carved;
  e.added = &c.added;
  e.restiffened = &c.restiffened;
  if (!c.nodes.empty()) e.nodes = &c.nodes;
  return detail::update::apply(after, d, e);
}

/// @brief The diagram after the change @p c (a cut_set of newly cut edges, a carving or a change),
///        from the diagram @p before (computed with parents): a copy of @p before updated by the
///        matching update_in_place(), so bitwise identical to a full solve of @p after (with the
///        edited node list for a change). @p stats, when given, receives what the update did.
template <class Policy, class P, class Change>
diagram<typename P::value_type, P::dim> update(const Policy& policy, const P& after,
                                               const diagram<typename P::value_type, P::dim>& before,
                                               const Change& c, update_stats* stats = nullptr) {
  detail::require_policy<Policy>();
  auto d = before;
  const auto s = update_in_place(policy, after, d, c);
  if (stats) *stats = s;
  return d;
}

/**
 * @brief The node list (voxel coordinates) that results from applying @p edits to @p nodes (linear
 *        indices, e.g. a diagram's seeds): what a full solve after the change takes.
 * @throws std::invalid_argument for a position beyond the list or a voxel outside the grid.
 */
template <int Dim>
std::vector<coord<Dim>> edited_nodes(const grid<Dim>& g, const std::vector<index_t>& nodes,
                                     const std::vector<node_edit<Dim>>& edits) {
  std::vector<coord<Dim>> out;
  for (const index_t v : detail::update::edit_node_list(g, nodes, edits)) out.push_back(g.coords(v));
  return out;
}

}  // namespace geovoronoi

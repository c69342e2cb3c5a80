#pragma once
/// @file change.hpp
/// @brief The edits of a problem that an incremental update (update.hpp, shape_update.hpp) applies:
///        cut edges, voxels carved out of or added to the domain, field values changed, node edits;
///        and what an update reports about its work.

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/grid.hpp>

#include <cstddef>
#include <optional>
#include <vector>

namespace geovoronoi {

/// A change that removes voxels from the domain: their linear indices (any order, repeats allowed).
struct carving {
  std::vector<index_t> voxels;
};

/// What an incremental update did (for benchmarks and tests).
struct update_stats {
  std::size_t cut_tree_edges = 0;  ///< roots of invalidated subtrees: tree edges cut or made heavier, carved
                                   ///< reached voxels, removed nodes
  std::size_t invalidated = 0;     ///< voxels in those subtrees (re-solved from scratch)
  std::size_t boundary = 0;        ///< valid voxels next to them that seeded the re-solve
  std::size_t settled = 0;         ///< voxels the re-solve settled
  std::size_t reparented = 0;      ///< voxels whose parent was recomputed
  std::size_t lowered = 0;         ///< valid voxels whose key decreased (stiffer material, new node, added voxels)
  std::size_t sources_added = 0;   ///< node sources queued: new nodes, and nodes whose voxel was invalidated
  std::size_t nodes_removed = 0;   ///< removed nodes whose cell was invalidated
  std::size_t repairs = 0;         ///< rounds that re-solved keys left without a realiser by rounding
};

/**
 * @brief One edit of a diagram's node list (its seeds), for change::nodes. Positions are those of
 *        the list as it stands when the edit applies (edits apply in order); labels are positions.
 *
 * - add(voxel, position): insert a node before @p position (default: append);
 * - remove(position): remove the node at @p position (the nodes after it move down by one);
 * - move(position, voxel): the node at @p position moves to @p voxel, keeping its position.
 */
template <int Dim>
struct node_edit {
  enum class kind { add, remove, move };
  static constexpr std::size_t append = std::size_t(-1);
  kind what = kind::add;
  std::size_t position = append;
  coord<Dim> voxel{};

  static node_edit add(const coord<Dim>& v, std::size_t at = append) { return {kind::add, at, v}; }
  static node_edit remove(std::size_t at) { return {kind::remove, at, {}}; }
  static node_edit move(std::size_t at, const coord<Dim>& v) { return {kind::move, at, v}; }
};

/**
 * @brief Every kind of edit, applied together by one update.
 *
 * The problem after the change must differ from the one the diagram was solved on exactly by these
 * edits: @p cut edges newly cut (the problem after carries them and every earlier cut), and the field
 * value of every voxel in @p carved, @p added or @p restiffened (and of no other voxel) changed.
 * A voxel may appear in several lists; the lists only differ in what is checked:
 * - carved: outside the domain after the change, and not a node;
 * - added: inside the domain after the change (it was outside before, or anything else: no check);
 * - restiffened: any new value, stiffer or softer, under any metric; it may also enter or leave the domain.
 */
template <int Dim>
struct change {
  std::optional<cut_set<Dim>> cut;       ///< newly cut edges (empty: none)
  std::vector<index_t> carved;           ///< voxels removed from the domain (linear indices)
  std::vector<index_t> added;            ///< voxels added to the domain
  std::vector<index_t> restiffened;      ///< voxels whose field value changed
  std::vector<node_edit<Dim>> nodes;     ///< node edits, applied in order
};

}  // namespace geovoronoi

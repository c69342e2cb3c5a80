#pragma once
// Which graph a search walks. A regular problem's nodes are the grid's voxels and its edges the
// stencil's, found by stencil_walker without any adjacency in memory. A problem over an explicit
// graph (a branching grid's copies, branching_grid.hpp) declares `walker_type`, a walker over its
// compressed rows, and `nodes()`. The engines (engine.hpp, the Thrust engine), the parent rule and
// the overflow scan take their walker and their node count from here, so one relaxation loop serves
// both; for a regular problem every name below resolves to what the loop used before, at no cost.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>

#include <cstdint>
#include <type_traits>

namespace geovoronoi::detail::search {

template <class P, class = void>
struct walker_of {
  using type = stencil_walker<P::dim>;
  static constexpr bool implicit = true;
};
template <class P>
struct walker_of<P, std::void_t<typename P::walker_type>> {
  using type = typename P::walker_type;
  static constexpr bool implicit = false;
};

/// The walker of problem P: stencil_walker<P::dim>, or P::walker_type for an explicit graph.
template <class P>
using walker_t = typename walker_of<P>::type;

/// Whether P is a regular grid problem (nodes = voxels, edges = the stencil's, found implicitly).
template <class P>
inline constexpr bool implicit_grid_v = walker_of<P>::implicit;

/// Number of nodes of @p p: the grid's voxels, or the explicit graph's nodes.
template <class P>
GEOVORONOI_HOST_DEVICE index_t node_count(const P& p) noexcept {
  if constexpr (implicit_grid_v<P>)
    return p.geometry.size();
  else
    return p.nodes();
}

/// The most edges a node of @p p has: the stencil's size, or the explicit graph's largest row.
template <class P>
GEOVORONOI_HOST_DEVICE index_t max_degree(const P& p) noexcept {
  if constexpr (implicit_grid_v<P>)
    return index_t(P::neighbours);
  else
    return p.max_links;
}

/**
 * Walker over an explicit graph in compressed rows: node v's edges are entries
 * [link_begin[v], link_begin[v+1]) of link_node (the other end) and link_dir (the stencil direction
 * whose length the edge has). Rows are sorted by link_node, so neighbours come in increasing index
 * as they do on a grid (the parent rule takes the first realiser as the lowest-index one).
 * Trivially copyable; the arrays must be readable where the walk runs.
 */
struct link_walker {
  const index_t* begin = nullptr;
  const index_t* node = nullptr;
  const std::uint8_t* dir = nullptr;

  link_walker() = default;
  template <class P>
  explicit link_walker(const P& p) : begin(p.link_begin), node(p.link_node), dir(p.link_dir) {}

  /// Calls f(k, u) for each edge v -> u of direction k, in increasing u.
  template <class P, class F>
  GEOVORONOI_HOST_DEVICE void for_each_neighbour(const P&, index_t v, F&& f) const {
    for (index_t i = begin[v], e = begin[v + 1]; i < e; ++i) f(int(dir[i]), node[i]);
  }
};

}  // namespace geovoronoi::detail::search

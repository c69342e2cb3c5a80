#pragma once
// Which graph a search walks. A regular problem's nodes are the grid's voxels and its edges the
// stencil's, found by stencil_walker without any adjacency in memory. A problem over an explicit
// graph (a branching grid's copies, branching_grid.hpp) declares `walker_type`, the walker of its
// links, and `nodes()`. The engines (engine.hpp, the Thrust engine), the parent rule and
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

/// What the walk reads of one node, in one place (one cache line fetch per settled node).
struct copy_walk {
  index_t cell = 0;            ///< the node's coarse cell
  index_t extra_begin = 0;     ///< its first entry in the extra rows
  std::uint32_t mask = 0;      ///< bit k: linked to the only copy of neighbour cell k
  std::uint32_t extra_count = 0;  ///< its entries in the extra rows
  /// In a slot's walk bits (its mask, the bit above the stencil's): the walk must read the slot's
  /// copy_walk (a cell's second or later copy, or a copy with extra rows).
  static constexpr std::uint32_t row_bit = std::uint32_t(1) << 31;
};

/// The order of node @p u for the parent rule (lowest wins): its index, or on an explicit graph the
/// problem's rank (a branching grid's copy index).
template <class P>
index_t node_rank(const P& p, index_t u) noexcept {
  if constexpr (implicit_grid_v<P>)
    return u;
  else
    return p.rank(u);
}

/**
 * Walker over a branching grid's copies (an explicit graph on a coarse grid), numbered by slots: slot
 * c is the first copy of coarse cell c, a cell's other copies have slots after the cells. Most links
 * of a copy go to the only copy of a neighbouring cell: those are the bits of its mask, bit k being
 * the neighbour cell cell + delta[k] of the problem's stencil, which is that copy's slot, so they are
 * found like a grid's neighbours, with nothing to read. The links to cells of several copies are its
 * extra rows (extra_node, extra_dir). Neighbours do not come in increasing copy order (the parent rule
 * compares node_rank). Trivially copyable; the arrays must be readable where the walk runs.
 */
struct link_walker {
  const copy_walk* info = nullptr;
  const index_t* extra_node = nullptr;
  const std::uint8_t* extra_dir = nullptr;
  const std::uint32_t* walk_bits = nullptr;
  index_t cells = 0;  ///< slots below are their cell's first copy

  link_walker() = default;
  template <class P>
  explicit link_walker(const P& p)
      : info(p.walk),
        extra_node(p.walk_extra_node),
        extra_dir(p.walk_extra_dir),
        walk_bits(p.walk_bits),
        cells(p.cells) {}

  /// The walk bits of slot @p v: its mask, and copy_walk::row_bit when walking it needs its row. A
  /// search that keeps them beside its keys (the seq dense solve's walk_node) walks a slot without
  /// the row with for_each_neighbour(p, v, bits, f), reading nothing else.
  std::uint32_t bits(index_t v) const noexcept { return walk_bits[v]; }

  /// for_each_neighbour(p, v, f) for slot @p v of walk bits @p bits (the same edges; a slot without
  /// row_bit is its cell's only copy, so its neighbours are cell + delta[k], k in the mask, and a
  /// slot linked to all of them takes the grid walk's interior loop).
  template <class P, class F>
  void for_each_neighbour(const P& p, index_t v, std::uint32_t bits, F&& f) const {
    constexpr std::uint32_t full = P::neighbours == 32 ? ~std::uint32_t(0) : (std::uint32_t(1) << P::neighbours) - 1;
    if (bits == full) {
      for (int k = 0; k < P::neighbours; ++k) f(k, v + p.edges.delta[k]);
      return;
    }
    if (bits & copy_walk::row_bit) {
      for_each_neighbour(p, v, f);
      return;
    }
    while (bits) {
      const int k = __builtin_ctz(bits);
      bits &= bits - 1;
      f(k, v + p.edges.delta[k]);
    }
  }

  /// Calls f(k, u) for each edge v -> u of stencil direction k.
  template <class P, class F>
  GEOVORONOI_HOST_DEVICE void for_each_neighbour(const P& p, index_t v, F&& f) const {
    const copy_walk w = info[v];
    std::uint32_t m = w.mask;
    while (m) {
#ifdef __CUDA_ARCH__
      const int k = __ffs(m) - 1;
#else
      const int k = __builtin_ctz(m);
#endif
      m &= m - 1;
      f(k, w.cell + p.edges.delta[k]);
    }
    for (index_t i = w.extra_begin, e = w.extra_begin + w.extra_count; i < e; ++i) f(int(extra_dir[i]), extra_node[i]);
  }
  /// Prefetches what walking @p v reads first (the search calls it for the next node it settles),
  /// for a search without walk bits beside its keys, which learns the neighbours only from the row
  /// (prefetching the neighbours' keys after it measured slower).
  void prefetch(index_t v) const noexcept { __builtin_prefetch(info + v, 0, 1); }
  /// For a search that keeps the walk bits beside its keys (State::walk_bits): prefetches the keys
  /// of the stencil neighbours of slot @p v when it is a cell's first copy (they are its neighbours'
  /// slots whenever those cells have one copy), as the grid walk does; nothing for the other slots.
  template <class P, class State>
  void prefetch_keys(const P& p, const State& st, index_t v) const noexcept {
    if (v < cells) st.prefetch(v, p.edges);
  }
};

}  // namespace geovoronoi::detail::search

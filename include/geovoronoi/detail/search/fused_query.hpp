#pragma once
// The count-only insert-query on the grid's own layout: the host path of Sibson and Laplace for
// problems whose padded grid does not fit 32-bit indices (fused_padded.hpp and fused_lanes.hpp are
// the paths for the others). The search from a query q is the engines' pruned Dijkstra (it enters v
// only if d_q(v) < d(v)) with the same relaxation step (relax.hpp), so it finds the same new cell C_q
// and the same d_q on it, bit for bit. Instead of materialising the cell (voxel, distance, owner),
// sorting it and re-reading it, it counts while it goes:
//
//  * Sibson: each settled voxel adds one to its owner's volume.
//  * Laplace: a facet pair (v in C_q, w not in C_q) can only be decided once the search has ended,
//    since w may still enter the cell later. After the search, the keys in the scratch say it: w is in
//    C_q iff its key fell below its initial bound. The pass runs over the cell list the search kept
//    (it needs it anyway to reset its keys).
//
// Scratch: one dense key array of the grid's size per worker (distance only: insert-query carries one
// label, so comparing distances is comparing the engines' keys), reset through the cell list, the
// radix heap and the cell list. Nothing is allocated per query once the vectors have grown.
//
// Balls: the exact balls of piecewise-constant regions (shape/piecewise.hpp's piecewise_tables, or
// any type with extent(axis) and for_each_ball_voxel(q, row_of, f)); a null table searches every voxel.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/cell_counts.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/metric.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <vector>

namespace geovoronoi::detail::search {

/// One worker's scratch for fused queries on problem P.
template <class P, class Balls>
class fused_query {
 public:
  using T = typename P::value_type;
  using kt = key_traits<T>;

  /// Bytes of the dense part of one scratch (the key array), what a memory budget must allow per worker.
  static std::size_t dense_bytes(const P& p) { return std::size_t(p.geometry.size()) * sizeof(slot); }

  /// @p pw: tables for the exact balls of piecewise-constant regions (piecewise.hpp), or null.
  fused_query(const P& p, const T* dist, const label_t* lab, const Balls* pw = nullptr)
      : p_(p), walk_(p), dist_(dist), lab_(lab), pw_(pw), key_(std::size_t(p.geometry.size())) {
    const index_t n = p.geometry.size();
    for (index_t v = 0; v < n; ++v) key_[std::size_t(v)] = {bound(v), p.field[v]};
  }

  /// Bytes this scratch holds now (keys, cell list, heap buckets are counted by their items).
  std::size_t bytes() const noexcept {
    return key_.capacity() * sizeof(slot) + cell_.capacity() * sizeof(index_t) + heap_peak_ * sizeof(typename radix_heap<T>::item);
  }

  /**
   * Accumulates the new cell of query @p q (d(q) > 0) into @p acc (cleared first): volumes per owner,
   * and for Laplace the facet faces per node and axis and h per node. Returns whether the cell has a
   * facet pair; @p visited gets the number of voxels settled (the cell's size).
   */
  bool run(index_t q, bool laplace, const std::vector<face<P::dim>>& faces, accumulators& acc, std::size_t& visited) {
    acc.clear();
    cell_.clear();
    heap_.clear();
    search(q);
    visited = cell_.size();
    for (index_t v : cell_) {
      const label_t o = lab_[v];
      if (o < 0) continue;
      acc.touch(o);
      ++acc.volume[o];
    }
    bool any_facet = false;
    if (laplace) any_facet = facets(faces, acc);
    for (index_t v : cell_) key_[std::size_t(v)].key = bound(v);
    return any_facet;
  }

 private:
  /// The initial key of v: the diagram's distance, which a candidate must beat to enter the cell. A
  /// bound that is not > 0 (a node's +0, a foreign -0, NaN), and a voxel outside the domain, admit no
  /// candidate (the engines test the domain before the metric; a bound of 0 rejects the same voxels
  /// before reading anything else).
  T bound(index_t v) const noexcept {
    return dist_[v] > T(0) && detail::inside<typename P::metric_type>(p_.field[v]) ? dist_[v] : T(0);
  }
  /// Key and field side by side: a relaxation reads one cache line per neighbour.
  struct slot {
    T key;
    T field;
  };

  void search(index_t q) {
    if (!(T(0) < dist_[q])) return;  // a query on a node has an empty cell
    slot* key = key_.data();
    std::size_t live = 0;
    if (!(pw_ && seed_from_table(q, live))) {
      key[q].key = T(0);
      heap_.push(kt::make(T(0), 0), q);
      live = 1;
    }
    while (!heap_.empty()) {
      const auto it = heap_.pop();
      --live;
      const index_t v = it.voxel;
      const T dv = kt::distance(it.key);
      if (dv != key[v].key) continue;  // stale: v was queued again with a smaller distance
      cell_.push_back(v);
      const T fv = key[v].field;
      walk_.for_each_neighbour(p_, v, [&](int k, index_t u) {
        slot& su = key[u];
        const T ku = su.key;
        if (!(dv < ku)) return;  // settled, out of reach, or outside the domain (bound 0)
        const T nd = relax(p_.metric, p_.edges.length[k], dv, fv, su.field);
        if (nd < ku) {
          su.key = nd;
          heap_.push(kt::make(nd, 0), u);
          if (++live > heap_peak_) heap_peak_ = live;
        }
      });
    }
  }

  /**
   * The exact ball of q's constant region (piecewise.hpp): its cell voxels get their distances from the
   * table; those whose neighbourhood lies in the ball join the cell list at once, the others (the rim)
   * are queued so the search continues from them. Returns false (nothing done) where no ball applies.
   */
  bool seed_from_table(index_t q, std::size_t& live) {
    slot* key = key_.data();
    const index_t ex = pw_->extent(0), ey = pw_->extent(1);
    const bool done = pw_->for_each_ball_voxel(
        q, [&](index_t y, index_t z) { return ex * (y + ey * z); },
        [&](index_t row, index_t x, T l, bool interior) {
          const index_t v = row + x;
          if (!(l < key[v].key)) return;  // not in the cell (key[v] is still its bound)
          key[v].key = l;
          if (interior) {
            cell_.push_back(v);  // its whole neighbourhood is in the ball: exact already
          } else {
            heap_.push(kt::make(l, 0), v);
            ++live;
          }
        });
    if (live > heap_peak_) heap_peak_ = live;
    return done;
  }

  bool facets(const std::vector<face<P::dim>>& faces, accumulators& acc) const {
    bool any_facet = false;
    const slot* key = key_.data();
    auto in_cell = [&](index_t w, const face<P::dim>&) { return key[w].key < bound(w); };
    for (index_t v : cell_)
      if (add_facets(p_, v, key[v].key, faces, lab_, dist_, in_cell, acc)) any_facet = true;
    return any_facet;
  }

  const P& p_;
  stencil_walker<P::dim> walk_;
  const T* dist_;
  const label_t* lab_;
  const Balls* pw_;
  std::vector<slot> key_;
  std::vector<index_t> cell_;
  radix_heap<T> heap_;
  std::size_t heap_peak_ = 0;
};

}  // namespace geovoronoi::detail::search

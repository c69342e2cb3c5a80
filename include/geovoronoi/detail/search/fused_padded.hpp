#pragma once
// The fused count-only insert-query (fused_query.hpp) on a padded copy of the grid: the fast path of
// Sibson and Laplace on host backends, for problems whose padded grid has fewer than 2^32 voxels
// (fused_query.hpp stays the path for the others).
//
// What differs from fused_query.hpp, and why the results stay bit for bit the same:
//
//  * Layout. Every axis gets one voxel of padding on each side, so every voxel of the grid has all its
//    stencil neighbours in the array and the neighbour loop needs no bounds checks and no coordinate
//    decoding. A padding voxel's key is 0, the bound that already rejects outside voxels: a relaxation
//    that reaches it is refused by the same comparison (nd < 0 is false for every nd >= 0, and for NaN),
//    exactly as the bounds check refused it before.
//  * Shared tables. Per call, one read-only array (bound, label) on the padded grid serves all workers:
//    resetting a key, counting an owner and testing a facet read it instead of decoding an index and
//    re-evaluating bound() from three arrays. A label there is no_label outside the domain and on the
//    padding, which folds the facet pass's in-grid, inside and labelled tests into one.
//  * Relaxation. Per settled voxel the neighbour keys and fields are gathered first, the weights and
//    sums computed over the whole stencil (a loop over local arrays the compiler can vectorise; the
//    weight of a non-candidate is computed and discarded, never used), then the improved neighbours
//    stored and pushed: the same two tests (dv < ku, then fl(dv + w) < ku with the same operands), as
//    one branch. A negative weight is still reported for candidates only, and not looked for at all
//    with the built-in metrics, whose weights between inside voxels are >= 0 or NaN.
//  * Cuts. A problem with cuts gets one more shared array, the cut mask of every voxel on the padded
//    grid (filled from the cut table's entries; 0 elsewhere): a cut direction is removed from the
//    improved set (and never checked for a negative weight), and a cut face is no facet, exactly as
//    the walker and face_in_grid skip them in fused_query.hpp.
//  * Heap. A radix heap keyed on the distance's bits alone, with 32-bit voxel indices (8-byte items for
//    float). Among equal distances the pop order changes, which changes nothing: the distances of a
//    Dijkstra search with non-negative weights do not depend on the order in which ties settle.

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/cell_counts.hpp>
#include <geovoronoi/detail/search/padded_grid.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/metric.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>


namespace geovoronoi::detail::search {

/// One worker's scratch for fused queries on the padded layout (same interface as fused_query).
template <class P, class Balls>
class fused_query_padded {
 public:
  using T = typename P::value_type;
  using heap_type = distance_heap<T>;
  using dkey = distance_key<T>;
  static constexpr int K = P::neighbours;
  static constexpr int KV = (K + 3) / 4 * 4;

  /// Bytes of the dense part of one scratch (the padded key array).
  static std::size_t dense_bytes(const P& p) { return padded_grid<P>::padded_size(p) * sizeof(slot); }
  static std::size_t heap_item_bytes() noexcept { return sizeof(typename heap_type::item); }

  fused_query_padded(const P& p, const padded_grid<P>& g, const Balls* pw = nullptr)
      : p_(p), g_(g), pw_(pw), key_(g.size()) {
    const auto* in = g.data();
    for (std::size_t w = 0; w < key_.size(); ++w) key_[w] = {in[w].bound, T(0)};
    g.for_each_row([&](index_t o, index_t w, index_t n) {
      for (index_t x = 0; x < n; ++x) key_[std::size_t(w + x)].field = p.field[o + x];
    });
  }

  std::size_t bytes() const noexcept {
    return key_.capacity() * sizeof(slot) + cell_.capacity() * sizeof(std::uint32_t) +
           heap_peak_ * sizeof(typename heap_type::item);
  }

  /// As fused_query::run (@p q is a grid index).
  bool run(index_t q, bool laplace, const std::vector<face<P::dim>>& faces, accumulators& acc, std::size_t& visited) {
    acc.clear();
    cell_.clear();
    heap_.clear();
    search(q);
    visited = cell_.size();
    const auto* in = g_.data();
    for (std::uint32_t v : cell_) {
      const label_t o = in[v].label;
      if (o < 0) continue;
      acc.touch(o);
      ++acc.volume[o];
    }
    bool any_facet = false;
    if (laplace) any_facet = facets(faces, acc);
    for (std::uint32_t v : cell_) key_[v].key = in[v].bound;
    return any_facet;
  }

 private:
  struct slot {
    T key;
    T field;
  };

  void search(index_t q0) {
    if (!(T(0) < g_.dist()[q0])) return;  // a query on a node has an empty cell
    const index_t q = g_.pad(q0);
    slot* key = key_.data();
    std::size_t live = 0;
    if (!(pw_ && seed_from_table(q0, live))) {
      key[q].key = T(0);
      heap_.push(dkey::make(T(0)), std::uint32_t(q));
      live = 1;
    }
    // the stencil rounded up to a multiple of 4 entries: the extra ones point at v itself with length 0
    // (ku = dv: never a candidate), so the loops below run over whole vectors
    index_t delta[KV];
    T len[KV];
    for (int k = 0; k < KV; ++k) delta[k] = k < K ? g_.delta()[k] : 0, len[k] = k < K ? g_.length()[k] : T(0);
    const auto metric = p_.metric;
    constexpr bool check = !never_negative_v<typename P::metric_type>;
    while (!heap_.empty()) {
      const auto it = heap_.pop();
      --live;
      const std::uint32_t v = it.voxel;
      const T dv = dkey::distance(it.key);
      slot* sv = key + v;
      if (dv != sv->key) continue;  // stale: v was queued again with a smaller distance
      cell_.push_back(v);
      const T fv = sv->field;
      cut_mask_t cut = 0;  // directions not to relax
      if constexpr (P::has_cuts) cut = g_.cut_mask(index_t(v));
      T nd[KV];
      int improved[KV];
      int n = 0;
#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
      if constexpr (std::is_same_v<T, float> && sse_weight<typename P::metric_type>::value) {
        // four neighbours at a time: the same IEEE operations as the metric's scalar expression, lane by
        // lane (SSE arithmetic is correctly rounded like the scalar one), so the same bits
        const __m128 vdv = _mm_set1_ps(dv), vfv = _mm_set1_ps(fv);
        unsigned mask = 0;
        for (int k = 0; k < KV; k += 4) {
          const slot& s0 = sv[delta[k]];
          const slot& s1 = sv[delta[k + 1]];
          const slot& s2 = sv[delta[k + 2]];
          const slot& s3 = sv[delta[k + 3]];
          const __m128 ku = _mm_set_ps(s3.key, s2.key, s1.key, s0.key);
          const __m128 fu = _mm_set_ps(s3.field, s2.field, s1.field, s0.field);
          const __m128 x = sse_relax<typename P::metric_type>(_mm_loadu_ps(len + k), vdv, vfv, fu);
          _mm_storeu_ps(nd + k, x);
          mask |= unsigned(_mm_movemask_ps(_mm_and_ps(_mm_cmplt_ps(vdv, ku), _mm_cmplt_ps(x, ku)))) << k;
        }
        mask &= ~unsigned(cut);
        while (mask) {
          improved[n++] = __builtin_ctz(mask);
          mask &= mask - 1;
        }
      } else
#endif
      {
        for (int k = 0; k < K; ++k) {
          const slot& su = sv[delta[k]];
          const T ku = su.key;
          const T w = edge_weight(metric, len[k], fv, su.field);
          const bool open = !((cut >> k) & 1u);
          if constexpr (check)
            if (open && dv < ku) check_weight(w);
          nd[k] = extend(dv, w);
          improved[n] = k;
          n += int(open & (dv < ku) & (nd[k] < ku));
        }
      }
      for (int i = 0; i < n; ++i) {
        const int k = improved[i];
        sv[delta[k]].key = nd[k];
        heap_.push(dkey::make(nd[k]), std::uint32_t(index_t(v) + delta[k]));
      }
      live += std::size_t(n);
      if (live > heap_peak_) heap_peak_ = live;
    }
  }

  /// The exact ball of q0's constant region (piecewise_tables::for_each_ball_voxel) on the padded layout.
  bool seed_from_table(index_t q0, std::size_t& live) {
    slot* key = key_.data();
    const bool done = pw_->for_each_ball_voxel(
        q0, [&](index_t y, index_t z) { return g_.pad(0, y, z); },
        [&](index_t row, index_t x, T l, bool interior) {
          const index_t v = row + x;
          if (!(l < key[v].key)) return;  // not in the cell (key[v] is still its bound)
          key[v].key = l;
          if (interior) {
            cell_.push_back(std::uint32_t(v));  // its whole neighbourhood is in the ball: exact already
          } else {
            heap_.push(dkey::make(l), std::uint32_t(v));
            ++live;
          }
        });
    if (live > heap_peak_) heap_peak_ = live;
    return done;
  }

  bool facets(const std::vector<face<P::dim>>& faces, accumulators& acc) const {
    const auto ft = g_.padded_faces(faces);
    bool any_facet = false;
    const slot* key = key_.data();
    for (std::uint32_t v : cell_) {
      const T fv = key[v].field;
      const T dq = key[v].key;
      g_.for_each_labelled_face(v, ft, [&](int i, index_t w, label_t k, T bw) {
        if (key[w].key < bw) return;  // w is in the cell too
        acc.touch(k);
        ++acc.faces[k][ft.axis[i]];
        any_facet = true;
        const T cvw = edge_weight(p_.metric, p_.edges.length[ft.edge[i]], fv, key[w].field);
        const T h = extend(extend(dq, cvw), g_.diagram_distance(w, bw));
        if (double(h) < acc.h[k]) acc.h[k] = double(h);
      });
    }
    return any_facet;
  }

  const P& p_;
  const padded_grid<P>& g_;
  const Balls* pw_;
  std::vector<slot> key_;
  std::vector<std::uint32_t> cell_;
  heap_type heap_;
  std::size_t heap_peak_ = 0;
};

}  // namespace geovoronoi::detail::search

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
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/fused_query.hpp>
#include <geovoronoi/detail/shape/piecewise.hpp>
#include <geovoronoi/detail/sse_metric.hpp>
#include <geovoronoi/metric.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>


namespace geovoronoi::detail::shape {

/// A monotone radix heap on the bit patterns of non-negative distances, with 32-bit payloads.
template <class T>
class distance_radix_heap {
 public:
  using bits_type = std::conditional_t<sizeof(T) == 4, std::uint32_t, std::uint64_t>;
  static_assert(sizeof(T) == sizeof(bits_type), "distance_radix_heap: T must be float or double");
  struct item {
    bits_type key;
    std::uint32_t voxel;
  };
  static constexpr int key_bits = int(sizeof(bits_type) * 8);
  static constexpr int nbuckets = key_bits + 1;

  static bits_type bits(T d) noexcept {
    bits_type b;
    std::memcpy(&b, &d, sizeof b);
    return b;
  }
  static T value(bits_type b) noexcept {
    T d;
    std::memcpy(&d, &b, sizeof d);
    return d;
  }

  bool empty() const noexcept { return size_ == 0; }

  /// @pre d >= +0 and not below the last popped distance
  void push(T d, std::uint32_t voxel) {
    const bits_type k = bits(d);
    const int b = bucket(k);
    buckets_[b].push_back({k, voxel});
    mask_[b >> 6] |= std::uint64_t(1) << (b & 63);
    ++size_;
  }

  /// @pre !empty()
  item pop() {
    if (buckets_[0].empty()) refill();
    const item x = buckets_[0].back();
    buckets_[0].pop_back();
    if (buckets_[0].empty()) mask_[0] &= ~std::uint64_t(1);
    --size_;
    return x;
  }

  void clear() {
    for (int b = 0; b < nbuckets; ++b) buckets_[b].clear();
    for (auto& m : mask_) m = 0;
    size_ = 0;
    last_ = 0;
  }

 private:
  int bucket(bits_type k) const noexcept {
    if (k == last_) return 0;
    if constexpr (sizeof(bits_type) == 4)
      return 32 - __builtin_clz(k ^ last_);
    else
      return 64 - __builtin_clzll(k ^ last_);
  }
  void refill() {
    int b = 0;
    for (int w = 0; w < nmask; ++w)
      if (mask_[w]) {
        b = w * 64 + __builtin_ctzll(mask_[w]);
        break;
      }
    auto& src = buckets_[b];
    bits_type m = src[0].key;
    for (const auto& x : src) m = x.key < m ? x.key : m;
    last_ = m;
    for (const auto& x : src) {
      const int nb = bucket(x.key);
      buckets_[nb].push_back(x);
      mask_[nb >> 6] |= std::uint64_t(1) << (nb & 63);
    }
    src.clear();
    mask_[b >> 6] &= ~(std::uint64_t(1) << (b & 63));
  }

  static constexpr int nmask = (nbuckets + 63) / 64;
  std::vector<item> buckets_[nbuckets];
  std::uint64_t mask_[nmask] = {};
  bits_type last_ = 0;
  std::size_t size_ = 0;
};

/// The read-only part of the padded layout, built once per call and shared by every worker.
template <class P>
class padded_grid {
 public:
  using T = typename P::value_type;
  static constexpr int dim = P::dim;
  static constexpr int neighbours = P::neighbours;
  struct info {
    T bound;        // the initial key (fused_query::bound), 0 on the padding
    label_t label;  // the diagram's label inside the domain, no_label outside and on the padding
  };

  /// Whether the fast path applies to @p p: a padded grid indexable in 32 bits.
  static bool applies(const P& p) noexcept {
    std::uint64_t n = 1;
    for (int a = 0; a < dim; ++a) n *= std::uint64_t(p.geometry.extent(a)) + 2;
    return n < std::uint64_t(UINT32_MAX);
  }
  /// Bytes of the shared tables for @p p.
  static std::size_t shared_bytes(const P& p) noexcept {
    return padded_size(p) * (sizeof(info) + (P::has_cuts ? sizeof(cut_mask_t) : 0));
  }
  static std::size_t padded_size(const P& p) noexcept {
    std::size_t n = 1;
    for (int a = 0; a < dim; ++a) n *= std::size_t(p.geometry.extent(a)) + 2;
    return n;
  }

  padded_grid(const P& p, const T* dist, const label_t* lab) : dist_(dist) {
    using M = typename P::metric_type;
    for (int a = 0; a < 3; ++a) ext_[a] = a < dim ? p.geometry.extent(a) : 1;
    px_ = ext_[0] + 2;
    py_ = ext_[1] + 2;
    pz_ = dim == 3 ? ext_[2] + 2 : 1;
    info_.assign(padded_size(p), info{T(0), no_label});
    for (index_t z = 0; z < ext_[2]; ++z)
      for (index_t y = 0; y < ext_[1]; ++y) {
        const index_t o = ext_[0] * (y + ext_[1] * z);
        info* row = info_.data() + pad(0, y, z);
        for (index_t x = 0; x < ext_[0]; ++x) {
          const index_t v = o + x;
          const bool in = detail::inside<M>(p.field[v]);
          row[x].bound = dist[v] > T(0) && in ? dist[v] : T(0);
          row[x].label = in ? lab[v] : no_label;
        }
      }
    for (int k = 0; k < neighbours; ++k) {
      delta_[k] = p.edges.offset[k][0] + px_ * (p.edges.offset[k][1] + py_ * p.edges.offset[k][2]);
      length_[k] = p.edges.length[k];
    }
    if constexpr (P::has_cuts) {
      cut_.assign(info_.size(), 0);
      const cut_view& c = p.cuts;
      for (std::uint64_t s = 0; s < c.capacity; ++s)
        if (c.keys[s] >= 0) cut_[std::size_t(pad(c.keys[s]))] = c.masks[s];
    }
  }

  std::size_t bytes() const noexcept { return info_.capacity() * sizeof(info) + cut_.capacity() * sizeof(cut_mask_t); }
  /// Cut directions of the voxel at padded index @p w (problems with cuts only).
  cut_mask_t cut_mask(index_t w) const noexcept { return cut_[std::size_t(w)]; }
  std::size_t size() const noexcept { return info_.size(); }
  const info* data() const noexcept { return info_.data(); }
  index_t extent(int a) const noexcept { return ext_[a]; }
  /// Padded index of grid voxel (x, y, z).
  index_t pad(index_t x, index_t y, index_t z) const noexcept {
    return (x + 1) + px_ * ((y + 1) + py_ * (z + (dim == 3 ? 1 : 0)));
  }
  index_t pad(index_t v) const noexcept {
    const index_t x = v % ext_[0], r = v / ext_[0];
    return pad(x, r % ext_[1], r / ext_[1]);
  }
  /// Grid index of a padded index that lies in the grid.
  index_t unpad(index_t w) const noexcept {
    const index_t x = w % px_ - 1, r = w / px_;
    const index_t y = r % py_ - 1, z = r / py_ - (dim == 3 ? 1 : 0);
    return x + ext_[0] * (y + ext_[1] * z);
  }
  index_t padded_delta(int a, int dir) const noexcept {
    const index_t s = a == 0 ? 1 : a == 1 ? px_ : px_ * py_;
    return dir * s;
  }
  /// The 2*Dim face neighbours of a voxel on the padded layout: linear offset, stencil edge, axis.
  struct face_table {
    index_t delta[2 * dim];
    int edge[2 * dim];
    int axis[2 * dim];
  };
  template <class Face>
  face_table padded_faces(const std::vector<Face>& faces) const {
    face_table t{};
    for (int i = 0; i < 2 * dim; ++i) {
      const auto& f = faces[std::size_t(i)];
      t.delta[i] = padded_delta(f.axis, f.dir);
      t.edge[i] = f.edge;
      t.axis[i] = f.axis;
    }
    return t;
  }
  /// Calls f(i, w, k, bw) for each face i (of table @p ft) of padded voxel v that is not cut and whose
  /// neighbour w is in the domain with a label: label k, bound bw. A Laplace facet's candidates.
  template <class F>
  void for_each_labelled_face(std::uint32_t v, const face_table& ft, F&& f) const {
    cut_mask_t cut = 0;  // a cut face is no facet
    if constexpr (P::has_cuts) cut = cut_mask(index_t(v));
    for (int i = 0; i < 2 * dim; ++i) {
      if ((cut >> ft.edge[i]) & 1u) continue;
      const index_t w = index_t(v) + ft.delta[i];
      const label_t k = info_[std::size_t(w)].label;  // no_label: padding (off the grid), outside, or unreached
      if (k == no_label) continue;
      f(i, w, k, info_[std::size_t(w)].bound);
    }
  }
  /// The diagram's distance of padded voxel w whose bound is @p bw: the bound where it is > 0 (then
  /// they are equal), else read.
  T diagram_distance(index_t w, T bw) const noexcept { return bw > T(0) ? bw : dist_[unpad(w)]; }
  const index_t* delta() const noexcept { return delta_; }
  const T* length() const noexcept { return length_; }
  const T* dist() const noexcept { return dist_; }

 private:
  const T* dist_;
  index_t ext_[3];
  index_t px_ = 1, py_ = 1, pz_ = 1;
  std::vector<info> info_;
  std::vector<cut_mask_t> cut_;  // problems with cuts: every voxel's cut mask (all directions)
  index_t delta_[neighbours];
  T length_[neighbours];
};

/// Whether metric M returns weights >= 0 or NaN for every pair of inside field values (the built-in
/// metrics): the search then skips the per-candidate check that reports a negative weight.
template <class M>
struct metric_never_negative
    : std::bool_constant<std::is_same_v<M, uniform> || std::is_same_v<M, min_stiffness> ||
                         std::is_same_v<M, mean_stiffness> || std::is_same_v<M, mean_cost>> {};


/// One worker's scratch for fused queries on the padded layout (same interface as fused_query).
template <class P>
class fused_query_padded {
 public:
  using T = typename P::value_type;
  using heap_type = distance_radix_heap<T>;
  static constexpr int K = P::neighbours;
  static constexpr int KV = (K + 3) / 4 * 4;

  /// Bytes of the dense part of one scratch (the padded key array).
  static std::size_t dense_bytes(const P& p) { return padded_grid<P>::padded_size(p) * sizeof(slot); }
  static std::size_t heap_item_bytes() noexcept { return sizeof(typename heap_type::item); }

  fused_query_padded(const P& p, const padded_grid<P>& g, const piecewise_tables<P>* pw = nullptr)
      : p_(p), g_(g), pw_(pw), key_(g.size()) {
    const auto* in = g.data();
    for (std::size_t w = 0; w < key_.size(); ++w) key_[w] = {in[w].bound, T(0)};
    for (index_t z = 0; z < g.extent(2); ++z)
      for (index_t y = 0; y < g.extent(1); ++y) {
        const index_t o = g.extent(0) * (y + g.extent(1) * z);
        slot* row = key_.data() + g.pad(0, y, z);
        for (index_t x = 0; x < g.extent(0); ++x) row[x].field = p.field[o + x];
      }
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
      heap_.push(T(0), std::uint32_t(q));
      live = 1;
    }
    // the stencil rounded up to a multiple of 4 entries: the extra ones point at v itself with length 0
    // (ku = dv: never a candidate), so the loops below run over whole vectors
    index_t delta[KV];
    T len[KV];
    for (int k = 0; k < KV; ++k) delta[k] = k < K ? g_.delta()[k] : 0, len[k] = k < K ? g_.length()[k] : T(0);
    const auto metric = p_.metric;
    constexpr bool check = !metric_never_negative<typename P::metric_type>::value;
    while (!heap_.empty()) {
      const auto it = heap_.pop();
      --live;
      const std::uint32_t v = it.voxel;
      const T dv = heap_type::value(it.key);
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
          const __m128 x = _mm_add_ps(vdv, sse_weight<typename P::metric_type>::apply(_mm_loadu_ps(len + k), vfv, fu));
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
          const T w = metric(len[k], fv, su.field);
          const bool open = !((cut >> k) & 1u);
          if constexpr (check)
            if (open && dv < ku && !(w >= T(0))) fused_bad_weight(double(w));
          nd[k] = dv + w;
          improved[n] = k;
          n += int(open & (dv < ku) & (nd[k] < ku));
        }
      }
      for (int i = 0; i < n; ++i) {
        const int k = improved[i];
        sv[delta[k]].key = nd[k];
        heap_.push(nd[k], std::uint32_t(index_t(v) + delta[k]));
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
            heap_.push(l, std::uint32_t(v));
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
        const T cvw = p_.metric(p_.edges.length[ft.edge[i]], fv, key[w].field);
        T h = dq + cvw;
        h = h + g_.diagram_distance(w, bw);
        if (double(h) < acc.h[k]) acc.h[k] = double(h);
      });
    }
    return any_facet;
  }

  const P& p_;
  const padded_grid<P>& g_;
  const piecewise_tables<P>* pw_;
  std::vector<slot> key_;
  std::vector<std::uint32_t> cell_;
  heap_type heap_;
  std::size_t heap_peak_ = 0;
};

}  // namespace geovoronoi::detail::shape

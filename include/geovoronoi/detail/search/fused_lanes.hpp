#pragma once
// 32 (or 16) insert-queries in one search: the padded fused search (fused_padded.hpp) with one distance
// lane per query. The fast path of Sibson and Laplace for float problems with a built-in metric on
// x86 hosts; fused_padded.hpp stays the path for every other problem.
//
// Why: the cells of neighbouring queries overlap almost entirely (the union of the cells of a 4x4x2
// block of queries is a small multiple of one cell), and the expensive part of a search -- the heap,
// loading the 26 neighbours, their field values and the edge weights -- does not depend on the query.
// So each voxel carries 32 keys, one per query (two 64-byte cache lines), and one settle relaxes all
// of them with two AVX-512 registers per neighbour where the CPU has it (chosen at run time), else
// eight SSE2 registers. 32 lanes cost less per query than 16 (docs/shape-functions.md); the query loop
// still takes 16 lanes (half the memory per worker) where the memory budget would otherwise run fewer
// workers than threads.
//
// Why the results are bit for bit those of single searches. For one lane (query q), the single
// search's keys end at the greatest solution, below the initial keys, of
//     key(q) = 0,   key(u) = min(bound(u), min over neighbours v with key(v) < bound(v) of fl(key(v) + w(v, u)))
// (bound = the diagram's distance; key(v) < bound(v) is "v is in the cell"; a cut edge is no neighbour).
// Dijkstra is one order of applying these relaxations until none improves; since fl(a + w) is monotone
// in a and never below a for w >= 0, every order that keeps relaxing until none improves reaches the
// same greatest solution (the keys only decrease and stay above that solution, and a stop means no
// relaxation improves, i.e. a solution). Here a lane takes part in a voxel's relaxation only while
// that voxel is in its cell (inactive lanes add +inf), so each lane runs exactly its own system; only
// the order is shared. Each lane's relaxation is the scalar expression: the weight is computed once
// per edge (relax.hpp's SSE form) and added to each lane's key by relax.hpp's extend on SSE or
// AVX-512 lanes, which round like the scalar addition. Counting owners, cell sizes and facets reads the final keys, so
// order does not enter the weights either.
//
// Order. A voxel is queued at the smallest key that improved, and processed (all its lanes relaxed)
// when popped, unless a later improvement queued it lower (its pending priority says which entry is
// live). Lanes unchanged since the voxel was last processed cannot improve a neighbour again (the
// neighbours' keys only went down), and every changed lane's key is at least the popped priority, so
// every push is at or above the last pop: the radix heap's monotone contract holds. A voxel is
// processed little more than once per search.
//
// Counting while searching. A lane enters a voxel's cell at most once (its key drops below the bound
// for good), so the owner's volume and the lane's cell size are counted at that moment, from the data
// already in registers: the lanes entering a voxel share its owner, so a masked vector addition per
// register (AVX-512; SSE2: four lanes per addition) counts them all in the owner's row, and the rows
// go into the lanes' accumulators after the search; no pass over the cell re-reads the keys.
// Laplace's facets need the final keys, so they are counted in a pass after the search, over the
// touched voxels sorted by address (that pass and the reset then sweep memory in order, which is much
// faster than the search's order).
//
// Exact balls (piecewise.hpp): each lane seeds its query's ball as the single search does. A lane's
// interior ball voxels are not queued, but they may be processed for another lane; their neighbours
// already hold exact distances (which satisfy the relaxation inequality), so that relaxes nothing.

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/cell_counts.hpp>
#include <geovoronoi/detail/search/padded_grid.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/metric.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace geovoronoi::detail::search {

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
#define GEOVORONOI_FUSED_LANES 1

/// Whether the lane search applies to problem type P: float and a built-in metric (weights on
/// SSE lanes; >= 0 or NaN between inside voxels).
template <class P>
struct fused_lanes_apply
    : std::bool_constant<std::is_same_v<typename P::value_type, float> && sse_weight<typename P::metric_type>::value &&
                         never_negative_v<typename P::metric_type>> {};

/// One worker's scratch for L (16 or 32) queries per search on the padded layout; Balls as in
/// fused_query.hpp.
template <class P, int L, class Balls>
class fused_lanes_padded {
 public:
  static_assert(L == 16 || L == 32, "fused_lanes_padded: 16 or 32 lanes");
  using T = float;
  using heap_type = distance_heap<T>;
  using dkey = distance_key<T>;
  static constexpr int lanes = L;
  static constexpr int K = P::neighbours;
  static constexpr int KV = (K + 3) / 4 * 4;
  static constexpr int NV = lanes / 4;   // SSE vectors per voxel
  static constexpr int NZ = lanes / 16;  // AVX-512 vectors per voxel

  /// Bytes of the dense part of one scratch: the lanes and a record (distance, label, field, pending
  /// priority) per padded voxel.
  static std::size_t dense_bytes(const P& p) {
    return padded_grid<P>::padded_size(p) * (sizeof(block) + sizeof(rec));
  }
  static std::size_t heap_item_bytes() noexcept { return sizeof(typename heap_type::item); }
  /// Bytes per node of the per-owner rows: the AVX-512 facet pass's four blocks (least h, face counts
  /// per axis), the volume counts, the seen flags and owner lists.
  static std::size_t per_node_bytes() noexcept {
    return 4 * sizeof(block) + sizeof(counts) + 2 * (sizeof(char) + sizeof(label_t));
  }

  /// @p avx512: whether the search may use AVX-512 where the CPU has it (else SSE2; the same bits).
  fused_lanes_padded(const P& p, const padded_grid<P>& g, const Balls* pw, bool avx512)
      : p_(p), g_(g), pw_(pw), key_(g.size()), rec_(g.size()) {
    for (int k = 0; k < KV; ++k) delta_[k] = k < K ? g.delta()[k] : 0, len_[k] = k < K ? g.length()[k] : T(0);
#ifdef GEOVORONOI_SIMD_AVX512
    wide_ = avx512 && __builtin_cpu_supports("avx512f");
    // a lane's facet count is at most 2 Dim times its cell's size: 32-bit lanes hold it below 2^31 / 6 voxels
    wide_facets_ = p.geometry.size() < (index_t(1) << 28);
#else
    (void)avx512;
#endif
    const auto* in = g.data();
    for (std::size_t w = 0; w < key_.size(); ++w) {
      fill(key_[w], in[w].bound);
      rec_[w] = {in[w].bound, in[w].label, T(0), untouched};
    }
    g.for_each_row([&](index_t o, index_t w, index_t n) {
      for (index_t x = 0; x < n; ++x) rec_[std::size_t(w + x)].field = p.field[o + x];
    });
  }

  std::size_t bytes() const noexcept {
    return key_.capacity() * sizeof(block) + rec_.capacity() * sizeof(rec) +
           (touched_.capacity() + sorted_.capacity()) * sizeof(std::uint32_t) + heap_peak_ * heap_item_bytes() +
           (facet_h_.capacity() + facet_count_.capacity()) * sizeof(block) + facet_seen_.capacity() +
           facet_owners_.capacity() * sizeof(label_t) + count_.capacity() * sizeof(counts) + count_seen_.capacity() +
           count_owners_.capacity() * sizeof(label_t);
  }

  /**
   * The new cells of queries @p q[0, n) (grid indices, n <= lanes) into @p *acc[j] (cleared first), as
   * fused_query::run does for one; @p any_facet[j] and @p visited[j] (the cell's size) per query.
   */
  void run(const index_t* q, int n, bool laplace, const std::vector<face<P::dim>>& faces, accumulators* const* acc,
           bool* any_facet, std::size_t* visited) {
    for (int j = 0; j < n; ++j) acc[j]->clear(), any_facet[j] = false, visited[j] = 0;
    touched_.clear();
    heap_.clear();
    std::size_t live = 0;
    for (int j = 0; j < n; ++j) seed(j, q[j], *acc[j], visited[j], live);
    if (count_.size() < acc[0]->volume.size()) count_.resize(acc[0]->volume.size()), count_seen_.resize(count_.size(), 0);
    search(live);
    flush_counts(n, acc, visited);
    if (laplace) {
      sort_touched();  // the facet pass and the reset then sweep memory in address order
#ifdef GEOVORONOI_SIMD_AVX512
      if (wide_ && wide_facets_)
        facets_avx512(n, faces, acc, any_facet);
      else
#endif
        facets(n, faces, acc, any_facet);
    }
    const auto* in = g_.data();
    for (std::uint32_t v : touched_) {
      fill(key_[v], in[v].bound);
      rec_[v].pend = untouched;
    }
  }

 private:
  struct alignas(64) block {  // one cache line per voxel
    T k[lanes];
  };
  // rec::pend: the priority a voxel is queued at (>= 0), or one of these
  static constexpr T untouched = T(-2);  // every lane still at its bound
  static constexpr T idle = T(-1);       // touched, not queued

  static void fill(block& b, T x) noexcept {
    for (int j = 0; j < lanes; ++j) b.k[j] = x;
  }

  void touch(std::uint32_t v) {
    if (rec_[v].pend == untouched) {
      touched_.push_back(v);
      rec_[v].pend = idle;
    }
  }
  /// Queues v at priority @p m unless it is queued at m or lower already.
  void queue(std::uint32_t v, T m, std::size_t& live) {
    const T pv = rec_[v].pend;
    if (pv == untouched) touched_.push_back(v);
    if (pv < T(0) || m < pv) {
      rec_[v].pend = m;
      heap_.push(dkey::make(m), v);
      if (++live > heap_peak_) heap_peak_ = live;
    }
  }
  /// Sorts touched_ (distinct padded indices) by a least-significant-digit radix sort of 11-bit digits.
  void sort_touched() {
    const std::size_t m = touched_.size();
    if (m < 2) return;
    sorted_.resize(m);
    unsigned bits = 1;
    while (bits < 32 && (std::uint64_t(1) << bits) < std::uint64_t(g_.size())) ++bits;
    constexpr unsigned digit = 11;
    constexpr std::uint32_t mask = (1u << digit) - 1u;
    std::uint32_t* src = touched_.data();
    std::uint32_t* dst = sorted_.data();
    for (unsigned shift = 0; shift < bits; shift += digit) {
      std::uint32_t start[mask + 2] = {};
      for (std::size_t i = 0; i < m; ++i) ++start[((src[i] >> shift) & mask) + 1];
      for (std::uint32_t b = 1; b <= mask + 1; ++b) start[b] += start[b - 1];
      for (std::size_t i = 0; i < m; ++i) dst[start[(src[i] >> shift) & mask]++] = src[i];
      std::swap(src, dst);
    }
    if (src != touched_.data()) touched_.swap(sorted_);
  }
  /// A lane's cell gains a voxel owned by @p owner: its volume and the cell size counted.
  void enter(accumulators& acc, std::size_t& visited, label_t owner) {
    ++visited;
    if (owner >= 0) acc.touch(owner), ++acc.volume[owner];
  }

  void seed(int j, index_t q0, accumulators& acc, std::size_t& visited, std::size_t& live) {
    if (!(T(0) < g_.dist()[q0])) return;  // a query on a node has an empty cell
    const auto* in = g_.data();
    const bool ball = pw_ && pw_->for_each_ball_voxel(
                                 q0, [&](index_t y, index_t z) { return g_.pad(0, y, z); },
                                 [&](index_t row, index_t x, T l, bool interior) {
                                   const std::uint32_t v = std::uint32_t(row + x);
                                   T& kj = key_[v].k[j];
                                   if (!(l < kj)) return;  // not in the cell, or set already
                                   if (!(kj < in[v].bound)) enter(acc, visited, in[v].label);
                                   kj = l;
                                   if (interior)
                                     touch(v);  // its whole neighbourhood is in the ball: exact already
                                   else
                                     queue(v, l, live);
                                 });
    if (ball) return;
    const std::uint32_t q = std::uint32_t(g_.pad(q0));
    key_[q].k[j] = T(0);
    enter(acc, visited, in[q].label);
    queue(q, T(0), live);
  }

  /**
   * Pops the next live entry into @p v and computes the weights of its edges into @p w (four
   * neighbours at a time: the metric's scalar expression on SSE lanes); false when the queue is empty.
   */
  bool next(std::uint32_t& v, T* w, std::size_t& live) {
    using W = sse_weight<typename P::metric_type>;
    for (;;) {
      if (heap_.empty()) return false;
      const auto it = heap_.pop();
      --live;
      v = it.voxel;
      if (rec_[v].pend == dkey::distance(it.key)) break;  // else stale: queued lower since, or processed
    }
    rec_[v].pend = idle;
    const rec* fld = rec_.data();
    const __m128 fv = _mm_set1_ps(fld[v].field);
    for (int k = 0; k < KV; k += 4) {
      const __m128 fu = _mm_set_ps(fld[v + delta_[k + 3]].field, fld[v + delta_[k + 2]].field,
                                   fld[v + delta_[k + 1]].field, fld[v + delta_[k]].field);
      _mm_storeu_ps(w + k, W::apply(_mm_loadu_ps(len_ + k), fv, fu));
    }
    return true;
  }
  /// The row of count_ for @p owner (>= 0), noted for flush_counts().
  std::int32_t* count_row(label_t owner) {
    if (!count_seen_[std::size_t(owner)]) count_seen_[std::size_t(owner)] = 1, count_owners_.push_back(owner);
    return count_[std::size_t(owner)].c;
  }
  /// The lanes in @p fresh entered the cell of a voxel owned by @p owner just now: their cell sizes and
  /// the owner's volume, four lanes per SSE addition (a lane's mask is -1: subtracting it adds one).
  void count_fresh(unsigned fresh, label_t owner) {
    alignas(16) static const std::int32_t bits[16][4] = {
        {0, 0, 0, 0},   {-1, 0, 0, 0},   {0, -1, 0, 0},  {-1, -1, 0, 0},  {0, 0, -1, 0},  {-1, 0, -1, 0},
        {0, -1, -1, 0}, {-1, -1, -1, 0}, {0, 0, 0, -1},  {-1, 0, 0, -1},  {0, -1, 0, -1}, {-1, -1, 0, -1},
        {0, 0, -1, -1}, {-1, 0, -1, -1}, {0, -1, -1, -1}, {-1, -1, -1, -1}};
    auto add = [&](std::int32_t* row) {
      for (int i = 0; i < NV; ++i) {
        auto* x = reinterpret_cast<__m128i*>(row + 4 * i);
        const __m128i mask = _mm_load_si128(reinterpret_cast<const __m128i*>(bits[(fresh >> (4 * i)) & 15u]));
        _mm_store_si128(x, _mm_sub_epi32(_mm_load_si128(x), mask));
      }
    };
    add(cell_size_.c);
    if (owner >= 0) add(count_row(owner));
  }
  cut_mask_t cut_of(std::uint32_t v) const noexcept {
    if constexpr (P::has_cuts) return g_.cut_mask(index_t(v));
    return 0;
  }

  void search(std::size_t& live) {
#ifdef GEOVORONOI_SIMD_AVX512
    if (wide_) return search_avx512(live);
#endif
    const rec* in = rec_.data();
    block* key = key_.data();
    const __m128 inf = _mm_set1_ps(std::numeric_limits<T>::infinity());
    std::uint32_t v;
    T w[KV];
    while (next(v, w, live)) {
      // the lanes of v that are in their cells; the others add +inf, which improves nothing
      __m128 kv[NV];
      const __m128 bv = _mm_set1_ps(in[v].bound);
      for (int i = 0; i < NV; ++i) {
        const __m128 a = _mm_load_ps(key[v].k + 4 * i);
        const __m128 act = _mm_cmplt_ps(a, bv);
        kv[i] = _mm_or_ps(_mm_and_ps(act, a), _mm_andnot_ps(act, inf));
      }
      const cut_mask_t cut = cut_of(v);  // directions not to relax
      for (int k = 0; k < K; ++k) {
        if ((cut >> k) & 1u) continue;
        const std::uint32_t u = std::uint32_t(index_t(v) + delta_[k]);
        T* ku = key[u].k;
        const __m128 wk = _mm_set1_ps(w[k]);
        __m128 c[NV], lt[NV];
        int any = 0;
        for (int i = 0; i < NV; ++i) {
          // the single search's two tests, dv < ku and fl(dv + w) < ku (false for NaN): the first one
          // matters where w < 0, which the built-in metrics give only toward voxels outside the domain
          const __m128 old = _mm_load_ps(ku + 4 * i);
          c[i] = extend(kv[i], wk);
          lt[i] = _mm_and_ps(_mm_cmplt_ps(kv[i], old), _mm_cmplt_ps(c[i], old));
          any |= _mm_movemask_ps(lt[i]);
        }
        if (!any) continue;
        // store the improved lanes; note those entering u's cell now; queue u at the least improved key
        const __m128 bu = _mm_set1_ps(in[u].bound);
        __m128 m = inf;
        unsigned fresh = 0;
        for (int i = 0; i < NV; ++i) {
          const __m128 old = _mm_load_ps(ku + 4 * i);
          fresh |= unsigned(_mm_movemask_ps(_mm_andnot_ps(_mm_cmplt_ps(old, bu), lt[i]))) << (4 * i);
          _mm_store_ps(ku + 4 * i, _mm_or_ps(_mm_and_ps(lt[i], c[i]), _mm_andnot_ps(lt[i], old)));
          m = _mm_min_ps(m, _mm_or_ps(_mm_and_ps(lt[i], c[i]), _mm_andnot_ps(lt[i], inf)));
        }
        m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(1, 0, 3, 2)));
        m = _mm_min_ps(m, _mm_shuffle_ps(m, m, _MM_SHUFFLE(2, 3, 0, 1)));
        if (fresh) count_fresh(fresh, in[u].label);
        queue(u, _mm_cvtss_f32(m), live);
      }
    }
  }

#ifdef GEOVORONOI_SIMD_AVX512
  /// The least of 16 floats (none NaN). Written with the masked forms, whose pass-through operand is
  /// given: GCC 12's unmasked ones (and _mm512_mask_reduce_min_ps) pass an undefined vector that
  /// -Wmaybe-uninitialized reports.
  __attribute__((target("avx512f"))) static T least(__m512 x) noexcept {
    constexpr __mmask16 all = 0xFFFF;
    x = _mm512_mask_min_ps(x, all, x, _mm512_mask_shuffle_f32x4(x, all, x, x, _MM_SHUFFLE(1, 0, 3, 2)));
    x = _mm512_mask_min_ps(x, all, x, _mm512_mask_shuffle_f32x4(x, all, x, x, _MM_SHUFFLE(2, 3, 0, 1)));
    x = _mm512_mask_min_ps(x, all, x, _mm512_mask_shuffle_ps(x, all, x, x, _MM_SHUFFLE(1, 0, 3, 2)));
    x = _mm512_mask_min_ps(x, all, x, _mm512_mask_shuffle_ps(x, all, x, x, _MM_SHUFFLE(2, 3, 0, 1)));
    return _mm512_cvtss_f32(x);
  }
  /// The same search with a voxel's keys in AVX-512 registers (16 lanes each): the same per-lane IEEE
  /// operations and tests, masks instead of blends.
  __attribute__((target("avx512f"))) void search_avx512(std::size_t& live) {
    const rec* in = rec_.data();
    block* key = key_.data();
    const __m512 inf = _mm512_set1_ps(std::numeric_limits<T>::infinity());
    const __m512i one = _mm512_set1_epi32(1);
    __m512i size[NZ];
    for (int z = 0; z < NZ; ++z) size[z] = _mm512_load_si512(cell_size_.c + 16 * z);
    std::uint32_t v;
    T w[KV];
    while (next(v, w, live)) {
      __m512 kv[NZ];
      const __m512 bv = _mm512_set1_ps(in[v].bound);
      for (int z = 0; z < NZ; ++z) {
        const __m512 a = _mm512_load_ps(key[v].k + 16 * z);
        kv[z] = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(a, bv, _CMP_LT_OQ), inf, a);
      }
      const cut_mask_t cut = cut_of(v);
      for (int k = 0; k < K; ++k) {
        if ((cut >> k) & 1u) continue;
        const std::uint32_t u = std::uint32_t(index_t(v) + delta_[k]);
        T* ku = key[u].k;
        const __m512 wk = _mm512_set1_ps(w[k]);
        __m512 old[NZ], c[NZ];
        __mmask16 lt[NZ];
        unsigned any = 0;
        for (int z = 0; z < NZ; ++z) {
          old[z] = _mm512_load_ps(ku + 16 * z);
          c[z] = extend(kv[z], wk);
          lt[z] = __mmask16(_mm512_cmp_ps_mask(kv[z], old[z], _CMP_LT_OQ) & _mm512_cmp_ps_mask(c[z], old[z], _CMP_LT_OQ));
          any |= lt[z];
        }
        if (!any) continue;
        // store the improved lanes; count those entering u's cell now; queue u at the least improved key
        const auto& r = in[u];
        const __m512 bu = _mm512_set1_ps(r.bound);
        __mmask16 fresh[NZ];
        unsigned any_fresh = 0;
        __m512 m = inf;
        for (int z = 0; z < NZ; ++z) {
          fresh[z] = __mmask16(lt[z] & ~_mm512_cmp_ps_mask(old[z], bu, _CMP_LT_OQ));
          any_fresh |= fresh[z];
          _mm512_mask_store_ps(ku + 16 * z, lt[z], c[z]);
          m = _mm512_mask_min_ps(m, lt[z], m, c[z]);  // the least improved key (masked: see least())
        }
        if (any_fresh) {  // the owner's volume and the cell sizes, one masked addition per register
          for (int z = 0; z < NZ; ++z) size[z] = _mm512_mask_add_epi32(size[z], fresh[z], size[z], one);
          if (r.label >= 0) {
            std::int32_t* row = count_row(r.label);
            for (int z = 0; z < NZ; ++z) {
              const __m512i x = _mm512_load_si512(row + 16 * z);
              _mm512_store_si512(row + 16 * z, _mm512_mask_add_epi32(x, fresh[z], x, one));
            }
          }
        }
        queue(u, least(m), live);
      }
    }
    for (int z = 0; z < NZ; ++z) _mm512_store_si512(cell_size_.c + 16 * z, size[z]);
  }
#endif

  /// Laplace's facet pairs of every lane, as fused_query_padded::facets does for one.
  void facets(int n, const std::vector<face<P::dim>>& faces, accumulators* const* acc, bool* any_facet) const {
    const auto ft = g_.padded_faces(faces);
    const auto* in = g_.data();
    const unsigned all = n >= 32 ? ~0u : (1u << n) - 1u;
    for (std::uint32_t v : touched_) {
      const unsigned cell_v = members(v, in[v].bound) & all;
      if (!cell_v) continue;
      const T fv = rec_[v].field;
      g_.for_each_labelled_face(v, ft, [&](int i, index_t w, label_t k, T bw) {
        unsigned pair = cell_v & ~members(std::uint32_t(w), bw);  // lanes with v in the cell and w not
        if (!pair) return;
        const T cvw = edge_weight(p_.metric, p_.edges.length[ft.edge[i]], fv, rec_[std::size_t(w)].field);
        const T dw = g_.diagram_distance(w, bw);
        while (pair) {
          const int j = __builtin_ctz(pair);
          pair &= pair - 1;
          accumulators& a = *acc[j];
          a.touch(k);
          ++a.faces[k][ft.axis[i]];
          any_facet[j] = true;
          const T h = extend(extend(key_[v].k[j], cvw), dw);
          if (double(h) < a.h[k]) a.h[k] = double(h);
        }
      });
    }
  }
#ifdef GEOVORONOI_SIMD_AVX512
  /**
   * The same facet pairs with 16 lanes per AVX-512 register: for a face (v, w) the lanes with v in
   * their cell and w not form a mask, h = (key + c(v, w)) + d(w) is the same two IEEE additions per
   * lane, and per owner k the lanes keep their least h (a masked min: the old value stays where h is not
   * smaller, as the scalar test `h < best` keeps it) and their face counts per axis in vectors, which go
   * into the lanes' accumulators once at the end. A float's least value converts to the least double, so
   * every accumulator ends as in facets(); the order in which owners reach an accumulator's touched list
   * differs, and nothing reads that order (the candidates are sorted by weight, then node).
   */
  __attribute__((target("avx512f"))) void facets_avx512(int n, const std::vector<face<P::dim>>& faces,
                                                        accumulators* const* acc, bool* any_facet) {
    const auto ft = g_.padded_faces(faces);
    const auto* in = g_.data();
    const std::size_t nodes = acc[0]->h.size();
    if (facet_h_.size() < nodes) {
      facet_h_.resize(nodes);
      facet_count_.resize(3 * nodes);
      facet_seen_.assign(nodes, 0);
    }
    static_assert(lanes <= 32, "fused_lanes_padded: lane masks are 32-bit");
    const std::uint32_t all = n >= 32 ? ~std::uint32_t(0) : (std::uint32_t(1) << n) - 1u;
    const __m512 inf = _mm512_set1_ps(std::numeric_limits<T>::infinity());
    const __m512i one = _mm512_set1_epi32(1);
    std::uint32_t with_facet = 0;
    for (std::uint32_t v : touched_) {
      __m512 kv[NZ];
      __mmask16 cell_v[NZ];
      unsigned any_v = 0;
      const __m512 bv = _mm512_set1_ps(in[v].bound);
      for (int z = 0; z < NZ; ++z) {
        kv[z] = _mm512_load_ps(key_[v].k + 16 * z);
        cell_v[z] = __mmask16(_mm512_cmp_ps_mask(kv[z], bv, _CMP_LT_OQ) & (all >> (16 * z)));
        any_v |= cell_v[z];
      }
      if (!any_v) continue;
      const T fv = rec_[v].field;
      // the faces of for_each_labelled_face, written out (a lambda would not inherit the target)
      const cut_mask_t cut = cut_of(v);
      for (int i = 0; i < 2 * P::dim; ++i) {
        if ((cut >> ft.edge[i]) & 1u) continue;
        const index_t w = index_t(v) + ft.delta[i];
        const label_t k = in[w].label;
        if (k == no_label) continue;
        const T bw = in[w].bound;
        const __m512 bwv = _mm512_set1_ps(bw);
        __mmask16 pair[NZ];  // lanes with v in the cell and w not
        unsigned any_pair = 0;
        for (int z = 0; z < NZ; ++z) {
          const __mmask16 in_w = _mm512_cmp_ps_mask(_mm512_load_ps(key_[std::size_t(w)].k + 16 * z), bwv, _CMP_LT_OQ);
          pair[z] = __mmask16(cell_v[z] & ~in_w);
          any_pair |= pair[z];
        }
        if (!any_pair) continue;
        const std::size_t o = std::size_t(k);
        if (!facet_seen_[o]) {
          facet_seen_[o] = 1;
          facet_owners_.push_back(k);
          for (int z = 0; z < NZ; ++z) {
            _mm512_store_ps(facet_h_[o].k + 16 * z, inf);
            for (int a = 0; a < 3; ++a)
              _mm512_store_si512(facet_count_[3 * o + std::size_t(a)].k + 16 * z, _mm512_setzero_si512());
          }
        }
        const T cvw = edge_weight(p_.metric, p_.edges.length[ft.edge[i]], fv, rec_[std::size_t(w)].field);
        const T dw = g_.diagram_distance(w, bw);
        float* c = facet_count_[3 * o + std::size_t(ft.axis[i])].k;
        for (int z = 0; z < NZ; ++z) {
          const __m512 h = extend(extend(kv[z], _mm512_set1_ps(cvw)), _mm512_set1_ps(dw));
          const __m512 best = _mm512_load_ps(facet_h_[o].k + 16 * z);
          _mm512_store_ps(facet_h_[o].k + 16 * z, _mm512_mask_min_ps(best, pair[z], h, best));  // h < best ? h : best
          const __m512i count = _mm512_load_si512(c + 16 * z);
          _mm512_store_si512(c + 16 * z, _mm512_mask_add_epi32(count, pair[z], count, one));
          with_facet |= std::uint32_t(pair[z]) << (16 * z);
        }
      }
    }
    for (const label_t k : facet_owners_) {
      const std::size_t o = std::size_t(k);
      for (int j = 0; j < n; ++j) {
        std::int32_t count[3];
        for (int a = 0; a < 3; ++a) std::memcpy(&count[a], facet_count_[3 * o + std::size_t(a)].k + j, sizeof(std::int32_t));
        if ((count[0] | count[1] | count[2]) == 0) continue;
        accumulators& acc_j = *acc[j];
        acc_j.touch(k);
        for (int a = 0; a < 3; ++a) acc_j.faces[o][std::size_t(a)] += count[a];
        const double h = double(facet_h_[o].k[j]);
        if (h < acc_j.h[o]) acc_j.h[o] = h;
      }
      facet_seen_[o] = 0;
    }
    facet_owners_.clear();
    for (int j = 0; j < n; ++j) any_facet[j] = (with_facet >> j) & 1u;
  }
#endif
  /// Bit j set where lane j of padded voxel v is in its cell.
  unsigned members(std::uint32_t v, T bound) const noexcept {
    const __m128 b = _mm_set1_ps(bound);
    unsigned m = 0;
    for (int i = 0; i < NV; ++i)
      m |= unsigned(_mm_movemask_ps(_mm_cmplt_ps(_mm_load_ps(key_[v].k + 4 * i), b))) << (4 * i);
    return m;
  }

  /// Per-owner cell volumes of the lanes, counted by vector additions during the search (32 bits each:
  /// a lane's count is at most the grid's size, below 2^31 where the lanes are used); flush_counts()
  /// adds them to the lanes' accumulators after the search.
  struct alignas(64) counts {
    std::int32_t c[lanes];
  };
  void flush_counts(int n, accumulators* const* acc, std::size_t* visited) {
    for (const label_t o : count_owners_) {
      std::int32_t* c = count_[std::size_t(o)].c;
      for (int j = 0; j < n; ++j)
        if (c[j] != 0) acc[j]->touch(o), acc[j]->volume[std::size_t(o)] += c[j];
      for (int j = 0; j < lanes; ++j) c[j] = 0;
      count_seen_[std::size_t(o)] = 0;
    }
    count_owners_.clear();
    for (int j = 0; j < n; ++j) visited[j] += std::size_t(cell_size_.c[j]);
    for (int j = 0; j < lanes; ++j) cell_size_.c[j] = 0;
  }

  const P& p_;
  const padded_grid<P>& g_;
  const Balls* pw_;
  std::vector<block> key_;
  // What the search reads of a voxel besides its keys, in one 16-byte record: the diagram's distance
  // (the keys' bound) and label (copies of the shared padded_grid's), the field, and the pending priority
  // (>= 0, or untouched / idle above). A row of three neighbours is then one cache line rather than
  // one in each of three arrays.
  struct alignas(16) rec {
    T bound;
    label_t label;
    T field;
    T pend;
  };
  static_assert(sizeof(T) == 4 && sizeof(label_t) == 4, "fused_lanes_padded: a 16-byte voxel record");
  std::vector<rec> rec_;
  std::vector<std::uint32_t> touched_;
  std::vector<std::uint32_t> sorted_;  // sort_touched()'s other buffer
  heap_type heap_;
  std::size_t heap_peak_ = 0;
  // the stencil rounded up to a multiple of 4 entries: the extra ones point at v itself with length 0
  index_t delta_[KV];
  T len_[KV];
  bool wide_ = false;  // AVX-512 search
  bool wide_facets_ = false;  // and AVX-512 facets
  // the AVX-512 facets' per-owner vectors: least h, face counts per axis (32-bit integers in a block)
  std::vector<block> facet_h_;
  std::vector<block> facet_count_;
  std::vector<char> facet_seen_;
  std::vector<label_t> facet_owners_;
  std::vector<counts> count_;
  std::vector<char> count_seen_;
  std::vector<label_t> count_owners_;
  counts cell_size_{};
};

#else
template <class P>
struct fused_lanes_apply : std::false_type {};
#endif

}  // namespace geovoronoi::detail::search

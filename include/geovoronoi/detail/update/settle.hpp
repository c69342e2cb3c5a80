#pragma once
// The update's search: Dijkstra over the diagram's own images that may lower any key, setting parents
// as voxels settle and recording the parent candidates the parent step decides (apply.hpp).

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/parents.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/voxel_bits.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <cstdint>
#include <limits>
#include <type_traits>
#include <vector>

namespace geovoronoi::detail::update {

using search::key_traits;
using search::radix_heap;
using search::stencil_walker;
using search::voxel_bits;

/// Whether @p v is the source of its label (node l on voxel v at distance 0, as voronoi() solves).
template <class T, int Dim>
bool is_source(const diagram<T, Dim>& d, index_t v) {
  const label_t l = d.label[v];
  return l != no_label && std::size_t(l) < d.seeds.size() && d.seeds[std::size_t(l)] == v && d.distance[v] == T(0);
}

/// The canonical parent of voxel @p v (search/parents.hpp's rule); none for unreached voxels and
/// sources.
template <class P, class D>
index_t parent_of(const P& p, const stencil_walker<P::dim>& walk, const D& d, index_t v) {
  if (d.label[v] == no_label || is_source(d, v)) return no_index;
  return search::lowest_realiser(p, walk, d.distance.data(), d.label.data(), v);
}

/// A Dijkstra state over the diagram's images that records every voxel whose key it lowers.
template <class T>
struct tracking_keys {
  using kt = key_traits<T>;
  using key_type = typename kt::key_type;
  T* dist;
  label_t* lab;
  const T* fieldp;
  voxel_bits* lowered_bits;
  std::vector<index_t>* lowered;
  struct slot {
    tracking_keys* s;
    index_t v;
    T field;
    key_type get_key() const noexcept { return s->get(v); }
    void set_key(key_type k) { s->set(v, k); }
  };
  slot cur{};
  slot& at(index_t v) noexcept {
    cur = slot{this, v, fieldp[v]};
    return cur;
  }
  key_type get(index_t v) const noexcept { return lab[v] == no_label ? kt::unreached : kt::make(dist[v], lab[v]); }
  void set(index_t v, key_type k) {
    dist[v] = kt::distance(k);
    lab[v] = kt::label(k);
    if (lowered_bits->insert(v)) lowered->push_back(v);
  }
  T field(index_t v) const noexcept { return fieldp[v]; }
  template <class S>
  void prefetch(index_t, const S&) const noexcept {}
};

/// An edge (x -> y, direction k) from a voxel x that settled with a changed key to a neighbour y
/// whose key x did not lower: y's parent must be decided again (it was x) or may become x (x realises
/// y's key). The parent step decides these once every key is final, unless y's key changed too.
struct parent_candidate {
  index_t x, y;
  int k;
};

/// Appends a parent candidate; out of line, so that the settle loop keeps its registers for the
/// common case (a candidate is recorded for a small fraction of the edges).
GEOVORONOI_NOINLINE inline void add_candidate(std::vector<parent_candidate>& c, index_t x, index_t y, int k) {
  c.push_back({x, y, k});
}

#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
/// Whether settle() classifies an interior voxel's neighbours four at a time (float keys, a built-in
/// metric): the same comparisons and IEEE operations as its scalar loop, lane by lane.
template <class P>
inline constexpr bool settle_sse_v = std::is_same_v<typename P::value_type, float> &&
                                     search::sse_weight<typename P::metric_type>::value &&
                                     search::sse_inside<typename P::metric_type>::value && P::neighbours <= 32;
#else
template <class P>
inline constexpr bool settle_sse_v = false;
#endif

/// Dijkstra over the diagram's own images that may lower any key (the engine's relaxation, bit for
/// bit: same skip, mask, weight check and overflow rule), recording every voxel it lowers and setting
/// each settled voxel's parent as it pops: its realisers have smaller keys, so they are final then.
/// It also records the parent candidates (above) of the voxels it settles, for the parent step.
template <class P>
std::size_t settle(const P& after, diagram<typename P::value_type, P::dim>& d, radix_heap<typename P::value_type>& heap,
                   const stencil_walker<P::dim>& walk, voxel_bits& lowered_bits, std::vector<index_t>& lowered,
                   std::vector<parent_candidate>& candidates) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const T inf = std::numeric_limits<T>::infinity();
  // the images and the bit set through raw pointers: the vectors' own data pointers would be
  // reloaded after every push_back (an opaque call)
  T* const dist = d.distance.data();
  label_t* const lab = d.label.data();
  index_t* const par = d.parent.data();
  const T* const field = after.field;
  const index_t* const seeds = d.seeds.data();
  const std::size_t seed_count = d.seeds.size();
  std::uint64_t* const lowered_words = lowered_bits.words();
  auto was_lowered = [lowered_words](index_t u) { return (lowered_words[u >> 6] >> (u & 63)) & 1u; };
  constexpr int K = P::neighbours;
  // the stencil padded to whole groups of four; the padding lanes read v itself and are masked off
  constexpr int KV = (K + 3) / 4 * 4;
  [[maybe_unused]] T len4[KV];
  [[maybe_unused]] index_t delta4[KV];
  for (int k = 0; k < KV; ++k) {
    len4[k] = k < K ? after.edges.length[k] : T(1);
    delta4[k] = k < K ? after.edges.delta[k] : index_t(0);
  }
  std::size_t settled = 0;
  while (!heap.empty()) {
    const auto it = heap.pop();
    const index_t v = it.voxel;
    const auto vkey = it.key;
    const label_t l = lab[v];
    if (l == no_label || vkey != kt::make(dist[v], l)) continue;  // stale entry
    ++settled;
    const T dv = dist[v];
    const T fv = field[v];
    index_t best = no_index;
#if defined(__SSE2__) && !defined(__CUDA_ARCH__)
    if constexpr (settle_sse_v<P>) {
      if (walk.interior(v)) {
        // The scalar loop below, four neighbours at a time. Keys compare as (distance bits, label)
        // pairs of unsigned 32-bit lanes (the sign flip makes the signed compare an unsigned one),
        // exactly as the packed 64-bit keys do; the weights are the metric's IEEE operations lane by
        // lane. The masks then drive the rare scalar work (stores, pushes, candidates) in increasing k.
        using W = search::sse_weight<typename P::metric_type>;
        using I = search::sse_inside<typename P::metric_type>;
        cut_mask_t open = K == 32 ? ~cut_mask_t(0) : (cut_mask_t(1) << K) - 1;
        if constexpr (P::has_cuts) open &= ~after.cut_mask(v);
        const __m128 vdv = _mm_set1_ps(dv), vfv = _mm_set1_ps(fv), vinf = _mm_set1_ps(inf);
        const __m128i flip = _mm_set1_epi32(INT32_MIN), vdb = _mm_castps_si128(vdv), vl = _mm_set1_epi32(l);
        const __m128i vdbf = _mm_xor_si128(vdb, flip), vlf = _mm_xor_si128(vl, flip);
        auto bits = [](__m128i m) { return unsigned(_mm_movemask_ps(_mm_castsi128_ps(m))); };
        unsigned m_real = 0, m_same_eq = 0, m_other = 0, m_imp = 0, m_gt = 0, m_tie = 0, m_bad = 0;
        alignas(16) float nd[KV];
        for (int k = 0; k < KV; k += 4) {
          const index_t u0 = v + delta4[k], u1 = v + delta4[k + 1], u2 = v + delta4[k + 2], u3 = v + delta4[k + 3];
          const __m128 du = _mm_set_ps(dist[u3], dist[u2], dist[u1], dist[u0]);
          const __m128i lu = _mm_set_epi32(lab[u3], lab[u2], lab[u1], lab[u0]);
          const __m128 fu = _mm_set_ps(field[u3], field[u2], field[u1], field[u0]);
          const __m128 len = _mm_loadu_ps(len4 + k);
          const __m128i dub = _mm_castps_si128(du);
          const __m128i dubf = _mm_xor_si128(dub, flip), luf = _mm_xor_si128(lu, flip);
          const __m128i lab_less = _mm_cmplt_epi32(vlf, luf);  // l < lu, unsigned
          // vkey < ku
          const __m128i larger =
              _mm_or_si128(_mm_cmplt_epi32(vdbf, dubf), _mm_and_si128(_mm_cmpeq_epi32(dub, vdb), lab_less));
          const __m128i same = _mm_cmpeq_epi32(lu, vl);
          const __m128i final_same = _mm_andnot_si128(larger, same);
          // a realiser: fl(du + w(u -> v)) has v's distance bits (and u has v's label)
          const __m128 back = search::extend(du, W::apply(len, fu, vfv));
          m_real |= bits(_mm_and_si128(final_same, _mm_cmpeq_epi32(_mm_castps_si128(back), vdb))) << k;
          m_same_eq |= bits(_mm_and_si128(final_same, _mm_castps_si128(_mm_cmpeq_ps(du, vdv)))) << k;
          m_other |= (~bits(_mm_or_si128(larger, same)) & 15u) << k;
          // a larger key inside the domain: relax it with nk = (fl(dv + w), l), unreached on overflow
          const __m128 w = W::apply(len, vfv, fu);
          const __m128 x = search::extend(vdv, w);
          _mm_store_ps(nd + k, x);
          const __m128i gt = _mm_and_si128(larger, _mm_castps_si128(I::apply(fu)));
          m_gt |= bits(gt) << k;
          m_bad |= bits(_mm_andnot_si128(_mm_castps_si128(_mm_cmpge_ps(w, _mm_setzero_ps())), gt)) << k;
          const __m128i xb = _mm_castps_si128(x);
          const __m128i xeq = _mm_cmpeq_epi32(xb, dub);
          const __m128i fin = _mm_and_si128(gt, _mm_castps_si128(_mm_cmplt_ps(x, vinf)));
          const __m128i less = _mm_or_si128(_mm_cmplt_epi32(_mm_xor_si128(xb, flip), dubf), _mm_and_si128(xeq, lab_less));
          m_imp |= bits(_mm_and_si128(fin, less)) << k;
          m_tie |= bits(_mm_and_si128(fin, _mm_and_si128(xeq, same))) << k;
        }
        m_real &= open, m_same_eq &= open, m_other &= open, m_imp &= open, m_gt &= open, m_tie &= open, m_bad &= open;
        if (m_real) best = v + delta4[__builtin_ctz(m_real)];
        if (m_bad) {  // the scalar loop's check, at the first such neighbour (never for the built-in metrics)
          const int k = __builtin_ctz(m_bad);
          search::bad_weight(double(search::edge_weight(after.metric, after.edges.length[k], fv, field[v + delta4[k]])));
        }
        for (unsigned m = m_imp | m_same_eq | m_other | (m_gt & ~m_imp); m; m &= m - 1) {
          const int k = __builtin_ctz(m);
          const index_t u = v + delta4[k];
          if ((m_imp >> k) & 1u) {
            dist[u] = nd[k];
            lab[u] = l;
            if (lowered_bits.insert(u)) lowered.push_back(u);
            heap.push(kt::make(nd[k], l), u);
          } else if (!was_lowered(u) && (((m_same_eq | m_tie) >> k) & 1u || par[u] == v)) {
            add_candidate(candidates, v, u, k);
          }
        }
        const bool source = dv == T(0) && std::size_t(l) < seed_count && seeds[std::size_t(l)] == v;
        par[v] = source ? no_index : best;
        continue;
      }
    }
#endif
    walk.for_each_neighbour(after, v, [&](int k, index_t u) {
      const label_t lu = lab[u];
      const T du = dist[u];
      // an unreached voxel holds (+inf, no_label), whose key orders above every reached key, as the
      // unreached sentinel does
      const auto ku = kt::make(du, lu);
      if (!(vkey < ku)) {  // u's key is not larger: final, nothing to relax
        if (lu == l) {
          // a realiser if u + w(u -> v) gives v's key (the walker visits neighbours in increasing
          // index order: the first realiser is the parent; a source keeps none, below)
          if (best == no_index &&
              kt::make(search::extend(du, search::edge_weight(after.metric, after.edges.length[k], field[u], fv)), l) ==
                  vkey)
            best = u;
          // an equal distance (a zero or absorbed weight): v may realise u's key too
          if (du == dv && !was_lowered(u)) add_candidate(candidates, v, u, k);
        } else if (par[u] == v && !was_lowered(u)) {  // another label: v was its parent?
          add_candidate(candidates, v, u, k);
        }
        return;
      }
      const T fu = field[u];
      if (!detail::inside<typename P::metric_type>(fu)) return;
      const T nd = search::relax(after.metric, after.edges.length[k], dv, fv, fu);
      const auto nk = nd < inf ? kt::make(nd, l) : kt::unreached;
      if (nk < ku) {
        dist[u] = kt::distance(nk);
        lab[u] = l;
        if (lowered_bits.insert(u)) lowered.push_back(u);
        heap.push(nk, u);
      } else if (!was_lowered(u) && (par[u] == v || (nk == ku && lu == l))) {
        // not lowered (yet): v was u's parent, or realises u's key; decided once every key is final
        add_candidate(candidates, v, u, k);
      }
    });
    // voronoi()'s sources (node l on voxel v at distance 0) have no parent
    const bool source = dv == T(0) && std::size_t(l) < seed_count && seeds[std::size_t(l)] == v;
    par[v] = source ? no_index : best;
  }
  return settled;
}

}  // namespace geovoronoi::detail::update

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

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/dijkstra/engine.hpp>
#include <geovoronoi/detail/key.hpp>
#include <geovoronoi/detail/radix_heap.hpp>
#include <geovoronoi/detail/sse_metric.hpp>
#include <geovoronoi/detail/stencil_walk.hpp>
#include <geovoronoi/detail/validate.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <string>
#include <type_traits>
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

namespace detail::update {

/// A set of voxels as one bit each.
class voxel_bits {
 public:
  explicit voxel_bits(index_t n) : w_(std::size_t((n + 63) / 64), 0) {}
  bool test(index_t v) const noexcept { return (w_[std::size_t(v >> 6)] >> (v & 63)) & 1u; }
  /// Sets the bit; true when it was clear.
  bool insert(index_t v) noexcept {
    auto& w = w_[std::size_t(v >> 6)];
    const std::uint64_t b = std::uint64_t(1) << (v & 63);
    if (w & b) return false;
    w |= b;
    return true;
  }
  void erase(index_t v) noexcept { w_[std::size_t(v >> 6)] &= ~(std::uint64_t(1) << (v & 63)); }
  /// The words (bit v of word v / 64), for loops that keep the pointer in a register.
  std::uint64_t* words() noexcept { return w_.data(); }

 private:
  std::vector<std::uint64_t> w_;
};

/// The canonical parent of voxel @p v (detail/parents.hpp's rule): the lowest-index neighbour whose
/// relaxation reproduces v's key; none for unreached voxels and sources.
template <class P, class D>
index_t parent_of(const P& p, const stencil_walker<P::dim>& walk, const D& d, index_t v) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const label_t l = d.label[v];
  if (l == no_label) return no_index;
  // voronoi()'s sources: seed i at distance 0 with label i
  if (std::size_t(l) < d.seeds.size() && d.seeds[std::size_t(l)] == v && d.distance[v] == T(0)) return no_index;
  const auto target = kt::make(d.distance[v], l);
  const T fv = p.field[v];
  index_t best = no_index;
  const T dv = d.distance[v];
  walk.for_each_neighbour(p, v, [&](int k, index_t u) {
    // a realiser carries v's label and, weights being >= 0, is no farther than v: test that first;
    // neighbours come in increasing index order, so the first realiser is the lowest-index one
    if (best != no_index || d.label[u] != l || !(d.distance[u] <= dv)) return;
    const T w = p.metric(p.edges.length[k], p.field[u], fv);
    const T nd = d.distance[u] + w;
    if (kt::make(nd, d.label[u]) == target) best = u;
  });
  return best;
}

/// The checks every change shares: the diagram fits the problem and has parents.
template <class P>
void check_diagram(const P& after, const diagram<typename P::value_type, P::dim>& d) {
  const std::string who = "geovoronoi::update: ";
  const index_t n = after.geometry.size();
  if (!(d.geometry() == after.geometry) || d.label.size() != n)
    throw std::invalid_argument(who + "the diagram's grid differs from the problem's");
  if (d.parent.size() != n)
    throw std::invalid_argument(who + "the diagram has no parent image; compute it with solve_options::with_parent "
                                      "(the update follows the shortest-path tree)");
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

/// What one update applies; null/empty members change nothing.
template <int Dim>
struct edit_refs {
  const cut_set<Dim>* cut = nullptr;
  const std::vector<index_t>* carved = nullptr;
  const std::vector<index_t>* added = nullptr;
  const std::vector<index_t>* restiffened = nullptr;
  const std::vector<node_edit<Dim>>* nodes = nullptr;
};

/// The node list after @p edits, applied in order to @p seeds; positions are checked.
template <int Dim>
std::vector<index_t> edit_node_list(const grid<Dim>& g, std::vector<index_t> nodes,
                                  const std::vector<node_edit<Dim>>& edits) {
  const std::string who = "geovoronoi::update: ";
  for (std::size_t e = 0; e < edits.size(); ++e) {
    const auto& x = edits[e];
    const std::string name = "node edit " + std::to_string(e);
    const bool adds = x.what == node_edit<Dim>::kind::add;
    const std::size_t pos = adds && x.position == node_edit<Dim>::append ? nodes.size() : x.position;
    if (adds ? pos > nodes.size() : pos >= nodes.size())
      throw std::invalid_argument(who + name + " names node position " + std::to_string(x.position) +
                                  ", but the node list has " + std::to_string(nodes.size()) + " nodes at that point");
    if (x.what == node_edit<Dim>::kind::remove) {
      nodes.erase(nodes.begin() + std::ptrdiff_t(pos));
      continue;
    }
    if (!g.contains(x.voxel))
      throw std::invalid_argument(who + name + " puts a node at " + to_string<Dim>(x.voxel) + ", outside the grid");
    if (adds)
      nodes.insert(nodes.begin() + std::ptrdiff_t(pos), g.index(x.voxel));
    else
      nodes[pos] = g.index(x.voxel);
  }
  return nodes;
}

/// Whether @p v is the source of its label (node l on voxel v at distance 0).
template <class T, int Dim>
bool is_source(const diagram<T, Dim>& d, index_t v) {
  const label_t l = d.label[v];
  return l != no_label && std::size_t(l) < d.seeds.size() && d.seeds[std::size_t(l)] == v && d.distance[v] == T(0);
}

/// A full solve in place of the diagram's nodes (with parents), through the update's state.
template <class P, class Keys, class Heap>
void solve_all(const P& after, diagram<typename P::value_type, P::dim>& d, Keys& keys, Heap& heap) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const index_t n = after.geometry.size();
  const stencil_walker<P::dim> walk(after);
  for (index_t v = 0; v < n; ++v) {
    d.distance[v] = std::numeric_limits<T>::infinity();
    d.label[v] = no_label;
  }
  heap.clear();
  for (std::size_t j = 0; j < d.seeds.size(); ++j) {
    const auto k = kt::make(T(0), label_t(j));
    keys.set(d.seeds[j], k);
    heap.push(k, d.seeds[j]);
  }
  dijkstra::run(after, keys, heap, [](index_t, T nd) { return nd < std::numeric_limits<T>::infinity(); });
  for (index_t v = 0; v < n; ++v) d.parent[v] = parent_of(after, walk, d, v);
}

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
                                     sse_weight<typename P::metric_type>::value &&
                                     sse_inside<typename P::metric_type>::value && P::neighbours <= 32;
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
        using W = sse_weight<typename P::metric_type>;
        using I = sse_inside<typename P::metric_type>;
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
          const __m128 back = _mm_add_ps(du, W::apply(len, fu, vfv));
          m_real |= bits(_mm_and_si128(final_same, _mm_cmpeq_epi32(_mm_castps_si128(back), vdb))) << k;
          m_same_eq |= bits(_mm_and_si128(final_same, _mm_castps_si128(_mm_cmpeq_ps(du, vdv)))) << k;
          m_other |= (~bits(_mm_or_si128(larger, same)) & 15u) << k;
          // a larger key inside the domain: relax it with nk = (fl(dv + w), l), unreached on overflow
          const __m128 w = W::apply(len, vfv, fu);
          const __m128 x = _mm_add_ps(vdv, w);
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
          dijkstra::bad_weight(double(after.metric(after.edges.length[k], fv, field[v + delta4[k]])));
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
          if (best == no_index && kt::make(du + after.metric(after.edges.length[k], field[u], fv), l) == vkey) best = u;
          // an equal distance (a zero or absorbed weight): v may realise u's key too
          if (du == dv && !was_lowered(u)) add_candidate(candidates, v, u, k);
        } else if (par[u] == v && !was_lowered(u)) {  // another label: v was its parent?
          add_candidate(candidates, v, u, k);
        }
        return;
      }
      const T fu = field[u];
      if (!detail::inside<typename P::metric_type>(fu)) return;
      const T w = after.metric(after.edges.length[k], fv, fu);
      if (!(w >= T(0))) dijkstra::bad_weight(double(w));
      const T nd = dv + w;
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

/// Applies @p e to @p d in place (see update_in_place(policy, after, d, change)).
template <class P>
update_stats apply(const P& after, diagram<typename P::value_type, P::dim>& d, const edit_refs<P::dim>& e) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  constexpr int Dim = P::dim;
  const std::string who = "geovoronoi::update: ";
  const index_t n = after.geometry.size();
  check_diagram(after, d);
  update_stats st;
  const stencil_walker<Dim> walk(after);
  const auto whole = without_cuts(after);
  auto where = [&](index_t v) { return to_string<Dim>(after.geometry.coords(v)); };

  // ---- the node list after the change, and which old node each new one continues -----------------
  const std::vector<index_t>& old_nodes = d.seeds;
  std::vector<index_t> nodes = e.nodes ? edit_node_list(after.geometry, old_nodes, *e.nodes) : old_nodes;
  // an old node continues as the new node on the same voxel if that keeps the old nodes' relative
  // order (so every old tie keeps its outcome); any other old node is removed, any other new one added
  std::vector<label_t> relabel(old_nodes.size(), no_label);
  std::vector<char> fresh(nodes.size(), 1);
  bool shifted = false;
  if (e.nodes) {
    std::vector<std::pair<index_t, std::size_t>> by_voxel(nodes.size());
    for (std::size_t j = 0; j < nodes.size(); ++j) by_voxel[j] = {nodes[j], j};
    std::sort(by_voxel.begin(), by_voxel.end());
    long last = -1;
    for (std::size_t i = 0; i < old_nodes.size(); ++i) {
      const auto it = std::lower_bound(by_voxel.begin(), by_voxel.end(), std::make_pair(old_nodes[i], std::size_t(0)));
      if (it == by_voxel.end() || it->first != old_nodes[i] || long(it->second) <= last) continue;
      last = long(it->second);
      relabel[i] = label_t(it->second);
      fresh[it->second] = 0;
      shifted = shifted || it->second != i;
    }
  } else {
    for (std::size_t i = 0; i < old_nodes.size(); ++i) relabel[i] = label_t(i), fresh[i] = 0;
  }
  std::vector<index_t> sorted_nodes(nodes);
  std::sort(sorted_nodes.begin(), sorted_nodes.end());
  auto node_at = [&](index_t v) -> long {
    if (!std::binary_search(sorted_nodes.begin(), sorted_nodes.end(), v)) return -1;
    return long(std::find(nodes.begin(), nodes.end(), v) - nodes.begin());
  };

  // ---- voxels whose field value changed -----------------------------------------------------------
  std::vector<index_t> changed;
  const bool any_field = (e.carved && !e.carved->empty()) || (e.added && !e.added->empty()) ||
                         (e.restiffened && !e.restiffened->empty());
  voxel_bits in_changed(any_field ? n : 0);
  auto take = [&](const std::vector<index_t>* list, const char* what) {
    if (!list) return;
    for (const index_t v : *list) {
      if (v < 0 || v >= n)
        throw std::invalid_argument(who + what + " voxel " + std::to_string(v) + " is outside the grid (" +
                                    std::to_string(n) + " voxels)");
      if (in_changed.insert(v)) changed.push_back(v);
    }
  };
  take(e.carved, "carved");
  take(e.added, "added");
  take(e.restiffened, "restiffened");
  if (e.carved)
    for (const index_t v : *e.carved) {
      if (after.inside(v))
        throw std::invalid_argument(who + "carved voxel " + where(v) +
                                    " is still inside the domain of the problem after the change");
      const long j = node_at(v);
      if (j >= 0)
        throw std::invalid_argument(who + "the carving removes seed " + std::to_string(j) + " at " + where(v) +
                                    "; remove the node instead");
    }
  if (e.added)
    for (const index_t v : *e.added)
      if (!after.inside(v))
        throw std::invalid_argument(who + "added voxel " + where(v) +
                                    " is outside the domain of the problem after the change (field value " +
                                    std::to_string(double(after.field[v])) + ")");
  if (e.nodes || any_field) {
    std::vector<source<T>> s(nodes.size());
    for (std::size_t j = 0; j < nodes.size(); ++j) s[j] = {nodes[j], T(0), label_t(j)};
    detail::validate_sources(after, s, "node");
  }

  // ---- 1. roots of the invalidated subtrees ------------------------------------------------------
  std::vector<index_t> invalid;
  voxel_bits in_invalid(n);
  auto root = [&](index_t v) {
    if (d.label[v] != no_label && in_invalid.insert(v)) invalid.push_back(v), ++st.cut_tree_edges;
  };
  if (e.cut && !e.cut->empty()) {
    if (!(e.cut->geometry() == after.geometry) || e.cut->directions() != P::neighbours)
      throw std::invalid_argument(who + "the cut_set of the change belongs to another grid or connectivity");
    index_t bad_u = -1;
    int bad_d = -1;
    e.cut->for_each_edge([&](index_t u, int k) {
      if (!((after.cut_mask(u) >> k) & 1u)) bad_u = u, bad_d = k;
      const index_t v = u + after.edges.delta[k];
      if (d.parent[v] == u) root(v);
      if (d.parent[u] == v) root(u);
    });
    if (bad_u >= 0)
      throw std::invalid_argument(who + "the edge from voxel " + where(bad_u) + " in direction " +
                                  std::to_string(bad_d) + " is in the change but not cut in the problem after it");
  }
  // a tree edge touching a changed voxel stays only if it still yields a key no larger than the old
  // one (then the old key stays an upper bound reached by a path); a voxel leaving the domain goes
  for (const index_t s : changed) {
    if (d.label[s] == no_label) continue;
    if (!after.inside(s)) {
      root(s);
      continue;
    }
    const T fs = after.field[s];
    const T ds = d.distance[s];
    const index_t ps = d.parent[s];
    walk.for_each_neighbour(after, s, [&](int k, index_t u) {
      if (u == ps) {
        if (after.inside(u) && !(d.distance[u] + after.metric(after.edges.length[k], after.field[u], fs) <= ds)) root(s);
      } else if (d.parent[u] == s) {
        if (after.inside(u) && !(ds + after.metric(after.edges.length[k], fs, after.field[u]) <= d.distance[u]))
          root(u);
      }
    });
  }
  // a removed node's cell is its tree
  for (std::size_t i = 0; i < old_nodes.size(); ++i)
    if (relabel[i] == no_label && d.label[old_nodes[i]] == label_t(i)) root(old_nodes[i]), ++st.nodes_removed;

  // ---- 2. the subtrees: children are the neighbours (any stencil edge) whose parent is x ---------
  for (std::size_t i = 0; i < invalid.size(); ++i) {
    const index_t x = invalid[i];
    walk.for_each_neighbour(whole, x, [&](int, index_t y) {
      if (d.parent[y] == x && in_invalid.insert(y)) invalid.push_back(y);
    });
  }
  st.invalidated = invalid.size();
  for (index_t x : invalid) {
    d.distance[x] = std::numeric_limits<T>::infinity();
    d.label[x] = no_label;
    d.parent[x] = no_index;
  }
  // the remaining labels follow their node to its new position (an order-preserving map, so every
  // comparison between remaining keys, ties included, is unchanged); a linear pass, only when needed
  if (shifted)
    for (index_t v = 0; v < n; ++v)
      if (d.label[v] != no_label) d.label[v] = relabel[std::size_t(d.label[v])];
  d.seeds = nodes;

  // ---- 3. start keys: invalidated and changed voxels pull from valid neighbours; changed voxels
  //         and (re)started sources are queued, and Dijkstra lowers whatever gets better ---------
  std::vector<index_t> lowered;
  voxel_bits lowered_bits(n);
  std::vector<parent_candidate> candidates;
  tracking_keys<T> keys{d.distance.data(), d.label.data(), after.field, &lowered_bits, &lowered, {}};
  radix_heap<T> heap;
  voxel_bits in_boundary(n);
  std::size_t boundary = 0;
  const T inf = std::numeric_limits<T>::infinity();
  // The least key that x's reached neighbours offer over their edges to x, passing over those that
  // skip(u) rejects; seen(u) is told of every reached neighbour considered.
  auto least_offer = [&](index_t x, auto&& skip, auto&& seen) {
    auto best = kt::unreached;
    const T fx = after.field[x];
    walk.for_each_neighbour(after, x, [&](int k, index_t u) {
      const label_t lu = d.label[u];
      if (lu == no_label || skip(u)) return;
      seen(u);
      const T nd = d.distance[u] + after.metric(after.edges.length[k], after.field[u], fx);
      if (!(nd < inf)) return;
      const auto c = kt::make(nd, lu);
      if (c < best) best = c;
    });
    return best;
  };
  auto none = [](index_t) { return false; };
  auto ignore = [](index_t) {};
  // the invalidated voxels pull from their valid neighbours; until every pull is known their keys
  // stay unreached (the reset above), so a reached neighbour is a valid one and no set test is needed
  {
    std::vector<std::pair<index_t, typename kt::key_type>> start;
    start.reserve(invalid.size());
    auto count_boundary = [&](index_t u) {
      if (in_boundary.insert(u)) ++boundary;
    };
    for (const index_t x : invalid) {
      if (!after.inside(x)) continue;  // a voxel outside the domain stays unreached
      const auto best = least_offer(x, none, count_boundary);
      if (best != kt::unreached) start.emplace_back(x, best);
    }
    for (const auto& [x, k] : start) {
      keys.set(x, k);
      heap.push(k, x);
    }
  }
  // a changed voxel that stayed valid pulls from the valid neighbours (the invalidated ones hold
  // start keys by then, not final ones)
  if (any_field)
    for (index_t x : changed) {
      if (in_invalid.test(x) || !after.inside(x)) continue;  // outside the domain: stays unreached
      const auto now = keys.get(x);
      const auto best = std::min(now, least_offer(x, [&](index_t u) { return in_invalid.test(u); }, ignore));
      if (best < now) keys.set(x, best);
      if (best != kt::unreached) heap.push(best, x);
    }
  std::vector<index_t> restarted;
  for (std::size_t j = 0; j < nodes.size(); ++j)
    if (fresh[j] || in_invalid.test(nodes[j])) {
      restarted.push_back(nodes[j]);
      const auto k = kt::make(T(0), label_t(j));
      if (k < keys.get(nodes[j])) keys.set(nodes[j], k);
      heap.push(keys.get(nodes[j]), nodes[j]);
      ++st.sources_added;
    }
  st.boundary = boundary;
  // the accept rule of the unbounded solve: a sum that overflows to +inf reaches nothing
  st.settled = settle(after, d, heap, walk, lowered_bits, lowered, candidates);
  for (index_t v : lowered)
    if (!in_invalid.test(v)) ++st.lowered;

  // ---- 4. parents: a voxel's set of realisers changes only if its key, a neighbour's key or an
  //         edge between them changed. The parent rule runs on the voxels whose key changed, on the
  //         changed voxels and their neighbours (their edges changed), and on the voxels whose parent
  //         changed key; any other neighbour of a changed key only takes it as parent when it now
  //         realises the neighbour's key and has a lower index than its parent (an O(1) test).
  std::vector<index_t> checked;
  // the keyed voxels that settled gave their neighbours' cases to `candidates` as they settled; the
  // others (left unreached) are walked here
  auto fix_parents = [&](const std::vector<const std::vector<index_t>*>& lists, bool edges_changed) {
    voxel_bits marked(n);
    std::vector<index_t> keyed;
    checked.clear();
    for (const auto* l : lists)
      for (index_t x : *l)
        if (marked.insert(x)) keyed.push_back(x), checked.push_back(x);
    if (edges_changed)
      for (index_t x : changed) {
        if (marked.insert(x)) checked.push_back(x);
        walk.for_each_neighbour(after, x, [&](int, index_t u) {
          if (marked.insert(u)) checked.push_back(u);
        });
      }
    // the keyed voxels got their parent when they settled (or stay unreached, without one)
    for (std::size_t i = keyed.size(); i < checked.size(); ++i) d.parent[checked[i]] = parent_of(after, walk, d, checked[i]);
    auto decide = [&](index_t x, int k, index_t y) {
      if (marked.test(y)) return;
      if (d.parent[y] == x) {  // its parent's key changed: the rule decides again
        marked.insert(y);
        checked.push_back(y);
        d.parent[y] = parent_of(after, walk, d, y);
        return;
      }
      const label_t lx = d.label[x];
      const T dx = d.distance[x];
      if (lx == no_label || d.label[y] != lx || !(dx <= d.distance[y]) || !(x < d.parent[y])) return;
      if (d.distance[y] == dx + after.metric(after.edges.length[k], after.field[x], after.field[y])) d.parent[y] = x;
    };
    for (const auto& c : candidates) decide(c.x, c.k, c.y);
    candidates.clear();
    for (index_t x : keyed)
      if (d.label[x] == no_label) walk.for_each_neighbour(after, x, [&](int k, index_t y) { decide(x, k, y); });
    st.reparented += checked.size();
  };
  fix_parents({&invalid, &lowered, &restarted}, any_field);
  // ---- 5. repair: a kept or pulled key can lose its last realiser when the key it came from was
  //         lowered to one whose sum rounds to the same distance with another label (fl(a + w) ==
  //         fl(b + w) for a < b): the key is then below the full solve's. Such a voxel has no parent;
  //         its subtree is re-solved like an invalidated one, until every key is realised.
  for (int round = 0;; ++round) {
    std::vector<index_t> redo;
    for (index_t x : checked)
      if (d.label[x] != no_label && d.parent[x] == no_index && !is_source(d, x)) redo.push_back(x);
    if (redo.empty()) break;
    ++st.repairs;
    if (round == 64) {  // a safety net: a full solve in place, exact by construction
      solve_all(after, d, keys, heap);
      st.reparented += std::size_t(n);
      return st;
    }
    voxel_bits in_redo(n);
    for (index_t x : redo) in_redo.insert(x);
    for (std::size_t i = 0; i < redo.size(); ++i) {
      const index_t x = redo[i];
      walk.for_each_neighbour(whole, x, [&](int, index_t y) {
        if (d.parent[y] == x && in_redo.insert(y)) redo.push_back(y);
      });
    }
    for (index_t x : redo) {
      d.distance[x] = inf;
      d.label[x] = no_label;
      d.parent[x] = no_index;
    }
    heap.clear();  // the radix heap is monotone: start a new run from an empty one
    for (index_t x : redo) {
      if (!after.inside(x)) continue;
      auto best = least_offer(x, [&](index_t u) { return in_redo.test(u); }, ignore);
      const long j = node_at(x);  // a node's voxel that another node's key had taken at distance 0
      if (j >= 0 && kt::make(T(0), label_t(j)) < best) best = kt::make(T(0), label_t(j));
      if (best != kt::unreached) {
        keys.set(x, best);
        heap.push(best, x);
      }
    }
    for (index_t x : lowered) lowered_bits.erase(x);
    lowered.clear();
    st.settled += settle(after, d, heap, walk, lowered_bits, lowered, candidates);
    fix_parents({&redo, &lowered}, false);
  }
  return st;
}

}  // namespace detail::update

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
template <class Policy, class P, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const cut_set<P::dim>& added) {
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
template <class Policy, class P, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const carving& carved) {
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
template <class Policy, class P, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
update_stats update_in_place(const Policy&, const P& after, diagram<typename P::value_type, P::dim>& d,
                             const change<P::dim>& c) {
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
template <class Policy, class P, class Change, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
diagram<typename P::value_type, P::dim> update(const Policy& policy, const P& after,
                                               const diagram<typename P::value_type, P::dim>& before,
                                               const Change& c, update_stats* stats = nullptr) {
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

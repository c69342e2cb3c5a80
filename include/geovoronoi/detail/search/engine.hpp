#pragma once
// The shared Dijkstra engine: label-carrying Dijkstra on the implicit grid graph (or on an explicit
// graph, a branching grid's copies: topology.hpp) with a radix heap over packed (distance, label) keys. One loop serves the dense solve, the bounded solve and
// insert-query, for the seq backend and for the Thrust backend's host insert-query; they differ only
// in where keys are stored (a dense array, or scratch bounded by what is visited: the pages of
// sparse.hpp) and in which relaxations they accept.

#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

namespace geovoronoi::detail::search {

/// One voxel of the dense solver's working array: its key and its field value side by side, so a
/// relaxation touches one cache line per neighbour instead of two.
template <class T>
struct node {
  typename key_traits<T>::key_type key;
  T field;
  typename key_traits<T>::key_type get_key() const noexcept { return key; }
  void set_key(typename key_traits<T>::key_type k) noexcept { key = k; }
};
/// For float the key is stored as two 32-bit halves: 12 bytes a voxel instead of 16.
template <>
struct node<float> {
  std::uint32_t hi, lo;
  float field;
  std::uint64_t get_key() const noexcept { return (std::uint64_t(hi) << 32) | lo; }
  void set_key(std::uint64_t k) noexcept { hi = std::uint32_t(k >> 32), lo = std::uint32_t(k); }
};

/// A node of an explicit graph whose walker keeps per-node walk bits (topology.hpp's link_walker):
/// the bits beside the key and the field, on the cache line the search reads when it settles the node.
template <class T>
struct walk_node : node<T> {
  std::uint32_t bits;
};

/// Keys and field values (and walk bits, with walk_node) in a dense per-voxel array.
template <class T, class Node = node<T>>
struct dense_keys {
  using kt = key_traits<T>;
  Node* n;
  Node& at(index_t v) noexcept { return n[v]; }
  typename kt::key_type get(index_t v) const noexcept { return n[v].get_key(); }
  void set(index_t v, typename kt::key_type key) noexcept { n[v].set_key(key); }
  T field(index_t v) const noexcept { return n[v].field; }
  template <class M = Node>
  auto walk_bits(index_t v) const noexcept -> decltype(std::declval<const M&>().bits) {
    return n[v].bits;
  }
  template <class Stencil>
  void prefetch(index_t v, const Stencil& s) const noexcept {
    for (int k = 0; k < Stencil::size; ++k) __builtin_prefetch(n + v + s.delta[k], 1, 1);
  }
};

template <class S, class = void>
struct has_walk_bits : std::false_type {};
template <class S>
struct has_walk_bits<S, std::void_t<decltype(std::declval<const S&>().walk_bits(index_t()))>> : std::true_type {};

template <class H, class = void>
struct has_peek : std::false_type {};
template <class H>
struct has_peek<H, std::void_t<decltype(std::declval<const H&>().peek_ready())>> : std::true_type {};

/// Every State's at(v) returns a reference to the voxel's slot (its key, or a node with get_key(),
/// set_key() and field), valid at least until the next at(): a relaxation looks it up once.
template <class K>
auto slot_key(const K& key) noexcept -> decltype(key < key, K()) {
  return key;
}
template <class N>
auto slot_key(const N& node) noexcept -> decltype(node.get_key()) {
  return node.get_key();
}
template <class S, class K>
auto slot_field(const S& st, const K&, index_t v) noexcept -> decltype(std::declval<K>() < std::declval<K>(), st.field(v)) {
  return st.field(v);
}
template <class S, class N>
auto slot_field(const S&, const N& node, index_t) noexcept -> decltype(node.field) {
  return node.field;
}
template <class K>
auto set_slot_key(K& slot, const K& key) noexcept -> decltype(key < key, void()) {
  slot = key;
}
template <class N, class K>
auto set_slot_key(N& node, const K& key) noexcept -> decltype(node.set_key(key)) {
  node.set_key(key);
}

/// What a run reports besides its result, for the solves that watch (see solve_monitor): the run
/// calls overflow() when it rejects a candidate whose distance is +inf (detail/overflow.hpp) and,
/// when `watching`, tick(settled) every tick_mask + 1 settled voxels. The default watches nothing
/// and compiles away.
struct no_monitor {
  static constexpr bool watching = false;
  void overflow() noexcept {}
  void tick(std::size_t) {}
};

/// Voxels settled between two progress reports of a watched run (a power of two).
inline constexpr std::size_t tick_mask = 4095;

/**
 * Runs Dijkstra from the keys already in the heap until it is empty. Heap is a monotone priority
 * queue of (key, voxel) items (radix_heap; the benchmarks also plug in binary heaps to compare).
 * accept(u, nd) filters relaxations (radius bounds, insert-query pruning): a rejected candidate is
 * neither stored nor queued. Returns the number of voxels settled.
 */
template <class P, class State, class Heap, class Accept, class Monitor = no_monitor>
std::size_t run(const P& p, State& st, Heap& heap, Accept&& accept, Monitor&& mon = Monitor{}) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const walker_t<P> walk(p);
  std::size_t settled = 0;
  while (!heap.empty()) {
    const auto it = heap.pop();
    if (it.key != st.get(it.voxel)) continue;  // stale entry: a smaller key was queued later
    ++settled;
    if constexpr (std::decay_t<Monitor>::watching)
      if ((settled & tick_mask) == 0) mon.tick(settled);
    const index_t v = it.voxel;
    if constexpr (has_peek<Heap>::value) {
      if constexpr (implicit_grid_v<P>) {
        if (const auto* nx = heap.peek_ready()) st.prefetch(nx->voxel, p.edges);
      } else if constexpr (has_walk_bits<State>::value) {
        if (const auto* nx = heap.peek_ready()) walk.prefetch_keys(p, st, nx->voxel);
      } else {
        if (const auto* nx = heap.peek_ready()) walk.prefetch(nx->voxel);
      }
    }
    const T dv = kt::distance(it.key);
    const label_t l = kt::label(it.key);
    const T fv = st.field(v);
    const auto relax_edge = [&](int k, index_t u) {
      auto& slot = st.at(u);
      // A neighbour whose key is already <= the popped key cannot improve (weights are >= 0): skip
      // it before paying for the metric. This covers every settled neighbour.
      const auto ku = slot_key(slot);
      if (!(it.key < ku)) return;
      const T fu = slot_field(st, slot, u);
      if (!detail::inside<typename P::metric_type>(fu)) return;
      const T nd = relax(p.metric, p.edges.length[k], dv, fv, fu);
      if (!accept(u, nd)) {
        // the unbounded solves reject nothing else: no cost on their hot path
        if (!(nd <= std::numeric_limits<T>::max())) mon.overflow();
        return;
      }
      const auto nk = kt::make(nd, l);
      if (nk < ku) {
        set_slot_key(slot, nk);
        heap.push(nk, u);
      }
    };
    if constexpr (has_walk_bits<State>::value)
      walk.for_each_neighbour(p, v, st.walk_bits(v), relax_edge);
    else
      walk.for_each_neighbour(p, v, relax_edge);
  }
  return settled;
}

/// Voxels (nodes) of the domain (the denominator of the solves' progress).
template <class P>
index_t count_inside(const P& p) {
  index_t c = 0;
  const index_t n = node_count(p);
  for (index_t v = 0; v < n; ++v) c += detail::inside<typename P::metric_type>(p.field[v]) ? 1 : 0;
  return c > 0 ? c : 1;
}

/// The monitor of the dense and bounded solves: records an overflow, reports progress as settled
/// voxels over @p total (the domain's voxels, counted only when someone listens).
struct solve_monitor {
  static constexpr bool watching = true;
  const solve_control* control = nullptr;
  double total = 1;
  bool overflowed = false;
  void overflow() noexcept { overflowed = true; }
  void tick(std::size_t settled) {
    if (control) control->report(std::min(0.999, double(settled) / total));
  }
};

/// Queues the sources below @p radius (the smallest key wins on a shared voxel) and runs the search
/// bounded by the radius: the common start of the dense and the bounded solves.
template <class P, class State, class Heap, class Monitor = no_monitor>
std::size_t run_from_sources(const P& p, State& st, Heap& heap,
                             const std::vector<source<typename P::value_type>>& sources,
                             typename P::value_type radius, Monitor&& mon = Monitor{}) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  for (const auto& s : sources)
    if (s.distance < radius) {
      const auto k = kt::make(s.distance, s.label);
      if (k < st.get(s.voxel)) {
        st.set(s.voxel, k);
        heap.push(k, s.voxel);
      }
    }
  return run(p, st, heap, [radius](index_t, T nd) { return nd < radius; }, mon);
}

}  // namespace geovoronoi::detail::search

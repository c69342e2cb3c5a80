#pragma once
/// @file update.hpp
/// @brief Incremental update of a Voronoi diagram after a cut: only the voxels whose shortest-path
///        tree path crosses a newly cut edge are re-solved, and the result is bitwise identical to a
///        full solve of the cut problem (distances, labels and parents, ties included).
///
/// Why it is exact (docs/cuts.md, "Incremental update"): cutting removes edges, so no key (distance,
/// label) can decrease. A voxel whose parent chain to its seed crosses no cut edge still has that
/// chain in the new graph, and it reproduces the old key step by step; since the new key cannot be
/// smaller, it is the old key. Every other voxel (the subtrees hanging below the cut tree edges) is
/// invalidated and re-solved by Dijkstra seeded with the keys of its valid neighbours, which reaches
/// the same least fixed point as a full solve. Parents are recomputed, with the library's rule (the
/// lowest-index neighbour that realises the key), on the invalidated voxels and on their valid
/// neighbours, the only voxels whose set of realising neighbours can change.

#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/dijkstra/engine.hpp>
#include <geovoronoi/detail/key.hpp>
#include <geovoronoi/detail/radix_heap.hpp>
#include <geovoronoi/detail/stencil_walk.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/policy.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <cstdint>
#include <limits>
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
  std::size_t cut_tree_edges = 0;  ///< roots: newly cut parent edges of the old tree, or carved reached voxels
  std::size_t invalidated = 0;     ///< voxels whose tree path crossed a new cut (re-solved)
  std::size_t boundary = 0;        ///< valid voxels next to them that seeded the re-solve
  std::size_t settled = 0;         ///< voxels the re-solve settled
  std::size_t reparented = 0;      ///< voxels whose parent was recomputed
};

namespace detail::update {

/// A Dijkstra state over a diagram's own distance and label images (no extra per-voxel keys), so an
/// update touches only the voxels it visits.
template <class T>
struct diagram_keys {
  using kt = key_traits<T>;
  using key_type = typename kt::key_type;
  T* dist;
  label_t* lab;
  const T* fieldp;
  struct slot {
    T* dist;
    label_t* lab;
    T field;
    key_type get_key() const noexcept { return *lab == no_label ? kt::unreached : kt::make(*dist, *lab); }
    void set_key(key_type k) noexcept {
      *dist = kt::distance(k);
      *lab = kt::label(k);
    }
  };
  slot cur{};
  slot& at(index_t v) noexcept {
    cur = slot{dist + v, lab + v, fieldp[v]};
    return cur;
  }
  key_type get(index_t v) const noexcept { return lab[v] == no_label ? kt::unreached : kt::make(dist[v], lab[v]); }
  void set(index_t v, key_type k) noexcept {
    dist[v] = kt::distance(k);
    lab[v] = kt::label(k);
  }
  T field(index_t v) const noexcept { return fieldp[v]; }
  template <class S>
  void prefetch(index_t, const S&) const noexcept {}
};

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
    // a realiser carries v's label and, weights being >= 0, is no farther than v: test that first
    if (d.label[u] != l || !(d.distance[u] <= dv)) return;
    const T w = p.metric(p.edges.length[k], p.field[u], fv);
    const T nd = d.distance[u] + w;
    if (kt::make(nd, d.label[u]) == target && (best == no_index || u < best)) best = u;
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

template <class P>
void resolve(const P& after, diagram<typename P::value_type, P::dim>& d, std::vector<index_t>& invalid,
             voxel_bits& in_invalid, update_stats& st);

template <class P>
update_stats cut_in_place(const P& after, diagram<typename P::value_type, P::dim>& d,
                          const cut_set<P::dim>& added) {
  constexpr int Dim = P::dim;
  const std::string who = "geovoronoi::update: ";
  const index_t n = after.geometry.size();
  check_diagram(after, d);
  if (!(added.geometry() == after.geometry) || added.directions() != P::neighbours)
    throw std::invalid_argument(who + "the cut_set of the change belongs to another grid or connectivity");
  update_stats st;
  // 1. roots of the invalidated subtrees: ends of new cut edges whose parent is across the edge
  std::vector<index_t> invalid;
  voxel_bits in_invalid(n);
  index_t bad_u = -1;
  int bad_d = -1;
  added.for_each_edge([&](index_t u, int k) {
    if (!((after.cut_mask(u) >> k) & 1u)) bad_u = u, bad_d = k;
    const index_t v = u + after.edges.delta[k];
    if (d.parent[v] == u && in_invalid.insert(v)) invalid.push_back(v), ++st.cut_tree_edges;
    if (d.parent[u] == v && in_invalid.insert(u)) invalid.push_back(u), ++st.cut_tree_edges;
  });
  if (bad_u >= 0)
    throw std::invalid_argument(who + "the edge from voxel " + to_string<Dim>(after.geometry.coords(bad_u)) +
                                " in direction " + std::to_string(bad_d) +
                                " is in the change but not cut in the problem after it");
  resolve(after, d, invalid, in_invalid, st);
  return st;
}

/// Carving: the carved voxels (outside the domain after the change) and their subtrees are
/// invalidated; the carved ones stay unreached.
template <class P>
update_stats carve_in_place(const P& after, diagram<typename P::value_type, P::dim>& d,
                            const std::vector<index_t>& carved) {
  constexpr int Dim = P::dim;
  const std::string who = "geovoronoi::update: ";
  const index_t n = after.geometry.size();
  check_diagram(after, d);
  update_stats st;
  std::vector<index_t> invalid;
  voxel_bits in_invalid(n);
  for (const index_t v : carved) {
    if (v < 0 || v >= n)
      throw std::invalid_argument(who + "carved voxel " + std::to_string(v) + " is outside the grid (" +
                                  std::to_string(n) + " voxels)");
    if (after.inside(v))
      throw std::invalid_argument(who + "carved voxel " + to_string<Dim>(after.geometry.coords(v)) +
                                  " is still inside the domain of the problem after the change");
    for (std::size_t i = 0; i < d.seeds.size(); ++i)
      if (d.seeds[i] == v)
        throw std::invalid_argument(who + "the carving removes seed " + std::to_string(i) + " at " +
                                    to_string<Dim>(after.geometry.coords(v)) + "; remove the node instead");
    if (d.label[v] != no_label && in_invalid.insert(v)) invalid.push_back(v), ++st.cut_tree_edges;
  }
  resolve(after, d, invalid, in_invalid, st);
  return st;
}

/// Invalidates the subtrees of @p invalid (the roots on entry), re-solves them and recomputes the
/// parents that may have changed.
template <class P>
void resolve(const P& after, diagram<typename P::value_type, P::dim>& d, std::vector<index_t>& invalid,
             voxel_bits& in_invalid, update_stats& st) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  constexpr int Dim = P::dim;
  const index_t n = after.geometry.size();
  // 2. their subtrees: children are the neighbours (any stencil edge, cut or not) whose parent is x
  const auto whole = without_cuts(after);
  const stencil_walker<Dim> walk(after);
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
  // 3. re-solve: each invalidated voxel starts from its best candidate through a valid reached
  //    neighbour (over uncut edges; the relaxation the full solve makes when it pops that neighbour),
  //    then Dijkstra among the invalidated voxels. Valid voxels already hold their final keys, so
  //    it lowers only invalidated ones.
  diagram_keys<T> keys{d.distance.data(), d.label.data(), after.field, {}};
  radix_heap<T> heap;
  voxel_bits in_boundary(n);
  std::vector<index_t> boundary;
  const T inf = std::numeric_limits<T>::infinity();
  for (index_t x : invalid) {
    auto best = kt::unreached;
    const T fx = after.field[x];
    const bool open = after.inside(x);  // a carved voxel stays unreached
    walk.for_each_neighbour(after, x, [&](int k, index_t u) {
      if (in_invalid.test(u)) return;
      const label_t lu = d.label[u];
      if (lu == no_label) return;
      if (in_boundary.insert(u)) boundary.push_back(u);
      if (!open) return;
      const T nd = d.distance[u] + after.metric(after.edges.length[k], after.field[u], fx);
      if (!(nd < inf)) return;
      const auto c = kt::make(nd, lu);
      if (c < best) best = c;
    });
    if (best != kt::unreached) {
      keys.set(x, best);
      heap.push(best, x);
    }
  }
  st.boundary = boundary.size();
  // the accept rule of the unbounded solve: a sum that overflows to +inf reaches nothing
  st.settled = dijkstra::run(after, keys, heap, [](index_t, T nd) { return nd < std::numeric_limits<T>::infinity(); });
  // 4. parents: the invalidated voxels, and their valid neighbours, whose realisers may have changed
  for (index_t x : invalid) d.parent[x] = parent_of(after, walk, d, x);
  for (index_t u : boundary) d.parent[u] = parent_of(after, walk, d, u);
  st.reparented = invalid.size() + boundary.size();
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
  return detail::update::cut_in_place(after, d, added);
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
  return detail::update::carve_in_place(after, d, carved.voxels);
}

/// @brief The diagram after the carving @p carved; see update_in_place().
template <class Policy, class P, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
diagram<typename P::value_type, P::dim> update(const Policy& policy, const P& after,
                                               const diagram<typename P::value_type, P::dim>& before,
                                               const carving& carved, update_stats* stats = nullptr) {
  auto d = before;
  const auto s = update_in_place(policy, after, d, carved);
  if (stats) *stats = s;
  return d;
}

/// @brief The diagram after the edges of @p added were cut, from the diagram @p before (computed
///        with parents); bitwise identical to a full solve of @p after. See update_in_place().
template <class Policy, class P, std::enable_if_t<is_backend_policy_v<Policy>, int> = 0>
diagram<typename P::value_type, P::dim> update(const Policy& policy, const P& after,
                                               const diagram<typename P::value_type, P::dim>& before,
                                               const cut_set<P::dim>& added, update_stats* stats = nullptr) {
  auto d = before;
  const auto s = update_in_place(policy, after, d, added);
  if (stats) *stats = s;
  return d;
}

}  // namespace geovoronoi

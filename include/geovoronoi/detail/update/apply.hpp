#pragma once
// Body of update.hpp: applies a change to a diagram in place, bitwise equal to a full solve of the
// changed problem (the argument is in update.hpp's header comment and docs/cuts.md).

#include <geovoronoi/change.hpp>
#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/update/node_list.hpp>
#include <geovoronoi/detail/update/settle.hpp>
#include <geovoronoi/detail/validate.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace geovoronoi::detail::update {

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

/// What one update applies; null/empty members change nothing.
template <int Dim>
struct edit_refs {
  const cut_set<Dim>* cut = nullptr;
  const std::vector<index_t>* carved = nullptr;
  const std::vector<index_t>* added = nullptr;
  const std::vector<index_t>* restiffened = nullptr;
  const std::vector<node_edit<Dim>>* nodes = nullptr;
};

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
  search::run(after, keys, heap, [](index_t, T nd) { return nd < std::numeric_limits<T>::infinity(); });
  for (index_t v = 0; v < n; ++v) d.parent[v] = parent_of(after, walk, d, v);
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
        if (after.inside(u) &&
            !(search::extend(d.distance[u], search::edge_weight(after.metric, after.edges.length[k], after.field[u], fs)) <= ds))
          root(s);
      } else if (d.parent[u] == s) {
        if (after.inside(u) &&
            !(search::extend(ds, search::edge_weight(after.metric, after.edges.length[k], fs, after.field[u])) <= d.distance[u]))
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
      const T nd = search::extend(d.distance[u], search::edge_weight(after.metric, after.edges.length[k], after.field[u], fx));
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
      if (d.distance[y] == search::extend(dx, search::edge_weight(after.metric, after.edges.length[k], after.field[x], after.field[y])))
        d.parent[y] = x;
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

}  // namespace geovoronoi::detail::update

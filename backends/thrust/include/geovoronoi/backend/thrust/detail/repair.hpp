#pragma once
// Targeted label repair for the near-far engine (host side, after the solve).
//
// The engine's distances are exact. Its labels are exact too, except where a voxel's final key was set
// by a *stale* proposal: a neighbour u expanded with an earlier, larger key whose sum d' + w rounded to
// the same float as its final d + w, but which carried a lower label. Such a label is lower than the
// tie rule's, and it can be inherited further along edges that realise the distances.
//
// The engine marks, at every re-expansion of a voxel u, each neighbour v that holds exactly the
// distance u proposes now but a lower label than u's (flag bit `suspect_bit`): every voxel whose key
// came from a stale proposal is among them (u's last expansion uses its final key, and v's key cannot
// have moved since, or it would not be final). This pass takes the marked voxels, adds every voxel
// that inherited one of their labels along a realising edge (d(x) + w(x, y) == d(y), same label), and
// recomputes the labels of that set in increasing distance: each takes the smallest label among its
// realising neighbours (outside the set: exact; inside: already recomputed) and its own source,
// iterated within groups of equal distance from "none" (the greatest fixed point, which is what
// Dijkstra's order produces). docs/backend-thrust.md gives the argument. Cost: proportional to the
// set, which is empty when nothing was expanded twice and small otherwise.

#include <geovoronoi/backend/thrust/detail/engine.hpp>
#include <geovoronoi/config.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cstddef>
#include <limits>
#include <unordered_set>
#include <utility>
#include <vector>

namespace geovoronoi::thrust::detail {

/// Distance and label storage seen by the repair pass: a dense diagram.
template <class T>
struct dense_labels {
  const T* distance;
  label_t* label;
  index_t n;
  /// Position of voxel v in the arrays, or -1 when v was not reached.
  index_t find(index_t v) const noexcept { return distance[v] < std::numeric_limits<T>::infinity() ? v : index_t(-1); }
};

/// The same over a sparse solution (voxels sorted by index).
template <class T>
struct sparse_labels {
  const index_t* voxel;
  const T* distance;
  label_t* label;
  index_t n;
  index_t find(index_t v) const noexcept {
    const index_t* it = std::lower_bound(voxel, voxel + n, v);
    return it != voxel + n && *it == v ? index_t(it - voxel) : index_t(-1);
  }
};

/**
 * Re-derives the labels of @p suspects and of everything that inherited their labels.
 * @return the number of voxels whose label was recomputed (0 when there was no suspect).
 */
template <class P, class Store>
std::size_t repair_labels(const P& p, Store& st, const std::vector<source<typename P::value_type>>& sources,
                          std::vector<index_t> set) {
  using T = typename P::value_type;
  if (set.empty()) return 0;
  const search::walker_t<P> walk(p);

  // sources by voxel, for the label a source gives its own voxel (if its distance is the final one)
  std::vector<std::pair<index_t, std::size_t>> by_voxel(sources.size());
  for (std::size_t i = 0; i < sources.size(); ++i) by_voxel[i] = {sources[i].voxel, i};
  std::sort(by_voxel.begin(), by_voxel.end());
  auto source_label = [&](index_t v, T dv) {
    label_t best = no_label;
    auto it = std::lower_bound(by_voxel.begin(), by_voxel.end(), std::make_pair(v, std::size_t(0)));
    for (; it != by_voxel.end() && it->first == v; ++it) {
      const auto& s = sources[it->second];
      if (s.distance == dv && (best == no_label || s.label < best)) best = s.label;
    }
    return best;
  };

  // 1. the suspects and every voxel that inherited their labels along realising edges
  std::unordered_set<index_t> in_set(set.begin(), set.end());
  for (std::size_t i = 0; i < set.size(); ++i) {
    const index_t x = set[i];
    const index_t ix = st.find(x);
    if (ix < 0) continue;
    const T dx = st.distance[ix];
    const label_t lx = st.label[ix];
    const T fx = p.field[x];
    auto visit = [&](int k, index_t y) {
      if (in_set.count(y)) return;
      const index_t iy = st.find(y);
      if (iy < 0 || st.label[iy] != lx || !p.inside(y)) return;
      const T nd = search::extend(dx, search::edge_weight(p.metric, p.edges.length[k], fx, p.field[y]));
      if (nd == st.distance[iy]) {
        in_set.insert(y);
        set.push_back(y);
      }
    };
    walk.for_each_neighbour(p, x, visit);
  }

  // 2. recompute in increasing distance from "none"; equal distances iterate to their fixed point
  std::vector<std::pair<T, index_t>> order;  // (distance, voxel)
  order.reserve(set.size());
  for (const index_t v : set) {
    const index_t iv = st.find(v);
    if (iv < 0) continue;
    order.push_back({st.distance[iv], v});
    st.label[iv] = no_label;
  }
  std::sort(order.begin(), order.end());
  for (std::size_t lo = 0; lo < order.size();) {
    std::size_t hi = lo;
    while (hi < order.size() && order[hi].first == order[lo].first) ++hi;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i = lo; i < hi; ++i) {
        const index_t v = order[i].second;
        const index_t iv = st.find(v);
        const T dv = order[i].first;
        const T fv = p.field[v];
        label_t best = source_label(v, dv);
        auto take = [&](int k, index_t u) {
          const index_t iu = st.find(u);
          if (iu < 0) return;
          const label_t lu = st.label[iu];
          if (lu == no_label || (best != no_label && lu >= best)) return;
          if (!p.inside(u)) return;
          const T nd = search::extend(st.distance[iu], search::edge_weight(p.metric, p.edges.length[k], p.field[u], fv));
          if (nd == dv) best = lu;
        };
        walk.for_each_neighbour(p, v, take);
        if (best != st.label[iv]) {
          st.label[iv] = best;
          changed = true;
        }
      }
    }
    lo = hi;
  }
  return order.size();
}

}  // namespace geovoronoi::thrust::detail

#pragma once
// Label repair for relaxation-based backends.
//
// Parallel relaxation converges to the right distances, but a label can survive from a proposal that
// a neighbour made through an earlier, larger distance of its own which happened to round to the
// same sum as its final one. Such a label is lower than the one the tie rule defines (keys only ever
// decrease) and no source or neighbour realises it any more. This pass finds those "unsupported"
// voxels, resets them together with every voxel that inherited their label along realising edges,
// and recomputes the reset voxels in increasing distance from the labels realised by final
// distances, iterating within groups of equal distance. The result equals Dijkstra's labels.
// Cost: one scan of every edge, plus work proportional to the (normally tiny) reset set.

#include <geovoronoi/detail/stencil_walk.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <vector>

namespace geovoronoi::detail {

template <class P>
std::size_t repair_labels(const P& p, diagram<typename P::value_type, P::dim>& d,
                          const std::vector<source<typename P::value_type>>& sources) {
  using T = typename P::value_type;
  const index_t n = p.geometry.size();
  const stencil_walker<P> walk(p);
  auto realises = [&](index_t u, int k, index_t v) {
    // edge u -> v through stencil entry k (the opposite entry has the same length)
    const T w = p.metric(p.edges.length[k], p.field[u], p.field[v]);
    return T(d.distance[u] + w) == d.distance[v];
  };
  auto source_of = [&](index_t v) {
    label_t best = no_label;
    for (const auto& s : sources)
      if (s.voxel == v && s.distance == d.distance[v] && (best == no_label || s.label < best)) best = s.label;
    return best;
  };
  std::vector<unsigned char> is_source(static_cast<std::size_t>(n), 0);
  for (const auto& s : sources) is_source[s.voxel] = 1;

  // 1. unsupported voxels
  std::vector<index_t> reset;
  for (index_t v = 0; v < n; ++v) {
    const label_t l = d.label[v];
    if (l == no_label) continue;
    bool ok = is_source[v] && source_of(v) == l;
    if (!ok)
      walk.for_each_neighbour(v, [&](int k, index_t u) {
        if (!ok && d.label[u] == l && p.inside(u) && realises(u, k, v)) ok = true;
      });
    if (!ok) reset.push_back(v);
  }
  if (reset.empty()) return 0;

  // 2. everything that inherited a reset label along realising edges
  std::vector<unsigned char> in_reset(static_cast<std::size_t>(n), 0);
  for (index_t v : reset) in_reset[v] = 1;
  for (std::size_t i = 0; i < reset.size(); ++i) {
    const index_t x = reset[i];
    walk.for_each_neighbour(x, [&](int k, index_t y) {
      if (!in_reset[y] && d.label[y] == d.label[x] && p.inside(y) && realises(x, k, y)) {
        in_reset[y] = 1;
        reset.push_back(y);
      }
    });
  }

  // 3. recompute in increasing distance, from "none", iterating groups of equal distance
  for (index_t v : reset) d.label[v] = no_label;
  std::sort(reset.begin(), reset.end(), [&](index_t a, index_t b) { return d.distance[a] < d.distance[b]; });
  for (std::size_t lo = 0; lo < reset.size();) {
    std::size_t hi = lo;
    while (hi < reset.size() && d.distance[reset[hi]] == d.distance[reset[lo]]) ++hi;
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t i = lo; i < hi; ++i) {
        const index_t v = reset[i];
        label_t best = is_source[v] ? source_of(v) : no_label;
        walk.for_each_neighbour(v, [&](int k, index_t u) {
          const label_t lu = d.label[u];
          if (lu != no_label && (best == no_label || lu < best) && p.inside(u) && realises(u, k, v)) best = lu;
        });
        if (best != d.label[v]) d.label[v] = best, changed = true;
      }
    }
    lo = hi;
  }
  return reset.size();
}

}  // namespace geovoronoi::detail

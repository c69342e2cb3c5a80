#pragma once
// The canonical parent image, computed from finished keys so that it is the same whichever backend
// produced them: among the neighbours u whose relaxation reproduces v's exact (distance, label) key,
// the one with the lowest linear index.

#include <geovoronoi/detail/key.hpp>
#include <geovoronoi/detail/stencil_walk.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <vector>

namespace geovoronoi::detail {

template <class P>
void compute_parents(const P& p, diagram<typename P::value_type, P::dim>& d,
                     const std::vector<source<typename P::value_type>>& sources) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const index_t n = p.geometry.size();
  d.parent = image<index_t, P::dim>(p.geometry, no_index);
  std::vector<unsigned char> is_source(static_cast<std::size_t>(n), 0);
  for (const auto& s : sources)
    if (d.distance[s.voxel] == s.distance && d.label[s.voxel] == s.label) is_source[s.voxel] = 1;
  const stencil_walker<P::dim> walk(p);
  for (index_t v = 0; v < n; ++v) {
    if (d.label[v] == no_label || is_source[v]) continue;
    const auto target = kt::make(d.distance[v], d.label[v]);
    const T fv = p.field[v];
    index_t best = no_index;
    walk.for_each_neighbour(p, v, [&](int k, index_t u) {
      if (d.label[u] == no_label) return;
      // the edge is walked from u to v: w(u -> v), evaluated with the same expression as the solvers
      const T w = p.metric(p.edges.length[k], p.field[u], fv);
      const T nd = d.distance[u] + w;
      if (kt::make(nd, d.label[u]) == target && (best == no_index || u < best)) best = u;
    });
    d.parent[v] = best;
  }
}

}  // namespace geovoronoi::detail

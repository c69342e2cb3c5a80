#pragma once
// The canonical parent rule, computed from finished keys so that it is the same whichever backend
// produced them: a voxel's parent is, among its neighbours u whose relaxation reproduces its exact
// (distance, label) key, the one with the lowest linear index; sources and unreached voxels have none.
// The dense parent image (solve_options::with_parent) and the diagram update both use lowest_realiser.

#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/problem.hpp>
#include <geovoronoi/result.hpp>

#include <vector>

namespace geovoronoi::detail::search {

/**
 * The lowest-index neighbour u of reached voxel @p v (distance @p dist[v], label @p lab[v]) whose
 * relaxation fl(d(u) + w(u -> v)) with u's label gives v's key; no_index when none does.
 */
template <class P>
index_t lowest_realiser(const P& p, const walker_t<P>& walk, const typename P::value_type* dist,
                        const label_t* lab, index_t v) {
  using T = typename P::value_type;
  using kt = key_traits<T>;
  const label_t l = lab[v];
  const T dv = dist[v];
  const auto target = kt::make(dv, l);
  const T fv = p.field[v];
  index_t best = no_index;
  walk.for_each_neighbour(p, v, [&](int k, index_t u) {
    // a realiser carries v's label and, weights being >= 0, is no farther than v: test that first;
    // neighbours come in increasing index order, so the first realiser is the lowest-index one
    // on an explicit graph neighbours may come in any order: keep the lowest realiser
    if (best != no_index && (implicit_grid_v<P> || node_rank(p, u) > node_rank(p, best))) return;
    if (lab[u] != l || !(dist[u] <= dv)) return;
    const T nd = extend(dist[u], edge_weight(p.metric, p.edges.length[k], p.field[u], fv));
    if (kt::make(nd, l) == target) best = u;
  });
  return best;
}

/// The parents of the nodes of a finished solve from @p sources (@p dist, @p lab: one entry per node
/// of @p p) into @p parent, which holds no_index on entry.
template <class P>
void parents_into(const P& p, const typename P::value_type* dist, const label_t* lab,
                  const std::vector<source<typename P::value_type>>& sources, index_t* parent) {
  const index_t n = node_count(p);
  std::vector<unsigned char> is_source(static_cast<std::size_t>(n), 0);
  for (const auto& s : sources)
    if (dist[s.voxel] == s.distance && lab[s.voxel] == s.label) is_source[s.voxel] = 1;
  const walker_t<P> walk(p);
  for (index_t v = 0; v < n; ++v) {
    if (lab[v] == no_label || is_source[v]) continue;
    parent[v] = lowest_realiser(p, walk, dist, lab, v);
  }
}

/// The parent image of diagram @p d, solved from @p sources.
template <class P>
void compute_parents(const P& p, diagram<typename P::value_type, P::dim>& d,
                     const std::vector<source<typename P::value_type>>& sources) {
  d.parent = image<index_t, P::dim>(p.geometry, no_index);
  parents_into(p, d.distance.data(), d.label.data(), sources, d.parent.data());
}

}  // namespace geovoronoi::detail::search

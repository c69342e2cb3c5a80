#pragma once
// What a count-only insert-query accumulates about a new cell, for Sibson and Laplace: per node the
// voxels stolen from it, the facet faces towards its remaining cell per axis and the least path
// length through them; and the table of face (2 * Dim) neighbours that the facets are made of.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/result.hpp>

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <vector>

namespace geovoronoi::detail::search {

/// Per-node accumulators of one query, cleared in O(touched).
struct accumulators {
  std::vector<std::int64_t> volume;                  // stolen voxels per node
  std::vector<std::array<std::int64_t, 3>> faces;    // facet faces per node and axis
  std::vector<double> h;                             // min path length through the facet (as double of T)
  std::vector<char> seen;
  std::vector<label_t> touched;
  explicit accumulators(std::size_t nodes)
      : volume(nodes, 0), faces(nodes, {0, 0, 0}), h(nodes, 0), seen(nodes, 0) {}
  void touch(label_t k) {
    if (!seen[k]) seen[k] = 1, touched.push_back(k), h[k] = std::numeric_limits<double>::infinity();
  }
  void clear() {
    for (label_t k : touched) volume[k] = 0, faces[k] = {0, 0, 0}, seen[k] = 0;
    touched.clear();
  }
};

/// The 2*Dim face neighbours of a grid: axis, direction, linear delta, the stencil entry with the same
/// offset (its length is the edge length every backend uses) and the face area.
template <int Dim>
struct face {
  int axis;
  int dir;
  index_t delta;
  int edge;
  double area;
};

template <class P>
std::vector<face<P::dim>> faces_of(const P& p) {
  constexpr int Dim = P::dim;
  std::vector<face<Dim>> out;
  index_t stride = 1;
  for (int a = 0; a < Dim; ++a) {
    double area = 1;
    for (int b = 0; b < Dim; ++b)
      if (b != a) area *= p.geometry.spacing(b);
    for (int dir = -1; dir <= 1; dir += 2) {
      int edge = -1;
      for (int n = 0; n < P::neighbours; ++n) {
        bool match = true;
        for (int b = 0; b < 3; ++b) match = match && p.edges.offset[n][b] == (b == a ? dir : 0);
        if (match) edge = n;
      }
      if (edge < 0) throw std::logic_error("geovoronoi::shape_functions: the connectivity lacks a face neighbour");
      out.push_back({a, dir, dir * stride, edge, area});
    }
    stride *= p.geometry.extent(a);
  }
  return out;
}

/// Whether the neighbour of voxel @p v (coordinates @p c) across face @p f lies inside the grid and
/// the edge to it is not cut: a cut face joins no two cells (no path crosses it), so it is neither a
/// Laplace facet nor a Distance Ratio frontier.
template <class P, class C>
bool face_in_grid(const P& p, index_t v, const C& c, const face<P::dim>& f) noexcept {
  const index_t x = c[f.axis] + f.dir;
  if (!(x >= 0 && x < p.geometry.extent(f.axis))) return false;
  if constexpr (P::has_cuts) return !((p.cut_mask(v) >> f.edge) & 1u);
  return true;
}

/// One Laplace facet pair (v in the new cell, w outside it, reached, label @p k) across a face of axis
/// @p axis and stencil edge @p edge: a face for k, and the path length through it
/// h = fl(fl(dq + c(v, w)) + d(w)) (@p fv, @p fw: the field values, @p dw: d(w)). Grids and copy graphs
/// (detail/branching/shape.hpp) count their pairs here.
template <class P>
void add_facet_pair(const P& p, accumulators& acc, label_t k, int axis, int edge, typename P::value_type dq,
                    typename P::value_type fv, typename P::value_type fw, typename P::value_type dw) {
  using T = typename P::value_type;
  acc.touch(k);
  ++acc.faces[k][axis];
  const T h = extend(extend(dq, edge_weight(p.metric, p.edges.length[edge], fv, fw)), dw);
  if (double(h) < acc.h[k]) acc.h[k] = double(h);
}

/**
 * Laplace's facet pairs of cell voxel @p v (query distance @p dq): each face neighbour w in the grid,
 * across an edge that is not cut, in the domain, reached (label k = @p lab[w]) and not in the cell
 * (@p in_cell(w) false) adds a face of its axis to k and offers the path length through the facet
 * h = fl(fl(dq + c(v, w)) + d(w)) (@p dist: the diagram's distances). Returns whether any pair was found.
 */
template <class P, class InCell>
bool add_facets(const P& p, index_t v, typename P::value_type dq, const std::vector<face<P::dim>>& faces,
                const label_t* lab, const typename P::value_type* dist, InCell&& in_cell, accumulators& acc) {
  using T = typename P::value_type;
  const auto c = p.geometry.coords(v);
  const T fv = p.field[v];
  bool any = false;
  for (const auto& f : faces) {
    if (!face_in_grid(p, v, c, f)) continue;
    const index_t w = v + f.delta;
    if (!p.inside(w)) continue;
    const label_t k = lab[w];
    if (k == no_label) continue;
    if (in_cell(w, f)) continue;
    add_facet_pair(p, acc, k, f.axis, f.edge, dq, fv, p.field[w], dist[w]);
    any = true;
  }
  return any;
}

}  // namespace geovoronoi::detail::search

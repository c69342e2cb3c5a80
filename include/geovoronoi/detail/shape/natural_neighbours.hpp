#pragma once
// Sibson and Laplace coordinates from the new cells of query voxels (insert_queries, in batches).
// Per query the scratch is bounded by its cell and the number of nodes: the cell itself (returned by
// the backend, sorted by voxel) and per-node accumulators reset through a touched list.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/voronoi.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace geovoronoi::detail::shape {

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

/// Whether voxel w is in the cell whose sorted voxels are cell[0, size), knowing cell[j] = w - delta.
/// Entries are distinct and sorted, so at most |delta| - 1 of them lie strictly between the two.
inline bool in_sorted_cell(const index_t* cell, std::size_t size, std::size_t j, index_t delta, index_t w) {
  if (delta > 0) {
    const std::size_t hi = std::min(size, j + 1 + std::size_t(delta));
    return std::binary_search(cell + j + 1, cell + hi, w);
  }
  const std::size_t span = std::size_t(-delta);
  const std::size_t lo = j > span ? j - span : 0;
  return std::binary_search(cell + lo, cell + j, w);
}

/**
 * Raw Laplace and Sibson weights of one query from its new cell (voxels sorted, their query
 * distances and owners). Writes candidates (node, raw > 0) to @p out.
 *
 * Sibson: raw_k = (voxels stolen from k) * voxel volume.
 * Laplace: raw_k = s_k / h_k over the facet pairs (v in C_q, w face neighbour of v in the domain, not
 * in C_q, label(w) = k); s_k = sum over axes of (faces of that axis) * face area; h_k = min of
 * (d_q(v) + c(v, w)) + d(w) evaluated in T. If some h_k is 0 (zero-weight edges) those nodes share the
 * weight in proportion to s_k. If the cell has no facet at all, Laplace falls back to Sibson.
 */
template <class P, class D>
void query_weights(const P& p, const D& d, const std::vector<face<P::dim>>& faces, bool laplace,
                   const index_t* cell, const typename P::value_type* dq, const label_t* owner, std::size_t size,
                   accumulators& acc, std::vector<candidate>& out) {
  using T = typename P::value_type;
  out.clear();
  acc.clear();
  for (std::size_t j = 0; j < size; ++j) {
    const label_t o = owner[j];
    if (o < 0) continue;
    acc.touch(o);
    ++acc.volume[o];
  }
  bool any_facet = false;
  if (laplace) {
    const T* dist = d.distance.data();
    const label_t* lab = d.label.data();
    for (std::size_t j = 0; j < size; ++j) {
      const index_t v = cell[j];
      const auto c = p.geometry.coords(v);
      const T fv = p.field[v];
      for (const auto& f : faces) {
        if (!face_in_grid(p, c, f)) continue;
        const index_t w = v + f.delta;
        if (!p.inside(w)) continue;
        const label_t k = lab[w];
        if (k == no_label) continue;
        if (in_sorted_cell(cell, size, j, f.delta, w)) continue;
        acc.touch(k);
        ++acc.faces[k][f.axis];
        any_facet = true;
        const T cvw = p.metric(p.edges.length[f.edge], fv, p.field[w]);
        T h = dq[j] + cvw;
        h = h + dist[w];
        if (double(h) < acc.h[k]) acc.h[k] = double(h);
      }
    }
  }
  if (laplace && any_facet) {
    double area[3] = {0, 0, 0};
    for (const auto& f : faces) area[f.axis] = f.area;
    bool zero_h = false;
    for (label_t k : acc.touched) {
      const auto& n = acc.faces[k];
      if ((n[0] | n[1] | n[2]) != 0 && acc.h[k] == 0) zero_h = true;
    }
    for (label_t k : acc.touched) {
      const auto& n = acc.faces[k];
      double s = 0;
      for (int a = 0; a < P::dim; ++a) s += double(n[a]) * area[a];
      if (!(s > 0)) continue;
      if (zero_h) {
        if (acc.h[k] == 0) out.push_back({k, s});
      } else {
        out.push_back({k, s / acc.h[k]});
      }
    }
  } else {
    const double vv = p.geometry.voxel_volume();
    for (label_t k : acc.touched)
      if (acc.volume[k] > 0) out.push_back({k, double(acc.volume[k]) * vv});
  }
}

template <class Policy, class P, class D, class W, class Options>
void natural_neighbours(const Policy& policy, const P& p, const D& d, const Options& opt, bool laplace, W& w) {
  using T = typename P::value_type;
  const index_t n = p.geometry.size();
  const int k = w.k;
  const auto faces = faces_of(p);
  std::vector<index_t> queries;
  for (index_t v = 0; v < n; ++v) {
    const label_t l = d.label[v];
    if (l == no_label) continue;
    if (d.distance[v] > T(0)) {
      queries.push_back(v);
    } else {  // a node (or a voxel at distance 0 from it): its cell is empty, Kronecker delta
      w.node[std::size_t(v) * k] = l;
      w.weight[std::size_t(v) * k] = T(1);
    }
  }
  accumulators acc(w.nodes);
  std::vector<candidate> cand;
  std::vector<index_t> batch;
  const std::size_t total = queries.size();
  for (std::size_t start = 0; start < total; start += opt.batch_size) {
    const std::size_t end = std::min(total, start + opt.batch_size);
    batch.assign(queries.begin() + std::ptrdiff_t(start), queries.begin() + std::ptrdiff_t(end));
    const auto cells = insert_queries(policy, p, d, batch);
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::size_t b = cells.offsets[i], sz = cells.cell_size(i);
      const index_t q = cells.query[i];
      const std::size_t at = std::size_t(q) * std::size_t(k);
      if (sz == 0) {  // defensive: only a voxel at distance 0 has an empty cell
        w.node[at] = d.label[q];
        w.weight[at] = T(1);
        continue;
      }
      query_weights(p, d, faces, laplace, cells.voxel.data() + b, cells.distance.data() + b,
                    cells.owner.data() + b, sz, acc, cand);
      store(cand, k, w.node.data() + at, w.weight.data() + at);
    }
    report(opt.progress, double(end) / double(total));
  }
  if (total == 0) report(opt.progress, 1.0);
}

}  // namespace geovoronoi::detail::shape

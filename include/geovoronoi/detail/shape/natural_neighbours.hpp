#pragma once
// Sibson and Laplace coordinates from the new cells of query voxels (insert_queries, in batches).
// Per query the scratch is bounded by its cell and the number of nodes: the cell itself (returned by
// the backend, sorted by voxel) and per-node accumulators reset through a touched list.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/host_parallel.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>
#include <geovoronoi/detail/dispatch.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <vector>

namespace geovoronoi::detail::shape {

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
 * Raw Laplace and Sibson weights of one query from its accumulators. Writes candidates (node, raw > 0)
 * to @p out.
 *
 * Sibson: raw_k = (voxels stolen from k) * voxel volume.
 * Laplace: raw_k = s_k / h_k over the facet pairs (v in C_q, w face neighbour of v in the domain, not
 * in C_q, label(w) = k); s_k = sum over axes of (faces of that axis) * face area; h_k = min of
 * (d_q(v) + c(v, w)) + d(w) evaluated in T. If some h_k is 0 (zero-weight edges) those nodes share the
 * weight in proportion to s_k. If the cell has no facet at all, Laplace falls back to Sibson.
 */
template <class P>
void finish_weights(const P& p, const std::vector<face<P::dim>>& faces, bool laplace, bool any_facet,
                    const accumulators& acc, std::vector<candidate>& out) {
  out.clear();
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

/// Fills the accumulators of one query from its new cell as a backend returns it (voxels sorted,
/// their query distances and owners); returns whether the cell has a facet pair.
template <class P, class D>
bool accumulate_cell(const P& p, const D& d, const std::vector<face<P::dim>>& faces, bool laplace,
                     const index_t* cell, const typename P::value_type* dq, const label_t* owner, std::size_t size,
                     accumulators& acc) {
  using T = typename P::value_type;
  acc.clear();
  for (std::size_t j = 0; j < size; ++j) {
    const label_t o = owner[j];
    if (o < 0) continue;
    acc.touch(o);
    ++acc.volume[o];
  }
  bool any_facet = false;
  if (!laplace) return false;
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
  return any_facet;
}

/// Per-worker scratch of the query loops.
template <class T>
struct query_scratch {
  accumulators acc;
  std::vector<candidate> cand;
  std::vector<unsigned char> mask;
  cell_members<T> members;
  explicit query_scratch(std::size_t nodes) : acc(nodes) {}
};

/// Queries per task of the host-parallel loops: enough to amortise a task's scratch, few enough to
/// balance cells of very different sizes.
inline constexpr std::size_t queries_per_task = 64;

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
  const std::size_t total = queries.size();
  auto write = [&](index_t q, query_scratch<T>& s, bool any_facet) {
    finish_weights(p, faces, laplace, any_facet, s.acc, s.cand);
    const std::size_t at = std::size_t(q) * std::size_t(k);
    if (s.cand.empty()) {  // defensive: only a voxel at distance 0 has an empty cell
      w.node[at] = d.label[q];
      w.weight[at] = T(1);
      return;
    }
    store(s.cand, k, w.node.data() + at, w.weight.data() + at);
  };
  // Each task owns its scratch and writes only its queries' slots.
  auto tasks = [](std::size_t count) { return index_t((count + queries_per_task - 1) / queries_per_task); };

  if (translation_invariant(p)) {
    // exact shortcut (translation_invariant.hpp): one backend solve, then every query is a box scan
    const offset_table<P> tab(policy, p);
    for (std::size_t start = 0; start < total; start += opt.batch_size) {
      const std::size_t end = std::min(total, start + opt.batch_size);
      host_parallel_for(policy, tasks(end - start), [&](index_t t) {
        query_scratch<T> s(w.nodes);
        const std::size_t b = start + std::size_t(t) * queries_per_task;
        const std::size_t e = std::min(end, b + queries_per_task);
        for (std::size_t i = b; i < e; ++i) {
          bool any_facet = false;
          accumulate_offset(tab, d, faces, laplace, queries[i], s.acc, s.mask, s.members, any_facet);
          write(queries[i], s, any_facet);
        }
      });
      report(opt.progress, double(end) / double(total));
    }
  } else {
    std::vector<index_t> batch;
    for (std::size_t start = 0; start < total; start += opt.batch_size) {
      const std::size_t end = std::min(total, start + opt.batch_size);
      batch.assign(queries.begin() + std::ptrdiff_t(start), queries.begin() + std::ptrdiff_t(end));
      const auto cells = dispatch::insert_queries(policy, p, d, batch);  // reached voxels: valid queries
      host_parallel_for(policy, tasks(cells.size()), [&](index_t t) {
        query_scratch<T> s(w.nodes);
        const std::size_t b = std::size_t(t) * queries_per_task;
        const std::size_t e = std::min(cells.size(), b + queries_per_task);
        for (std::size_t i = b; i < e; ++i) {
          const std::size_t o = cells.offsets[i];
          const bool any_facet = accumulate_cell(p, d, faces, laplace, cells.voxel.data() + o,
                                                 cells.distance.data() + o, cells.owner.data() + o,
                                                 cells.cell_size(i), s.acc);
          write(cells.query[i], s, any_facet);
        }
      });
      report(opt.progress, double(end) / double(total));
    }
  }
  if (total == 0) report(opt.progress, 1.0);
}

}  // namespace geovoronoi::detail::shape

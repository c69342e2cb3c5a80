#pragma once
// Distance Ratio shape functions (SOFA's method 0), node by node, from two bounded solves per node:
// the node's own distance over its support and the distance to its cell's frontier.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/host_parallel.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>
#include <geovoronoi/detail/dispatch.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

namespace geovoronoi::detail::shape {

/**
 * Raw Distance Ratio weight of node i at a voxel with distance d_p to i and d_b to i's frontier.
 * Inside i's cell: 1/2 (1 + d_b / (d_p + d_b)), 1 at the node. Outside: 1/2 (1 - d_b / (d_p - d_b))
 * clamped at 0, and 0 when d_p <= d_b (SOFA returns 1 for d_p < d_b: a voxel outside the cell is never
 * weighted more than at the frontier here).
 */
inline double distance_ratio_weight(double dp, double db, bool in_cell) noexcept {
  if (dp == 0) return 1;
  if (in_cell) return 0.5 * (1 + db / (dp + db));
  if (dp <= db) return 0;
  const double w = 0.5 * (1 - db / (dp - db));
  return w > 0 ? w : 0;
}

/// Inserts (node, w) into a voxel's K raw slots kept in slot order; a tie goes after the entries
/// already there (they have lower node indices), a full list drops its smallest weight.
inline void insert_slot(label_t* node, double* raw, int k, label_t i, double w) {
  int at = 0;
  while (at < k && node[at] != no_label && raw[at] >= w) ++at;
  if (at == k) return;
  for (int s = k - 1; s > at; --s) node[s] = node[s - 1], raw[s] = raw[s - 1];
  node[at] = i;
  raw[at] = w;
}

/**
 * Distance Ratio rows: for every voxel of the grid (@p voxel_of null, rows = grid size, row r = voxel r)
 * or for the voxels voxel_of[0, rows) (chosen points, repeats allowed), into the K slots of each row of
 * @p out_node / @p out_weight (which start empty: -1 and 0). With chosen points, raw weights are kept
 * only at their voxels, and a node whose support cannot hold any of them (the support is d_i < 2 dmax
 * and d_i >= d, the diagram's distance, everywhere) is skipped: the rows are those of the full
 * computation, bit for bit, since each voxel's slots only ever see its own contributions, in node order.
 */
template <class Policy, class P, class D, class Options>
void distance_ratio_rows(const Policy& policy, const P& p, const D& d, const Options& opt, int k, std::size_t node_count,
                         const index_t* voxel_of, std::size_t rows, label_t* out_node, typename P::value_type* out_weight) {
  using T = typename P::value_type;
  const index_t n = p.geometry.size();
  const label_t nodes = label_t(node_count);
  // compact slots: the voxel itself for the whole grid, else one slot per distinct chosen voxel
  std::vector<std::int64_t> slot_of;
  std::vector<index_t> slot_voxel;
  if (voxel_of) {
    slot_of.assign(std::size_t(n), -1);
    for (std::size_t r = 0; r < rows; ++r)
      if (slot_of[std::size_t(voxel_of[r])] < 0) {
        slot_of[std::size_t(voxel_of[r])] = std::int64_t(slot_voxel.size());
        slot_voxel.push_back(voxel_of[r]);
      }
  }
  const std::size_t slots = voxel_of ? slot_voxel.size() : std::size_t(n);
  auto slot = [&](index_t v) -> std::int64_t { return voxel_of ? slot_of[std::size_t(v)] : std::int64_t(v); };
  std::vector<label_t> point_node;
  std::vector<T> point_weight;
  if (voxel_of) point_node.assign(slots * std::size_t(k), no_label), point_weight.assign(slots * std::size_t(k), T(0));
  label_t* slot_node = voxel_of ? point_node.data() : out_node;
  T* slot_weight = voxel_of ? point_weight.data() : out_weight;
  const auto faces = faces_of(p);
  const T* dist = d.distance.data();
  const label_t* lab = d.label.data();

  // the cells as voxel lists (counting sort by label; each list sorted by voxel)
  std::vector<std::size_t> start(std::size_t(nodes) + 1, 0);
  for (index_t v = 0; v < n; ++v)
    if (lab[v] != no_label) ++start[std::size_t(lab[v]) + 1];
  for (label_t i = 0; i < nodes; ++i) start[std::size_t(i) + 1] += start[std::size_t(i)];
  std::vector<index_t> members(start.back());
  {
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (index_t v = 0; v < n; ++v)
      if (lab[v] != no_label) members[fill[std::size_t(lab[v])]++] = v;
  }

  // on a translation-invariant problem the node's own distance is a table lookup (no search)
  std::optional<offset_table<P>> tab;
  if (translation_invariant(p)) tab.emplace(policy, p);

  std::vector<double> raw(slots * std::size_t(k), 0.0);
  // Nodes are processed in groups: the group's searches run as parallel host tasks when the backend
  // offers them (each task's backend calls then run on its thread), each producing its node's
  // (voxel, raw weight) list; the lists are merged into the slots in node order, so the result does
  // not depend on the grouping or the thread count.
  constexpr label_t group = 8;
  std::vector<std::vector<std::pair<index_t, double>>> contrib(static_cast<std::size_t>(group));
  for (label_t g0 = 0; g0 < nodes; g0 += group) {
    const label_t g1 = std::min<label_t>(nodes, g0 + group);
    host_parallel_for(policy, index_t(g1 - g0), [&](index_t t) {
      const label_t i = g0 + label_t(t);
      auto& out = contrib[std::size_t(t)];
      out.clear();
      std::vector<source<T>> frontier;
      const index_t* cell = members.data() + start[std::size_t(i)];
      const std::size_t cell_size = start[std::size_t(i) + 1] - start[std::size_t(i)];
      // 1. bound: the largest distance over the cell and its face neighbours in other cells
      T dmax = T(0);
      for (std::size_t j = 0; j < cell_size; ++j) {
        const index_t x = cell[j];
        dmax = std::max(dmax, dist[x]);
        const auto c = p.geometry.coords(x);
        for (const auto& f : faces) {
          if (!face_in_grid(p, x, c, f)) continue;
          const index_t y = x + f.delta;
          if (lab[y] != no_label && lab[y] != i) dmax = std::max(dmax, dist[y]);
        }
      }
      const index_t node_voxel = d.seeds[std::size_t(i)];
      if (!(dmax > T(0))) {  // an isolated one-voxel cell: only the node itself
        if (slot(node_voxel) >= 0) out.push_back({node_voxel, 1.0});
        return;
      }
      // 2. the node's own distance over its support d_i < 2 dmax
      const T radius = T(2) * dmax;
      if (voxel_of) {  // chosen points: skip a node whose support holds none of them
        bool any = false;
        for (std::size_t c = 0; c < slots && !any; ++c)
          any = lab[slot_voxel[c]] != no_label && dist[slot_voxel[c]] < radius;
        if (!any) return;
      }
      const auto di = tab ? tab->ball(node_voxel, radius)
                          : dispatch::bounded(policy, p, std::vector<source<T>>{{node_voxel, T(0), 0}}, radius);
      auto di_at = [&](index_t v) -> T {
        const auto it = std::lower_bound(di.voxel.begin(), di.voxel.end(), v);
        return (it != di.voxel.end() && *it == v) ? di.distance[std::size_t(it - di.voxel.begin())]
                                                  : std::numeric_limits<T>::infinity();
      };
      // 3. distance to the frontier: sources on both sides of every face between cell i and a cell j,
      //    at their distance to the point where d_i = d_j along the path i -> x -> y -> j
      for (std::size_t j = 0; j < cell_size; ++j) {
        const index_t x = cell[j];
        const auto c = p.geometry.coords(x);
        for (const auto& f : faces) {
          if (!face_in_grid(p, x, c, f)) continue;
          const index_t y = x + f.delta;
          if (lab[y] == no_label || lab[y] == i) continue;
          const T diy = di_at(y);
          if (!(diy < std::numeric_limits<T>::infinity())) continue;
          const T dby = T(0.5) * (diy - dist[y]);
          const T mid = T(0.5) * (dist[y] + diy);
          const T dbx = std::max(T(0), mid - dist[x]);
          if (dby < dmax) frontier.push_back({y, dby, 0});
          if (dbx < dmax) frontier.push_back({x, dbx, 0});
        }
      }
      std::sort(frontier.begin(), frontier.end(), [](const source<T>& a, const source<T>& b) {
        return a.voxel < b.voxel || (a.voxel == b.voxel && a.distance < b.distance);
      });
      frontier.erase(std::unique(frontier.begin(), frontier.end(),
                                 [](const source<T>& a, const source<T>& b) { return a.voxel == b.voxel; }),
                     frontier.end());
      sparse_solution<T> db;
      // the frontier is valid as built: reached voxels, distinct after the unique above, distances
      // finite and >= +0 (a difference of equal floats is +0, and max(0, x) never gives -0 here)
      if (!frontier.empty()) db = dispatch::bounded(policy, p, frontier, dmax);  // d_B is capped at dmax
      // 4. raw weights over the support, merged with d_B (both sorted by voxel)
      std::size_t b = 0;
      for (std::size_t j = 0; j < di.size(); ++j) {
        const index_t x = di.voxel[j];
        while (b < db.size() && db.voxel[b] < x) ++b;
        const T dbx = (b < db.size() && db.voxel[b] == x) ? db.distance[b] : dmax;
        const double wx = distance_ratio_weight(double(di.distance[j]), double(dbx), lab[x] == i);
        if (wx > 0 && slot(x) >= 0) out.push_back({x, wx});
      }
    });
    for (label_t i = g0; i < g1; ++i) {
      for (const auto& [x, wx] : contrib[std::size_t(i - g0)]) {
        const std::size_t c = std::size_t(slot(x));
        insert_slot(slot_node + c * std::size_t(k), raw.data() + c * std::size_t(k), k, i, wx);
      }
      // progress by work: a node's searches cover its cell and support, so its cell's size stands
      // for its share of the work (not 1 / nodes: cells can differ by orders of magnitude)
      report(opt.progress, start.back() > 0 ? double(start[std::size_t(i) + 1]) / double(start.back())
                                            : double(i + 1) / double(nodes));
    }
  }
  // 5. normalise the kept weights of every reached voxel (every slot)
  std::vector<candidate> cand;
  for (std::size_t c = 0; c < slots; ++c) {
    const index_t v = voxel_of ? slot_voxel[c] : index_t(c);
    const std::size_t at = c * std::size_t(k);
    label_t* node = slot_node;
    T* weight = slot_weight;
    if (lab[v] == no_label) {
      for (int s = 0; s < k; ++s) node[at + s] = no_label;
      continue;
    }
    if (dist[v] == T(0)) {  // a node: Kronecker delta (another node's outside weight is ~0 there anyway)
      for (int s = 0; s < k; ++s) node[at + s] = no_label;
      node[at] = lab[v];
      weight[at] = T(1);
      continue;
    }
    cand.clear();
    for (int s = 0; s < k && node[at + s] != no_label; ++s) cand.push_back({node[at + s], raw[at + s]});
    for (int s = 0; s < k; ++s) node[at + s] = no_label;
    store(cand, k, node + at, weight + at);
  }
  // 6. chosen points: each row copies its voxel's slots
  if (voxel_of)
    for (std::size_t r = 0; r < rows; ++r) {
      const std::size_t c = std::size_t(slot_of[std::size_t(voxel_of[r])]);
      for (int s = 0; s < k; ++s) {
        out_node[r * std::size_t(k) + std::size_t(s)] = slot_node[c * std::size_t(k) + std::size_t(s)];
        out_weight[r * std::size_t(k) + std::size_t(s)] = slot_weight[c * std::size_t(k) + std::size_t(s)];
      }
    }
}

/// Distance Ratio at every voxel of the grid, into @p w.
template <class Policy, class P, class D, class W, class Options>
void distance_ratio(const Policy& policy, const P& p, const D& d, const Options& opt, W& w) {
  distance_ratio_rows(policy, p, d, opt, w.k, w.nodes, static_cast<const index_t*>(nullptr),
                      std::size_t(p.geometry.size()), w.node.data(), w.weight.data());
}

}  // namespace geovoronoi::detail::shape

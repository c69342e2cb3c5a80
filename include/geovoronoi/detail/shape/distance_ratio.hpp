#pragma once
// Distance Ratio shape functions (SOFA's method 0), node by node, from two bounded solves per node:
// the node's own distance over its support and the distance to its cell's frontier.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>
#include <geovoronoi/detail/dispatch.hpp>

#include <algorithm>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
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

/// One node's searches as Distance Ratio ran them: its bound d_max, its own distance d_i over its
/// support (d_i < 2 d_max) and its frontier distance d_B (< d_max), each sorted by voxel. An
/// isolated one-voxel cell (d_max = 0) holds only its voxel, at distance 0, and no frontier.
/// The lists are shared between the states of successive updates where they did not change.
template <class T>
struct dr_node {
  using voxels = std::shared_ptr<const std::vector<index_t>>;
  using values = std::shared_ptr<const std::vector<T>>;
  T dmax = T(0);
  voxels support;
  values di;
  voxels frontier;
  values db;
};

/// A list moved into a shared, immutable one.
template <class V>
std::shared_ptr<const V> share(V&& v) {
  return std::make_shared<const V>(std::forward<V>(v));
}

/// The node of an isolated one-voxel cell.
template <class T>
dr_node<T> isolated_node(T dmax, index_t node_voxel) {
  return dr_node<T>{dmax, share(std::vector<index_t>{node_voxel}), share(std::vector<T>{T(0)}),
                    share(std::vector<index_t>{}), share(std::vector<T>{})};
}

/// What shape_options::keep_update_state keeps in the weights (shape_weights::update_state): every
/// node's searches, so that update_shape_functions() repairs them instead of running them again.
template <class T>
struct distance_ratio_state {
  std::vector<index_t> seeds;
  std::vector<dr_node<T>> nodes;
};

/// The value at @p v of a sorted (voxel, value) list, or +inf.
template <class T>
T sorted_at(const std::vector<index_t>& voxel, const std::vector<T>& value, index_t v) noexcept {
  const auto it = std::lower_bound(voxel.begin(), voxel.end(), v);
  return (it != voxel.end() && *it == v) ? value[std::size_t(it - voxel.begin())] : std::numeric_limits<T>::infinity();
}

/// The cells as voxel lists (counting sort by label; each list sorted by voxel): cell i is
/// members[start[i], start[i + 1]).
struct cell_lists {
  std::vector<std::size_t> start;
  std::vector<index_t> members;
};
inline cell_lists cells_of(const label_t* lab, index_t n, label_t nodes) {
  cell_lists c;
  c.start.assign(std::size_t(nodes) + 1, 0);
  for (index_t v = 0; v < n; ++v)
    if (lab[v] != no_label) ++c.start[std::size_t(lab[v]) + 1];
  for (label_t i = 0; i < nodes; ++i) c.start[std::size_t(i) + 1] += c.start[std::size_t(i)];
  c.members.resize(c.start.back());
  std::vector<std::size_t> fill(c.start.begin(), c.start.end() - 1);
  for (index_t v = 0; v < n; ++v)
    if (lab[v] != no_label) c.members[fill[std::size_t(lab[v])]++] = v;
  return c;
}

/// Node i's bound d_max: the largest distance over its cell and the cell's face neighbours in other cells.
template <class P, class T>
T node_bound(const P& p, const std::vector<face<P::dim>>& faces, const T* dist, const label_t* lab, label_t i,
             const index_t* cell, std::size_t cell_size) {
  T dmax = T(0);
  for (std::size_t j = 0; j < cell_size; ++j) {
    const index_t x = cell[j];
    dmax = std::max(dmax, dist[x]);
    const auto c = p.geometry.coords(x);
    std::uint64_t cut = 0;  // (face_in_grid, with the voxel's cut bits read once)
    if constexpr (P::has_cuts) cut = std::uint64_t(p.cut_mask(x));
    for (const auto& f : faces) {
      const index_t to = c[f.axis] + f.dir;
      if (!(to >= 0 && to < p.geometry.extent(f.axis)) || ((cut >> f.edge) & 1u)) continue;
      const index_t y = x + f.delta;
      if (lab[y] != no_label && lab[y] != i) dmax = std::max(dmax, dist[y]);
    }
  }
  return dmax;
}

/// The frontier source values of a face from x (in cell i) to y (in another cell j), from d_i(y)
/// (@p diy) and the diagram's distances: y's, at its distance to the point where d_i = d_j on the
/// path i -> x -> y -> j, and x's, at the distance from x to that point (never -0).
template <class T>
T frontier_value_at_y(T diy, T dist_y) noexcept {
  return T(0.5) * (diy - dist_y);
}
template <class T>
T frontier_value_at_x(T diy, T dist_y, T dist_x) noexcept {
  const T mid = T(0.5) * (dist_y + diy);
  return std::max(T(0), mid - dist_x);
}

/// Node i's raw weight at a voxel of its support, from d_i there (@p di), d_B there (@p db, +inf where
/// the frontier search did not reach: d_max is used) and whether the voxel lies in cell i.
template <class T>
double node_weight(const dr_node<T>& s, T di, T db, bool in_cell) noexcept {
  return distance_ratio_weight(double(di), double(db < std::numeric_limits<T>::infinity() ? db : s.dmax), in_cell);
}

/// The frontier sources of one face from x (in cell i, distance @p dist_x) to y (in another cell,
/// @p dist_y), with @p diy = d_i(y) (+inf outside i's support: no source), those below @p dmax.
template <class T>
void add_frontier_face(std::vector<source<T>>& frontier, index_t x, index_t y, T diy, T dist_x, T dist_y, T dmax) {
  if (!(diy < std::numeric_limits<T>::infinity())) return;
  const T dby = frontier_value_at_y(diy, dist_y);
  const T dbx = frontier_value_at_x(diy, dist_y, dist_x);
  if (dby < dmax) frontier.push_back({y, dby, 0});
  if (dbx < dmax) frontier.push_back({x, dbx, 0});
}

/// Frontier sources sorted by voxel, one per voxel (its least).
template <class T>
void sort_frontier(std::vector<source<T>>& frontier) {
  std::sort(frontier.begin(), frontier.end(), [](const source<T>& a, const source<T>& b) {
    return a.voxel < b.voxel || (a.voxel == b.voxel && a.distance < b.distance);
  });
  frontier.erase(std::unique(frontier.begin(), frontier.end(),
                             [](const source<T>& a, const source<T>& b) { return a.voxel == b.voxel; }),
                 frontier.end());
}

/**
 * The sources of node i's frontier search: on both sides of every face between cell i and a cell j,
 * at their distance to the point where d_i = d_j along the path i -> x -> y -> j, below d_max; one per
 * voxel (its least), sorted by voxel. @p di_at(v) is node i's own distance at v (+inf outside its support).
 */
template <class P, class T, class DiAt>
std::vector<source<T>> frontier_sources(const P& p, const std::vector<face<P::dim>>& faces, const T* dist,
                                        const label_t* lab, label_t i, const index_t* cell, std::size_t cell_size,
                                        T dmax, DiAt&& di_at) {
  std::vector<source<T>> frontier;
  for (std::size_t j = 0; j < cell_size; ++j) {
    const index_t x = cell[j];
    const auto c = p.geometry.coords(x);
    for (const auto& f : faces) {
      if (!face_in_grid(p, x, c, f)) continue;
      const index_t y = x + f.delta;
      if (lab[y] == no_label || lab[y] == i) continue;
      add_frontier_face(frontier, x, y, di_at(y), dist[x], dist[y], dmax);
    }
  }
  sort_frontier(frontier);
  return frontier;
}

/**
 * Node i's two searches (steps 2 and 3 of distance_ratio_rows), given its bound @p dmax > 0: its own
 * distance over its support d_i < 2 d_max (from the offset table @p tab when there is one) and the
 * frontier distance d_B, capped at d_max.
 */
template <class Policy, class P, class Tab>
dr_node<typename P::value_type> node_searches(const Policy& policy, const P& p, const std::vector<face<P::dim>>& faces,
                                              const typename P::value_type* dist, const label_t* lab, label_t i,
                                              index_t node_voxel, const index_t* cell, std::size_t cell_size,
                                              typename P::value_type dmax, const Tab* tab) {
  using T = typename P::value_type;
  dr_node<T> s;
  s.dmax = dmax;
  const T radius = T(2) * dmax;
  auto di = tab ? tab->ball(node_voxel, radius)
                : dispatch::bounded(policy, p, std::vector<source<T>>{{node_voxel, T(0), 0}}, radius);
  s.support = share(std::move(di.voxel));
  s.di = share(std::move(di.distance));
  const auto frontier = frontier_sources(p, faces, dist, lab, i, cell, cell_size, dmax,
                                         [&](index_t v) { return sorted_at(*s.support, *s.di, v); });
  // the frontier is valid as built: reached voxels, distinct after the unique above, distances
  // finite and >= +0 (a difference of equal floats is +0, and max(0, x) never gives -0 here)
  sparse_solution<T> db;
  if (!frontier.empty()) db = dispatch::bounded(policy, p, frontier, dmax);  // d_B is capped at dmax
  s.frontier = share(std::move(db.voxel));
  s.db = share(std::move(db.distance));
  return s;
}

/// Node i's raw weights over its support, merged with d_B (both sorted by voxel): f(x, w) for each w > 0.
template <class T, class F>
void node_raw_weights(const dr_node<T>& s, const label_t* lab, label_t i, F&& f) {
  const auto &support = *s.support, &frontier = *s.frontier;
  const auto &di = *s.di, &db = *s.db;
  std::size_t b = 0;
  for (std::size_t j = 0; j < support.size(); ++j) {
    const index_t x = support[j];
    while (b < frontier.size() && frontier[b] < x) ++b;
    const T dbx = (b < frontier.size() && frontier[b] == x) ? db[b] : std::numeric_limits<T>::infinity();
    const double wx = node_weight(s, di[j], dbx, lab[x] == i);
    if (wx > 0) f(x, wx);
  }
}

/// Step 5 for one voxel: its K slots (nodes, with raw weights in @p raw) normalised in place; a node's
/// voxel gets the Kronecker delta, a voxel outside every cell empty slots.
template <class T>
void finish_row(label_t lv, T dv, int k, label_t* node, T* weight, const double* raw, std::vector<candidate>& cand) {
  if (lv == no_label) {
    for (int s = 0; s < k; ++s) node[s] = no_label;
    return;
  }
  if (dv == T(0)) {  // a node: Kronecker delta (another node's outside weight is ~0 there anyway)
    for (int s = 0; s < k; ++s) node[s] = no_label;
    node[0] = lv;
    weight[0] = T(1);
    return;
  }
  cand.clear();
  for (int s = 0; s < k && node[s] != no_label; ++s) cand.push_back({node[s], raw[s]});
  for (int s = 0; s < k; ++s) node[s] = no_label;
  store(cand, k, node, weight);
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
                         const index_t* voxel_of, std::size_t rows, label_t* out_node, typename P::value_type* out_weight,
                         distance_ratio_state<typename P::value_type>* keep = nullptr) {
  using T = typename P::value_type;
  const index_t n = p.geometry.size();
  const label_t nodes = label_t(node_count);
  if (keep && voxel_of) throw std::logic_error("geovoronoi: Distance Ratio keeps its searches only on the whole grid");
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
  const cell_lists cells = cells_of(lab, n, nodes);
  const auto& start = cells.start;
  if (keep) {
    keep->seeds = d.seeds;
    keep->nodes.assign(std::size_t(nodes), dr_node<T>{});
  }

  // on a translation-invariant problem the node's own distance is a table lookup (no search)
  std::optional<offset_table<P>> tab;
  if (translation_invariant(p)) tab.emplace(policy, p);

  // 1. every node's bound d_max (the largest distance over its cell and its face neighbours in other
  // cells), and with it the progress bar's measure of each node's work: the voxels with d < 2 d_max,
  // which hold its support (d_i >= d). Cell sizes would not do: a support can span the whole domain
  // around a small cell (a soft region between stiff ones).
  std::vector<T> bound(std::size_t(nodes), T(0));
  host_parallel_for(policy, index_t(nodes), [&](index_t t) {
    const std::size_t i = std::size_t(t);
    bound[i] = node_bound(p, faces, dist, lab, label_t(t), cells.members.data() + start[i], start[i + 1] - start[i]);
  });
  std::vector<double> work(std::size_t(nodes), 1.0);  // (+1: an isolated node still counts)
  if (opt.progress) {
    std::vector<std::pair<T, label_t>> radius(static_cast<std::size_t>(nodes));
    for (label_t i = 0; i < nodes; ++i) radius[std::size_t(i)] = {T(2) * bound[std::size_t(i)], i};
    std::sort(radius.begin(), radius.end());
    std::vector<double> below(std::size_t(nodes) + 1, 0.0);  // voxels with d in [r_(j-1), r_j)
    for (const label_t* l = lab; l != lab + n; ++l) {
      if (*l == no_label) continue;
      const T dv = dist[l - lab];
      const auto at = std::upper_bound(radius.begin(), radius.end(), dv,
                                       [](T x, const std::pair<T, label_t>& r) { return x < r.first; });
      below[std::size_t(at - radius.begin())] += 1.0;
    }
    double cum = 0.0;
    for (std::size_t j = 0; j < radius.size(); ++j) {
      cum += below[j];
      work[std::size_t(radius[j].second)] += cum;
    }
  }
  double work_total = 0.0, work_done = 0.0;
  for (const double w : work) work_total += w;

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
      const index_t* cell = cells.members.data() + start[std::size_t(i)];
      const std::size_t cell_size = start[std::size_t(i) + 1] - start[std::size_t(i)];
      const T dmax = bound[std::size_t(i)];
      const index_t node_voxel = d.seeds[std::size_t(i)];
      if (!(dmax > T(0))) {  // an isolated one-voxel cell: only the node itself
        if (slot(node_voxel) >= 0) out.push_back({node_voxel, 1.0});
        if (keep) keep->nodes[std::size_t(i)] = isolated_node(dmax, node_voxel);
        return;
      }
      if (voxel_of) {  // chosen points: skip a node whose support (d_i < 2 dmax) holds none of them
        const T radius = T(2) * dmax;
        bool any = false;
        for (std::size_t c = 0; c < slots && !any; ++c)
          any = lab[slot_voxel[c]] != no_label && dist[slot_voxel[c]] < radius;
        if (!any) return;
      }
      // 2.-3. the node's own distance over its support, the frontier distance
      auto s = node_searches(policy, p, faces, dist, lab, i, node_voxel, cell, cell_size, dmax, tab ? &*tab : nullptr);
      // 4. raw weights over the support
      node_raw_weights(s, lab, i, [&](index_t x, double wx) {
        if (slot(x) >= 0) out.push_back({x, wx});
      });
      if (keep) keep->nodes[std::size_t(i)] = std::move(s);
    });
    // merge the group's lists into the slots in node order. On the whole grid each list is sorted by
    // voxel (= slot), so the slots are split into ranges merged in parallel, every range taking the
    // nodes in order: each slot sees the same insertions in the same order as a serial merge.
    auto merge = [&](label_t i, const std::pair<index_t, double>* b, const std::pair<index_t, double>* e) {
      for (; b != e; ++b) {
        const std::size_t c = std::size_t(slot(b->first));
        insert_slot(slot_node + c * std::size_t(k), raw.data() + c * std::size_t(k), k, i, b->second);
      }
    };
    if (voxel_of) {
      for (label_t i = g0; i < g1; ++i) {
        const auto& l = contrib[std::size_t(i - g0)];
        merge(i, l.data(), l.data() + l.size());
      }
    } else {
      const index_t ranges = index_t(4 * host_threads(policy));
      host_parallel_for(policy, ranges, [&](index_t r) {
        const index_t lo = index_t(std::size_t(n) * std::size_t(r) / std::size_t(ranges));
        const index_t hi = index_t(std::size_t(n) * std::size_t(r + 1) / std::size_t(ranges));
        auto before = [](const std::pair<index_t, double>& a, index_t v) { return a.first < v; };
        for (label_t i = g0; i < g1; ++i) {
          const auto& l = contrib[std::size_t(i - g0)];
          merge(i, std::lower_bound(l.data(), l.data() + l.size(), lo, before),
                std::lower_bound(l.data(), l.data() + l.size(), hi, before));
        }
      });
    }
    // progress by work: a node's searches cover its support, measured up front (step 1)
    // (one report per node, as each may be the point where a caller cancels)
    for (label_t i = g0; i < g1; ++i) {
      work_done += work[std::size_t(i)];
      report(opt.progress, std::min(1.0, work_done / work_total));
    }
  }
  // 5. normalise the kept weights of every reached voxel (every slot; each on its own, in parallel)
  const index_t ranges = index_t(4 * host_threads(policy));
  host_parallel_for(policy, ranges, [&](index_t r) {
    std::vector<candidate> cand;
    const std::size_t lo = slots * std::size_t(r) / std::size_t(ranges), hi = slots * std::size_t(r + 1) / std::size_t(ranges);
    for (std::size_t c = lo; c < hi; ++c) {
      const index_t v = voxel_of ? slot_voxel[c] : index_t(c);
      const std::size_t at = c * std::size_t(k);
      finish_row(lab[v], dist[v], k, slot_node + at, slot_weight + at, raw.data() + at, cand);
    }
  });
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
  std::shared_ptr<distance_ratio_state<typename P::value_type>> keep;
  if (opt.keep_update_state) keep = std::make_shared<distance_ratio_state<typename P::value_type>>();
  distance_ratio_rows(policy, p, d, opt, w.k, w.nodes, static_cast<const index_t*>(nullptr),
                      std::size_t(p.geometry.size()), w.node.data(), w.weight.data(), keep.get());
  w.update_state = std::move(keep);
}

}  // namespace geovoronoi::detail::shape

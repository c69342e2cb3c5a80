#pragma once
// Distance Ratio after a change, from the nodes' searches kept with the weights
// (shape_options::keep_update_state): each node's own distance d_i and frontier distance d_B are
// repaired around the change, as update() repairs the diagram, and only the rows where some node's
// raw weight changed are recomputed. Why the result is the full computation's, bit for bit, is in
// docs/shape-functions.md ("After a change"); the comments below name the steps.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/distance_ratio.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/shape/translation_invariant.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/change.hpp>
#include <geovoronoi/detail/update/node_list.hpp>

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <queue>
#include <utility>
#include <vector>

namespace geovoronoi::detail::shape {

/// Calls f(k, u) for every stencil neighbour u of @p v inside the grid, cut or not.
template <class P, class F>
void for_each_grid_neighbour(const P& p, index_t v, F&& f) {
  const auto c = p.geometry.coords(v);
  for (int k = 0; k < P::neighbours; ++k) {
    bool in = true;
    for (int a = 0; a < P::dim; ++a) {
      const index_t x = c[std::size_t(a)] + p.edges.offset[k][a];
      in = in && x >= 0 && x < p.geometry.extent(a);
    }
    if (in) f(k, v + p.edges.delta[k]);
  }
}

/**
 * One search's distances (a sorted (voxel, value) list; +inf elsewhere) scattered into a dense array
 * for the repair, which reads them at random: one pass over the list in and one out, cheaper than a
 * search of the list per read. @p dense holds +inf everywhere between uses.
 */
template <class T>
class dense_distances {
 public:
  dense_distances(std::vector<T>& dense, const std::vector<index_t>& voxel, const std::vector<T>& value)
      : dense_(dense), voxel_(voxel) {
    for (std::size_t j = 0; j < voxel.size(); ++j) dense_[std::size_t(voxel[j])] = value[j];
  }
  dense_distances(const dense_distances&) = delete;
  dense_distances& operator=(const dense_distances&) = delete;
  ~dense_distances() {
    for (const index_t v : voxel_) dense_[std::size_t(v)] = std::numeric_limits<T>::infinity();
    for (const index_t v : written_) dense_[std::size_t(v)] = std::numeric_limits<T>::infinity();
  }
  T operator()(index_t v) const noexcept { return dense_[std::size_t(v)]; }
  void set(index_t v, T x) {
    dense_[std::size_t(v)] = x;
    written_.push_back(v);
  }

 private:
  std::vector<T>& dense_;
  const std::vector<index_t>& voxel_;
  std::vector<index_t> written_;
};

/**
 * Repairs the distances @p D (read and written through D(v) and D.set(v, d); +inf where not reached;
 * every finite value below @p radius) of a bounded search of the problem before a change into those
 * of the same search on @p after, whose sources are @p src(v) (+inf where v is no source). @p seeds
 * holds the voxels at a changed edge (both ends of a new cut edge) or field (@p xf: a carved, added or
 * restiffened voxel) and the voxels whose source value changed; @p whole is @p after without its cuts.
 *
 * A value that has a realising chain (each step fl(D(u) + w(u, v)) == D(v)) from an unchanged source
 * avoiding the seeds keeps its value: the chain exists after the change with the same sums, and no
 * value rises. So R, the seeds and every voxel some realising chain reaches from them (over an edge
 * that is not cut now, whose weight is then the old one; from a voxel of @p xf over every edge to a
 * neighbour at a distance not below its own, since those weights changed), is reset and re-solved
 * from its border; a Dijkstra that may lower any value spreads the decreases.
 * The result is a solution of the new search's equations whose every finite value is the sum of a
 * path: the least one, which the full search computes. @p touched receives every voxel whose value
 * may have changed, @p old_value its value before (same order).
 */
template <class P, class W, class Dist, class SrcAt>
void repair_distances(const P& after, const W& whole, const stencil_walker<P::dim>& walk, Dist& D,
                      typename P::value_type radius, const voxel_bits& xf, const std::vector<index_t>& seeds,
                      SrcAt&& src, std::vector<index_t>& touched, std::vector<typename P::value_type>& old_value) {
  using T = typename P::value_type;
  const T inf = std::numeric_limits<T>::infinity();
  const T* field = after.field;
  voxel_bits in_r(after.geometry.size());
  touched.clear();
  old_value.clear();
  for (const index_t v : seeds)
    if (in_r.insert(v)) touched.push_back(v);
  // R: the seeds and what realising chains reach from them
  for (std::size_t i = 0; i < touched.size(); ++i) {
    const index_t u = touched[i];
    const T du = D(u);
    if (!(du < inf)) continue;
    if (xf.test(u)) {
      walk.for_each_neighbour(whole, u, [&](int, index_t v) {
        if (in_r.test(v)) return;
        const T dv = D(v);
        if (dv < inf && !(dv < du) && in_r.insert(v)) touched.push_back(v);
      });
    } else {
      const T fu = field[u];
      walk.for_each_neighbour(after, u, [&](int k, index_t v) {
        if (in_r.test(v)) return;
        const T dv = D(v);
        if (!(dv < inf)) return;
        const T sum = extend(du, edge_weight(after.metric, after.edges.length[k], fu, field[v]));
        if (sum == dv && in_r.insert(v)) touched.push_back(v);
      });
    }
  }
  const std::size_t region = touched.size();
  old_value.reserve(region);
  for (const index_t v : touched) old_value.push_back(D(v)), D.set(v, inf);
  // its start values: the new source value, or the least offer of a neighbour outside R
  using item = std::pair<T, index_t>;
  std::priority_queue<item, std::vector<item>, std::greater<item>> heap;
  for (std::size_t i = 0; i < region; ++i) {
    const index_t v = touched[i];
    if (!after.inside(v)) continue;
    T best = src(v);
    const T fv = field[v];
    walk.for_each_neighbour(after, v, [&](int k, index_t u) {
      if (in_r.test(u)) return;
      const T du = D(u);
      if (!(du < inf)) return;
      const T nd = extend(du, edge_weight(after.metric, after.edges.length[k], field[u], fv));
      if (nd < best) best = nd;
    });
    if (best < radius) {
      D.set(v, best);
      heap.push({best, v});
    }
  }
  // Dijkstra from them, lowering any value (the engine's relaxation: mask, weight check, bound)
  while (!heap.empty()) {
    // (no structured binding: C++17 cannot capture one in the lambda below)
    const T dv = heap.top().first;
    const index_t v = heap.top().second;
    heap.pop();
    if (dv != D(v)) continue;  // stale
    const T fv = field[v];
    walk.for_each_neighbour(after, v, [&](int k, index_t u) {
      const T fu = field[u];
      if (!detail::inside<typename P::metric_type>(fu)) return;
      const T nd = relax(after.metric, after.edges.length[k], dv, fv, fu);
      if (!(nd < radius)) return;
      const T du = D(u);
      if (!(nd < du)) return;
      if (in_r.insert(u)) touched.push_back(u), old_value.push_back(du);
      D.set(u, nd);
      heap.push({nd, u});
    });
  }
}

/// The sorted (voxel, value) lists @p voxel / @p value after the values of @p touched changed to
/// @p now(v) (+inf: left out), shared with the lists before where they did not change; @p moved
/// receives the voxels whose value changed (bits, or presence), sorted.
template <class T, class Now>
void merge_repaired(typename dr_node<T>::voxels& voxel, typename dr_node<T>::values& value, Now&& now,
                    const std::vector<index_t>& touched, const std::vector<T>& old_value, std::vector<index_t>& moved) {
  const T inf = std::numeric_limits<T>::infinity();
  moved.clear();
  bool presence = false;  // a voxel enters or leaves the list
  for (std::size_t i = 0; i < touched.size(); ++i) {
    const T was = old_value[i], is = now(touched[i]);
    if (same_bits(was, is)) continue;
    moved.push_back(touched[i]);
    presence = presence || !(was < inf) || !(is < inf);
  }
  if (moved.empty()) return;
  std::sort(moved.begin(), moved.end());
  const auto& vx = *voxel;
  const auto& val = *value;
  if (!presence) {  // the same voxels: new values in place of a copy
    std::vector<T> nval(val);
    for (const index_t v : moved) nval[std::size_t(std::lower_bound(vx.begin(), vx.end(), v) - vx.begin())] = now(v);
    value = share(std::move(nval));
    return;
  }
  std::vector<index_t> nv;
  std::vector<T> nval;
  nv.reserve(vx.size() + moved.size());
  nval.reserve(vx.size() + moved.size());
  std::size_t a = 0, b = 0;
  while (a < vx.size() || b < moved.size()) {
    if (b == moved.size() || (a < vx.size() && vx[a] < moved[b])) {
      nv.push_back(vx[a]), nval.push_back(val[a]);
      ++a;
      continue;
    }
    const index_t v = moved[b++];
    if (a < vx.size() && vx[a] == v) ++a;
    const T is = now(v);
    if (is < inf) nv.push_back(v), nval.push_back(is);
  }
  voxel = share(std::move(nv));
  value = share(std::move(nval));
}

/**
 * The source node i's frontier search gets at voxel @p v: the least of the values frontier_sources()
 * builds at v over v's faces (as the x of a face into another cell, or as its y), +inf if none is
 * below d_max. The same expressions, so the same bits.
 */
template <class P, class T, class DiAt>
T frontier_source_at(const P& p, const std::vector<face<P::dim>>& faces, const T* dist, const label_t* lab, label_t i,
                     index_t v, T dmax, DiAt&& di_at) {
  T best = std::numeric_limits<T>::infinity();
  const label_t lv = lab[v];
  if (lv == no_label) return best;
  const auto c = p.geometry.coords(v);
  for (const auto& f : faces) {
    if (!face_in_grid(p, v, c, f)) continue;  // cuts are symmetric: the face from the other side too
    const index_t w = v + f.delta;
    const label_t lw = lab[w];
    if (lw == no_label) continue;
    if (lv == i && lw != i) {  // v is the x of the face, w its y
      const T diy = di_at(w);
      if (!(diy < std::numeric_limits<T>::infinity())) continue;
      const T dbx = frontier_value_at_x(diy, dist[w], dist[v]);
      if (dbx < dmax && dbx < best) best = dbx;
    } else if (lv != i && lw == i) {  // v is the y of a face from cell i
      const T diy = di_at(v);
      if (!(diy < std::numeric_limits<T>::infinity())) continue;
      const T dby = frontier_value_at_y(diy, dist[v]);
      if (dby < dmax && dby < best) best = dby;
    }
  }
  return best;
}

/**
 * Distance Ratio rows after a change, from the kept searches @p old of the problem before (every old
 * node keeps its label; a node appended after them or moved to another voxel runs its searches from
 * scratch, and its rows are recomputed anywhere in its supports, old and new). Every node's d_max is
 * computed on the diagram after; a node whose d_max changed runs its searches again, any other
 * repairs them: d_i from the voxels of X (its source, the node, is the same), then d_B from X and the
 * voxels whose frontier source changed (the frontier sources, built before and after from the cells,
 * the diagram's distances and d_i). A row can change only at X or where some node's d_i or d_B
 * changed (a node run again: anywhere in its old or new support): those rows are recomputed from the
 * new searches, node by node in node order, as distance_ratio_rows does.
 * Returns the new searches; @p node / @p weight are the whole grid's rows, updated in place.
 */
template <class Policy, class P, class D, class Stats>
std::shared_ptr<const distance_ratio_state<typename P::value_type>> distance_ratio_update(
    const Policy& policy, const P& after, const D& before, const D& d_after, const std::vector<index_t>& xs,
    const voxel_bits& xf, const std::vector<index_t>& xes,
    const distance_ratio_state<typename P::value_type>& old, int k,
    std::vector<label_t>& node, std::vector<typename P::value_type>& weight, Stats& stats) {
  using T = typename P::value_type;
  const T inf = std::numeric_limits<T>::infinity();
  const index_t n = after.geometry.size();
  const label_t nodes = label_t(d_after.seeds.size());
  const label_t old_count = label_t(old.nodes.size());
  const auto faces = faces_of(after);
  const stencil_walker<P::dim> walk(after);
  const cell_lists ca = cells_of(d_after.label.data(), n, nodes);
  auto cell = [](const cell_lists& c, label_t i) { return c.members.data() + c.start[std::size_t(i)]; };
  auto cell_size = [](const cell_lists& c, label_t i) {
    return c.start[std::size_t(i) + 1] - c.start[std::size_t(i)];
  };
  auto state = std::make_shared<distance_ratio_state<T>>();
  state->seeds = d_after.seeds;
  state->nodes.resize(std::size_t(nodes));
  const auto whole = without_cuts(after);
  // appended and moved nodes: their searches from scratch
  std::vector<char> fresh(std::size_t(nodes), 1);
  for (label_t i = 0; i < old_count; ++i)
    fresh[std::size_t(i)] = d_after.seeds[std::size_t(i)] != old.seeds[std::size_t(i)];
  // d_max reads a cell and its face neighbours: it can change only for fresh nodes and for the cells,
  // before or after, of the voxels of X and their face neighbours (a face that was cut has both ends in X)
  std::vector<char> bound_may_change = fresh;
  for (const index_t v : xs) {
    auto mark = [&](index_t y) {
      if (before.label[y] != no_label) bound_may_change[std::size_t(before.label[y])] = 1;
      if (d_after.label[y] != no_label) bound_may_change[std::size_t(d_after.label[y])] = 1;
    };
    mark(v);
    const auto c = after.geometry.coords(v);
    for (const auto& f : faces) {
      const index_t y = c[std::size_t(f.axis)] + f.dir;
      if (y >= 0 && y < after.geometry.extent(f.axis)) mark(v + f.delta);
    }
  }
  std::optional<offset_table<P>> tab;
  if (std::find(bound_may_change.begin(), bound_may_change.end(), char(1)) != bound_may_change.end() &&
      translation_invariant(after))
    tab.emplace(policy, after);
  // every node on its own (parallel host tasks where the backend has them): its new searches, and the
  // voxels where its contribution can have changed
  std::vector<std::vector<index_t>> node_rows(static_cast<std::size_t>(nodes));
  // dense scratch for the repairs, +inf between uses: one pair per concurrent task, reused
  using scratch = std::pair<std::vector<T>, std::vector<T>>;
  std::mutex pool_mutex;
  std::vector<std::unique_ptr<scratch>> pool;
  host_parallel_for(policy, index_t(nodes), [&](index_t t) {
    const label_t i = label_t(t);
    auto& s = state->nodes[std::size_t(i)];
    auto& rows = node_rows[std::size_t(i)];
    // an appended node has no searches before; a moved one (fresh) runs them again like a new one
    const dr_node<T>* prev = i < old_count ? &old.nodes[std::size_t(i)] : nullptr;
    const bool is_fresh = fresh[std::size_t(i)] != 0;  // fresh nodes have bound_may_change set
    const T dmax = bound_may_change[std::size_t(i)] ? node_bound(after, faces, d_after.distance.data(),
                                                                 d_after.label.data(), i, cell(ca, i), cell_size(ca, i))
                                                    : prev->dmax;
    const index_t node_voxel = d_after.seeds[std::size_t(i)];
    if (!is_fresh && same_bits(dmax, prev->dmax) && !(dmax > T(0))) {  // still an isolated one-voxel cell
      s = *prev;
      return;
    }
    if (is_fresh || !same_bits(dmax, prev->dmax)) {
      // a fresh node, or the bound changed: the searches run again; its rows change anywhere in either support
      if (prev) rows.assign(prev->support->begin(), prev->support->end());
      s = dmax > T(0) ? node_searches(policy, after, faces, d_after.distance.data(), d_after.label.data(), i, node_voxel,
                                      cell(ca, i), cell_size(ca, i), dmax, tab ? &*tab : nullptr)
                      : isolated_node(dmax, node_voxel);
      rows.insert(rows.end(), s.support->begin(), s.support->end());
      return;
    }
    const auto& o = *prev;
    std::unique_ptr<scratch> mine;
    {
      const std::lock_guard<std::mutex> hold(pool_mutex);
      if (!pool.empty()) mine = std::move(pool.back()), pool.pop_back();
    }
    if (!mine) mine = std::make_unique<scratch>(std::vector<T>(std::size_t(n), inf), std::vector<T>(std::size_t(n), inf));
    struct give_back {  // returns the scratch (reset by the repairs' views) when the task ends
      std::unique_ptr<scratch>& mine;
      std::vector<std::unique_ptr<scratch>>& pool;
      std::mutex& m;
      ~give_back() {
        const std::lock_guard<std::mutex> hold(m);
        pool.push_back(std::move(mine));
      }
    } returned{mine, pool, pool_mutex};
    std::vector<T>& dense_i = mine->first;
    std::vector<T>& dense_b = mine->second;
    std::vector<index_t> touched, seeds, moved;
    std::vector<T> old_value;
    // d_i: repaired from XE (its source, the node, is the same; it does not read the diagram)
    dense_distances<T> di(dense_i, *o.support, *o.di);
    repair_distances(after, whole, walk, di, T(2) * dmax, xf, xes,
                     [&](index_t v) { return v == node_voxel ? T(0) : inf; }, touched, old_value);
    s = o;
    merge_repaired(s.support, s.di, di, touched, old_value, moved);
    rows.insert(rows.end(), moved.begin(), moved.end());
    // d_B: a frontier source at v reads the diagram and d_i at v and its face neighbours, and the faces'
    // cuts; it exists only where v or a face neighbour is in cell i. The seeds: XE, and the voxels of X
    // and where d_i changed, with their face neighbours, that are in or next to cell i before or after
    // (a superset of the voxels whose source changed)
    auto in_cell = [&](index_t v) { return before.label[v] == i || d_after.label[v] == i; };
    auto near_cell = [&](index_t v, const coord<P::dim>& c) {
      if (in_cell(v)) return true;
      for (const auto& f : faces) {
        const index_t y = c[std::size_t(f.axis)] + f.dir;
        if (y >= 0 && y < after.geometry.extent(f.axis) && in_cell(v + f.delta)) return true;
      }
      return false;
    };
    seeds = xes;
    auto consider = [&](index_t v) {
      const auto c = after.geometry.coords(v);
      if (near_cell(v, c)) seeds.push_back(v);
      for (const auto& f : faces) {
        const index_t y = c[std::size_t(f.axis)] + f.dir;
        if (y >= 0 && y < after.geometry.extent(f.axis)) {
          const index_t w = v + f.delta;
          if (near_cell(w, after.geometry.coords(w))) seeds.push_back(w);
        }
      }
    };
    for (const index_t v : xs) consider(v);
    for (const index_t v : moved) consider(v);
    dense_distances<T> db(dense_b, *o.frontier, *o.db);
    repair_distances(
        after, whole, walk, db, dmax, xf, seeds,
        [&](index_t v) {
          return frontier_source_at(after, faces, d_after.distance.data(), d_after.label.data(), i, v, dmax, di);
        },
        touched, old_value);
    merge_repaired(s.frontier, s.db, db, touched, old_value, moved);
    rows.insert(rows.end(), moved.begin(), moved.end());
  });
  std::vector<index_t> rows(xs);  // X, then every voxel where some node's d_i or d_B changed
  std::size_t affected = 0;
  for (const auto& r : node_rows) {
    rows.insert(rows.end(), r.begin(), r.end());
    affected += !r.empty();
  }
  // the rows to recompute, each from every node's new searches in node order
  std::sort(rows.begin(), rows.end());
  rows.erase(std::unique(rows.begin(), rows.end()), rows.end());
  const label_t* lab = d_after.label.data();
  const T* dist = d_after.distance.data();
  const std::size_t ks = std::size_t(k);
  std::vector<label_t> row_node(ks);
  std::vector<T> row_weight(ks);
  std::vector<double> raw(ks);
  std::vector<candidate> cand;
  std::size_t changed = 0;
  // many rows: node by node over every list, as distance_ratio_rows does (a row's slots see the nodes'
  // contributions in node order either way); few rows: each looks its voxel up in every node's lists
  std::size_t entries = 0;
  for (const auto& s : state->nodes) entries += s.support->size();
  const bool by_node = rows.size() * 16 > entries;
  std::vector<std::ptrdiff_t> slot_of;
  std::vector<label_t> slot_node;
  std::vector<double> slot_raw;
  if (by_node) {
    slot_of.assign(std::size_t(n), -1);
    for (std::size_t j = 0; j < rows.size(); ++j) slot_of[std::size_t(rows[j])] = std::ptrdiff_t(j);
    slot_node.assign(rows.size() * ks, no_label);
    slot_raw.assign(rows.size() * ks, 0.0);
    for (label_t i = 0; i < nodes; ++i)
      node_raw_weights(state->nodes[std::size_t(i)], lab, i, [&](index_t x, double wx) {
        const std::ptrdiff_t j = slot_of[std::size_t(x)];
        if (j >= 0) insert_slot(slot_node.data() + std::size_t(j) * ks, slot_raw.data() + std::size_t(j) * ks, k, i, wx);
      });
  }
  for (std::size_t j = 0; j < rows.size(); ++j) {
    const index_t v = rows[j];
    std::fill(row_node.begin(), row_node.end(), no_label);
    std::fill(row_weight.begin(), row_weight.end(), T(0));
    std::fill(raw.begin(), raw.end(), 0.0);
    if (by_node) {
      std::copy_n(slot_node.begin() + std::ptrdiff_t(j * ks), ks, row_node.begin());
      std::copy_n(slot_raw.begin() + std::ptrdiff_t(j * ks), ks, raw.begin());
    } else if (lab[v] != no_label && dist[v] != T(0)) {
      for (label_t i = 0; i < nodes; ++i) {
        const auto& s = state->nodes[std::size_t(i)];
        const T di = sorted_at(*s.support, *s.di, v);
        if (!(di < inf)) continue;
        const T db = sorted_at(*s.frontier, *s.db, v);
        const double wx = node_weight(s, di, db, lab[v] == i);
        if (wx > 0) insert_slot(row_node.data(), raw.data(), k, i, wx);
      }
    }
    finish_row(lab[v], dist[v], k, row_node.data(), row_weight.data(), raw.data(), cand);
    const std::size_t at = std::size_t(v) * ks;
    bool same = true;
    for (std::size_t s = 0; s < ks; ++s) {
      same = same && node[at + s] == row_node[s] && same_bits(weight[at + s], row_weight[s]);
      node[at + s] = row_node[s];
      weight[at + s] = row_weight[s];
    }
    changed += !same;
  }
  stats.rows = std::size_t(n);
  stats.recomputed = rows.size();
  stats.region_voxels = rows.size();
  stats.changed = changed;
  stats.nodes_affected = affected;
  stats.full = false;
  return state;
}

}  // namespace geovoronoi::detail::shape

#pragma once
// Shape functions after a change (shape_update.hpp): the voxels whose rows can change, found by
// searches that bound, from below and with a proven rounding margin, what every row's computation
// read; then those rows recomputed with the methods' own row functions. The argument is written out
// in docs/shape-functions.md ("After a change"); the comments below name its steps.

#include <geovoronoi/detail/dispatch.hpp>
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/distance_ratio.hpp>
#include <geovoronoi/detail/shape/distance_ratio_update.hpp>
#include <geovoronoi/detail/shape/natural_neighbours.hpp>
#include <geovoronoi/shape_functions.hpp>
#include <geovoronoi/change.hpp>
#include <geovoronoi/detail/update/node_list.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <queue>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace geovoronoi::detail::shape {

/// 0, 1, ..., n - 1.
inline std::vector<index_t> all_voxels(index_t n) {
  std::vector<index_t> v(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = index_t(i);
  return v;
}

/// The change argument of the public functions as a change<Dim> (a cut_set or a carving alone).
template <int Dim>
const change<Dim>& as_change(const change<Dim>& c) {
  return c;
}
template <int Dim>
change<Dim> as_change(const cut_set<Dim>& c) {
  change<Dim> out;
  out.cut = c;
  return out;
}
template <int Dim>
change<Dim> as_change(const carving& c) {
  change<Dim> out;
  out.carved = c.voxels;
  return out;
}

/// Label of the diagram before -> label after: the node's new position, or `gone` for a removed node.
struct renumbering {
  static constexpr label_t gone = -2;
  std::vector<label_t> to_new;
  bool identity = true;  // no node edit moved a label
  bool monotone = true;  // surviving nodes keep their relative order (tie order is then preserved)
  label_t operator()(label_t l) const noexcept { return l == no_label ? no_label : to_new[std::size_t(l)]; }
};

/// Replays the node edits on the nodes' identities; checks that d_after's nodes are the result.
template <int Dim>
renumbering renumber(const grid<Dim>& g, const std::vector<index_t>& before, const std::vector<index_t>& after,
                     const std::vector<node_edit<Dim>>& edits) {
  if (update::edit_node_list(g, before, edits) != after)
    throw std::invalid_argument(
        "geovoronoi::update_shape_functions: the nodes of the diagram after the change are not those of the diagram "
        "before with the change's node edits applied");
  std::vector<label_t> id(before.size());
  for (std::size_t i = 0; i < id.size(); ++i) id[i] = label_t(i);
  for (const auto& e : edits) {
    const bool adds = e.what == node_edit<Dim>::kind::add;
    const std::size_t pos = adds && e.position == node_edit<Dim>::append ? id.size() : e.position;
    if (adds)
      id.insert(id.begin() + std::ptrdiff_t(pos), no_label);
    else if (e.what == node_edit<Dim>::kind::remove)
      id.erase(id.begin() + std::ptrdiff_t(pos));
    // a move keeps the identity: the label stays, the cells and distances show the move
  }
  renumbering r;
  r.to_new.assign(before.size(), renumbering::gone);
  label_t last = no_label;
  for (std::size_t p = 0; p < id.size(); ++p) {
    if (id[p] == no_label) continue;
    r.to_new[std::size_t(id[p])] = label_t(p);
    if (id[p] < last) r.monotone = false;
    last = id[p];
  }
  r.identity = before.size() == after.size();
  for (std::size_t i = 0; i < r.to_new.size() && r.identity; ++i) r.identity = r.to_new[i] == label_t(i);
  return r;
}

/**
 * The rounding margin. A computed distance is a left-to-right float sum a_i = fl(a_{i-1} + w_i) along
 * a simple path of h <= H hops (H bounds the voxels of the domain before and after). Round to nearest gives
 * a_i >= (a_{i-1} + w_i)(1 - u) - eta, so the exact sum S of the weights satisfies
 * S <= (a_h + H eta) / (1 - H u). Our searches sum the same T weights in double (relative error
 * below 2^-21 for H < 2^32), so "computed distance < r" implies "double search distance <
 * bound(r)" with bound(r) = (r + H eta) / (1 - H u) * (1 + 2^-18). Valid while H u < 1/4.
 */
template <class T>
struct rounding_margin {
  double scale = 0, add = 0;
  bool valid = false;
  explicit rounding_margin(index_t voxels) {
    const double H = double(voxels), u = double(std::numeric_limits<T>::epsilon()) / 2;
    const double eta = double(std::numeric_limits<T>::denorm_min());  // >= half the smallest spacing
    valid = H * u < 0.25;
    scale = (1 + std::ldexp(1.0, -18)) / (1 - H * u);
    add = H * eta * scale;
  }
  double operator()(double r) const noexcept { return r * scale + add; }
};

/**
 * A search that keeps, at every voxel, the largest budget left: sources start with their own budget,
 * a step along an edge spends the edge's weight, and voxels end with budget > 0 or are never reached.
 * @p step(u, b, f) calls f(w, weight) for the voxels w the search may enter from u, popped with its
 * final budget b; it returns false to end the search.
 */
template <class Step>
void budget_search(std::vector<double>& budget, std::vector<index_t>& reached,
                   std::vector<std::pair<double, index_t>>& sources, Step&& step) {
  std::priority_queue<std::pair<double, index_t>> heap(std::less<std::pair<double, index_t>>(), std::move(sources));
  while (!heap.empty()) {
    // (no structured binding: clang 14 cannot capture one in the lambda below)
    const double b = heap.top().first;
    const index_t u = heap.top().second;
    heap.pop();
    if (b < budget[std::size_t(u)]) continue;  // stale
    const bool more = step(u, b, [&](index_t w, double weight) {
      const double nb = b - weight;
      if (nb > 0 && nb > budget[std::size_t(w)]) {
        if (!(budget[std::size_t(w)] > 0)) reached.push_back(w);
        budget[std::size_t(w)] = nb;
        heap.push({nb, w});
      }
    });
    if (!more) return;
  }
}

/// Queues @p v with budget @p b when it is more than what v holds.
inline void offer(std::vector<double>& budget, std::vector<index_t>& reached,
                  std::vector<std::pair<double, index_t>>& sources, index_t v, double b) {
  if (!(b > 0) || !(b > budget[std::size_t(v)])) return;
  if (!(budget[std::size_t(v)] > 0)) reached.push_back(v);
  budget[std::size_t(v)] = b;
  sources.push_back({b, v});
}

/// One step of the searches from N[X] \ X: from @p u into its neighbours w outside X and inside the
/// domain, each at the weight of the edge w -> u (the searches being bounded run toward N[X]).
template <class P, class F>
void toward_x_step(const P& after, const stencil_walker<P::dim>& walk, const voxel_bits& x, index_t u, F&& f) {
  using T = typename P::value_type;
  const T fu = after.field[u];
  walk.for_each_neighbour(after, u, [&](int k, index_t w) {
    if (x.test(w) || !after.inside(w)) return;
    const T wt = edge_weight(after.metric, after.edges.length[opposite_direction(k, P::neighbours)], after.field[w], fu);
    if (wt >= T(0)) f(w, double(wt));
  });
}

/**
 * Sibson / Laplace: the queries whose search before the change can have read a changed voxel. The
 * search of q reads (distance, label, field, cut bits) only at voxels of its new cell C_q and their
 * stencil neighbours; if none of them is in X, the search after the change makes the same steps and
 * returns the same row. Such a q has a voxel of its cell in N[X] (X and its stencil neighbours), and
 * the first such voxel v on q's canonical path is reached through voxels outside N[X], over edges
 * that are the same before and after. So q is within d_before(v) of v (up to the rounding margin),
 * over a path that avoids X: a budget search from every v in N[X] \ X with budget bound(d_before(v)),
 * in the problem after, through voxels outside X, finds every such q.
 */
template <class P, class D>
void natural_neighbour_candidates(const P& after, const D& before, const voxel_bits& x,
                                  const std::vector<index_t>& xs, const rounding_margin<typename P::value_type>& bound,
                                  voxel_bits& rows) {
  using T = typename P::value_type;
  const index_t n = after.geometry.size();
  const stencil_walker<P::dim> walk(after);
  std::vector<double> budget(std::size_t(n), -1.0);
  std::vector<index_t> reached;
  std::vector<std::pair<double, index_t>> sources;
  auto source = [&](index_t v) {
    if (x.test(v)) return;  // in X itself: recomputed anyway, and paths through X do not count
    const T d = before.distance[v];
    if (!(d > T(0)) || !(d < std::numeric_limits<T>::infinity())) return;  // a node, or unreached
    offer(budget, reached, sources, v, bound(double(d)));
  };
  for (const index_t v : xs) walk.for_each_neighbour(after, v, [&](int, index_t u) { source(u); });
  budget_search(budget, reached, sources, [&](index_t u, double, auto&& f) {
    toward_x_step(after, walk, x, u, f);
    return true;
  });
  for (const index_t v : reached) rows.insert(v);
}

/**
 * Distance Ratio. Node j's contribution (its raw weights) is computed from reads of: its cell and the
 * cell's face neighbours (the bound d_max and the frontier), its support search (node j to 2 d_max)
 * and its frontier search (from sources in N_face[cell] to d_max), each reading their settled voxels
 * and those voxels' stencil neighbours. A node is affected when its identity or seed changed, when X
 * meets N[cell] before or after, or when one of its searches before could reach N[X] (a search from
 * N[X] \ X through voxels outside X, as for the natural neighbours). Other nodes contribute the same
 * raw weights, so a row changes only in X or in the support, before or after, of an affected node.
 * Those supports lie in balls of a lower-bound search (edges at a voxel of X weigh 0 and may cross
 * the cut or the mask) from the node's voxels, with budget bound(2 d_max) before and after.
 */
template <class P, class D>
std::size_t distance_ratio_candidates(const P& after, const D& before, const D& d_after, const renumbering& ren,
                                      const voxel_bits& x, const std::vector<index_t>& xs,
                                      const rounding_margin<typename P::value_type>& bound, voxel_bits& rows) {
  using T = typename P::value_type;
  const index_t n = after.geometry.size();
  const std::size_t nb = before.seeds.size(), na = d_after.seeds.size();
  const auto faces = faces_of(after);
  // d_max per node over its cell and every face neighbour, ignoring cuts (>= the exact bound)
  auto bounds = [&](const D& d, std::size_t nodes) {
    std::vector<T> dm(nodes, T(0));
    for (index_t v = 0; v < n; ++v) {
      const label_t l = d.label[v];
      if (l == no_label) continue;
      dm[std::size_t(l)] = std::max(dm[std::size_t(l)], d.distance[v]);
      const auto c = after.geometry.coords(v);
      for (const auto& f : faces) {
        const index_t y = c[std::size_t(f.axis)] + f.dir;
        if (y < 0 || y >= after.geometry.extent(f.axis)) continue;
        const label_t m = d.label[v + f.delta];
        if (m != no_label && m != l) dm[std::size_t(l)] = std::max(dm[std::size_t(l)], d.distance[v + f.delta]);
      }
    }
    return dm;
  };
  const std::vector<T> dmb = bounds(before, nb), dma = bounds(d_after, na);
  std::vector<char> hit_old(nb, 0), hit_new(na, 0);
  for (std::size_t j = 0; j < nb; ++j) {
    const label_t t = ren.to_new[j];
    if (t == renumbering::gone || before.seeds[j] != d_after.seeds[std::size_t(t)]) hit_old[j] = 1;
  }
  for (std::size_t j = 0; j < na; ++j) hit_new[j] = 1;
  for (std::size_t j = 0; j < nb; ++j)
    if (ren.to_new[j] != renumbering::gone) hit_new[std::size_t(ren.to_new[j])] = hit_old[j];  // new nodes stay hit
  // X meets N[cell] before or after
  for (const index_t v : xs) {
    auto mark = [&](index_t y) {
      if (before.label[y] != no_label) hit_old[std::size_t(before.label[y])] = 1;
      if (d_after.label[y] != no_label) hit_new[std::size_t(d_after.label[y])] = 1;
    };
    mark(v);
    for_each_grid_neighbour(after, v, [&](int, index_t y) { mark(y); });
  }
  // the searches before: distances from N[X] \ X (double, through voxels outside X, weight of the
  // direction the node's or the frontier's search runs: toward N[X])
  double reach = 0;
  for (std::size_t j = 0; j < nb; ++j)
    if (!hit_old[j] && dmb[j] > T(0)) reach = std::max(reach, bound(2 * double(dmb[j])));
  if (reach > 0 && !xs.empty()) {
    const stencil_walker<P::dim> walk(after);
    std::vector<double> budget(std::size_t(n), -1.0);  // reach - distance from N[X] \ X
    std::vector<index_t> reached;
    std::vector<std::pair<double, index_t>> sources;
    for (const index_t v : xs)
      walk.for_each_neighbour(after, v, [&](int, index_t u) {
        if (!x.test(u) && after.inside(u)) offer(budget, reached, sources, u, reach);
      });
    // the double sums err by at most 2^-21 of reach, whatever node is tested: add that
    const double slack = std::ldexp(reach, -20);
    std::size_t unhit = std::size_t(std::count(hit_old.begin(), hit_old.end(), char(0)));
    auto hit = [&](label_t l) {
      if (!hit_old[std::size_t(l)]) hit_old[std::size_t(l)] = 1, --unhit;
    };
    // each voxel is tested when it pops (its budget is final then); the search ends once every node is hit
    budget_search(budget, reached, sources, [&](index_t z, double b, auto&& f) {
      const double dist = reach - b - slack;
      // the support search of node j (from its voxel, to 2 d_max)
      const label_t lz = before.label[z];
      if (lz != no_label && before.seeds[std::size_t(lz)] == z && dist < bound(2 * double(dmb[std::size_t(lz)]))) hit(lz);
      // the frontier search of the cells z belongs or is a face neighbour to (to d_max)
      auto frontier = [&](label_t l) {
        if (l != no_label && dist < bound(double(dmb[std::size_t(l)]))) hit(l);
      };
      frontier(lz);
      const auto c = after.geometry.coords(z);
      for (const auto& fc : faces) {
        const index_t y = c[std::size_t(fc.axis)] + fc.dir;
        if (y >= 0 && y < after.geometry.extent(fc.axis)) frontier(before.label[z + fc.delta]);
      }
      if (unhit == 0) return false;
      toward_x_step(after, walk, x, z, f);
      return true;
    });
  }
  for (std::size_t j = 0; j < nb; ++j)
    if (ren.to_new[j] != renumbering::gone) {
      const std::size_t t = std::size_t(ren.to_new[j]);
      const char h = char(hit_old[j] | hit_new[t]);
      hit_old[j] = hit_new[t] = h;
    }
  // every node affected (supports of radius 2 d_max reach far): every row is recomputed, without the
  // search below (its balls would cover the grid)
  if (std::all_of(hit_old.begin(), hit_old.end(), [](char h) { return h != 0; }) &&
      std::all_of(hit_new.begin(), hit_new.end(), [](char h) { return h != 0; })) {
    for (index_t v = 0; v < n; ++v) rows.insert(v);
    return std::max(nb, na);
  }
  // the supports of the affected nodes, before and after: a lower-bound search from their voxels
  std::vector<double> budget(std::size_t(n), -1.0);
  std::vector<index_t> reached;
  std::vector<std::pair<double, index_t>> sources;
  std::size_t affected = 0;
  for (std::size_t j = 0; j < nb; ++j)
    if (hit_old[j]) {
      affected += ren.to_new[j] == renumbering::gone;
      offer(budget, reached, sources, before.seeds[j], bound(2 * double(dmb[j])));
      rows.insert(before.seeds[j]);
    }
  for (std::size_t j = 0; j < na; ++j)
    if (hit_new[j]) {
      ++affected;
      offer(budget, reached, sources, d_after.seeds[j], bound(2 * double(dma[j])));
      rows.insert(d_after.seeds[j]);
    }
  const stencil_walker<P::dim> walk(after);
  budget_search(budget, reached, sources, [&](index_t u, double, auto&& f) {
    if (x.test(u)) {  // every edge at a voxel of X: weight 0, cut or masked
      for_each_grid_neighbour(after, u, [&](int, index_t w) { f(w, 0.0); });
      return true;
    }
    const T fu = after.field[u];
    walk.for_each_neighbour(after, u, [&](int k, index_t w) {
      if (x.test(w)) return f(w, 0.0);
      if (!after.inside(w)) return;
      const T wt = edge_weight(after.metric, after.edges.length[k], fu, after.field[w]);
      if (wt >= T(0)) f(w, double(wt));
    });
    return true;
  });
  for (const index_t v : reached) rows.insert(v);
  return affected;
}

/**
 * The update itself: rows of K slots in @p node / @p weight, row r at voxel (*row_list)[r] (repeats
 * allowed) or, with a null @p row_list, row v at voxel v of the whole grid, hold the weights of the
 * problem before the change; afterwards they hold those of @p after. @p nodes is set to the node count
 * after the change.
 */
template <class Policy, class P, class D, class Options, class Stats>
void update_rows(const Policy& policy, const P& after, const D& before, const D& d_after,
                 const change<P::dim>& c, const Options& opt, int k, std::size_t& nodes,
                 const std::vector<index_t>* row_list, std::vector<label_t>& node,
                 std::vector<typename P::value_type>& weight, Stats& stats,
                 std::shared_ptr<const distance_ratio_state<typename P::value_type>>* state = nullptr) {
  using T = typename P::value_type;
  const std::string who = "geovoronoi::update_shape_functions: ";
  const index_t n = after.geometry.size();
  if (!(before.geometry() == after.geometry) || before.distance.size() != n || before.label.size() != n)
    throw std::invalid_argument(who + "the diagram before the change belongs to another grid than the problem's");
  if (k != opt.max_nodes_per_voxel)
    throw std::invalid_argument(who + "the weights have K = " + std::to_string(k) + " slots but the options ask for " +
                                std::to_string(opt.max_nodes_per_voxel));
  if (nodes != before.seeds.size())
    throw std::invalid_argument(who + "the weights have " + std::to_string(nodes) +
                                " nodes but the diagram before the change has " + std::to_string(before.seeds.size()));
  for (std::size_t i = 0; i < before.seeds.size(); ++i)
    if (before.seeds[i] < 0 || before.seeds[i] >= n || before.label[before.seeds[i]] != label_t(i))
      throw std::invalid_argument(who + "node " + std::to_string(i) +
                                  " of the diagram before the change does not carry its own label");
  const renumbering ren = renumber(after.geometry, before.seeds, d_after.seeds, c.nodes);
  for (int q = 0; q < P::neighbours; ++q)
    if (after.edges.delta[opposite_direction(q, P::neighbours)] != -after.edges.delta[q])
      throw std::logic_error(who + "the stencil is not symmetric about its middle");

  // X: voxels whose distance, (renumbered) label or field changed, and the ends of new cut edges
  voxel_bits x(n);
  std::vector<index_t> xs;
  // and apart, XE: the voxels at a changed edge or field (what a search's distances depend on), and
  // XF: those whose field changed (all their edges' weights may have changed)
  voxel_bits xe(n), xf(n);
  std::vector<index_t> xes;
  auto mark = [&](index_t v) {
    if (x.insert(v)) xs.push_back(v);
  };
  auto mark_edge = [&](index_t v) {
    mark(v);
    if (xe.insert(v)) xes.push_back(v);
  };
  for (index_t v = 0; v < n; ++v)
    if (!same_bits(before.distance[v], d_after.distance[v]) || ren(before.label[v]) != d_after.label[v]) mark(v);
  for (const auto* list : {&c.carved, &c.added, &c.restiffened})
    for (const index_t v : *list) {
      if (v < 0 || v >= n)
        throw std::invalid_argument(who + "the change lists voxel " + std::to_string(v) + ", outside the grid");
      mark_edge(v);
      xf.insert(v);
    }
  if (c.cut) {
    if (!(c.cut->geometry() == after.geometry) || c.cut->directions() != P::neighbours)
      throw std::invalid_argument(who + "the cut belongs to another grid or connectivity than the problem's");
    for (const auto& e : *c.cut)
      for (int f = 0; f < P::neighbours / 2; ++f)
        if ((e.forward >> f) & 1u) {
          mark_edge(e.voxel);
          mark_edge(e.voxel + after.edges.delta[P::neighbours / 2 + f]);
        }
  }
  stats.changed_voxels = xs.size();

  // Distance Ratio with the nodes' searches kept in the weights: repair them when every node keeps its
  // label (nodes may be moved or appended: their searches run from scratch)
  bool labels_kept = d_after.seeds.size() >= before.seeds.size();
  for (std::size_t i = 0; i < before.seeds.size() && labels_kept; ++i) labels_kept = ren.to_new[i] == label_t(i);
  if (state && *state && opt.method == shape_method::distance_ratio && !row_list && labels_kept &&
      (*state)->seeds == before.seeds && (*state)->nodes.size() == nodes) {
    *state = distance_ratio_update(policy, after, before, d_after, xs, xf, xes, **state, k, node, weight, stats);
    nodes = d_after.seeds.size();  // every old label kept (appended ones follow): no row renumbered
    report(opt.progress, 1.0);
    return;
  }
  // the rows below are recomputed without the searches: they can be kept again only by running
  // every node's searches (all rows), and only when asked for
  const bool keep = state && opt.keep_update_state && opt.method == shape_method::distance_ratio && !row_list;
  if (state) state->reset();

  // R: the voxels whose rows are recomputed
  voxel_bits rows(n);
  // a simple path of the problem before or after stays in its domain: at most (inside after) + |X|
  // voxels, since a voxel whose domain membership changed is in X
  index_t inside = index_t(xs.size());
  for (index_t v = 0; v < n; ++v) inside += after.inside(v) ? 1 : 0;
  const rounding_margin<T> bound(std::min(inside, n));
  stats.full = !bound.valid || !ren.monotone || keep;
  if (stats.full) {
    for (index_t v = 0; v < n; ++v) rows.insert(v);
  } else {
    for (const index_t v : xs) rows.insert(v);
    if (opt.method == shape_method::distance_ratio)
      stats.nodes_affected = distance_ratio_candidates(after, before, d_after, ren, x, xs, bound, rows);
    else
      natural_neighbour_candidates(after, before, x, xs, bound, rows);
  }

  for (index_t v = 0; v < n; ++v) stats.region_voxels += rows.test(v);
  // recompute those rows (in voxel order: the row functions keep sorted lists in that order); every
  // row of the whole grid: the whole-grid form (no per-point bookkeeping)
  const std::size_t ks = std::size_t(k), row_count = row_list ? row_list->size() : std::size_t(n);
  auto row_voxel = [&](std::size_t r) { return row_list ? (*row_list)[r] : index_t(r); };
  std::vector<std::size_t> redo;
  for (std::size_t r = 0; r < row_count; ++r)
    if (rows.test(row_voxel(r))) redo.push_back(r);
  if (row_list)
    std::stable_sort(redo.begin(), redo.end(), [&](std::size_t a, std::size_t b) { return row_voxel(a) < row_voxel(b); });
  const bool whole = !row_list && redo.size() == std::size_t(n);
  std::vector<index_t> vox(whole ? 0 : redo.size());
  for (std::size_t i = 0; i < vox.size(); ++i) vox[i] = row_voxel(redo[i]);
  std::vector<label_t> new_node(redo.size() * ks, no_label);
  std::vector<T> new_weight(redo.size() * ks, T(0));
  if (!redo.empty())
    with_threads(policy, opt.threads, [&] {
      // with `whole`, null voxel lists mean the whole grid
      const index_t* list = whole ? nullptr : vox.data();
      if (opt.method == shape_method::distance_ratio) {
        std::shared_ptr<distance_ratio_state<T>> kept;
        if (keep) kept = std::make_shared<distance_ratio_state<T>>();
        distance_ratio_rows(policy, after, d_after, opt, k, d_after.seeds.size(), list, redo.size(),
                            new_node.data(), new_weight.data(), kept.get());
        if (keep) *state = std::move(kept);
      }
      else if (whole && (opt.method == shape_method::sibson || opt.method == shape_method::laplace))
        natural_neighbour_rows(policy, after, d_after, opt, opt.method == shape_method::laplace,
                               all_voxels(n).data(), redo.size(), k, d_after.seeds.size(), new_node.data(),
                               new_weight.data());
      else if (opt.method == shape_method::sibson || opt.method == shape_method::laplace)
        natural_neighbour_rows(policy, after, d_after, opt, opt.method == shape_method::laplace, vox.data(),
                               vox.size(), k, d_after.seeds.size(), new_node.data(), new_weight.data());
      else
        throw std::invalid_argument(who + "unknown shape_method " + std::to_string(static_cast<int>(opt.method)));
      return 0;
    });
  else
    report(opt.progress, 1.0);

  // renumber every row (a kept row cannot name a removed node: its voxel would be in R), then write
  // the recomputed ones
  if (!ren.identity)
    for (std::size_t at = 0; at < node.size(); ++at) {
      const label_t m = ren(node[at]);
      if (m == renumbering::gone && !rows.test(row_voxel(at / ks)))
        throw std::logic_error(who + "a kept row names a removed node");
      node[at] = m == renumbering::gone ? no_label : m;
    }
  std::size_t changed = 0;
  for (std::size_t i = 0; i < redo.size(); ++i) {
    const std::size_t at = redo[i] * ks;
    bool same = true;
    for (std::size_t s = 0; s < ks; ++s) {
      same = same && node[at + s] == new_node[i * ks + s] && same_bits(weight[at + s], new_weight[i * ks + s]);
      node[at + s] = new_node[i * ks + s];
      weight[at + s] = new_weight[i * ks + s];
    }
    changed += !same;
  }
  nodes = d_after.seeds.size();
  stats.rows = row_count;
  stats.recomputed = redo.size();
  stats.changed = changed;
}

}  // namespace geovoronoi::detail::shape

#pragma once
// Bodies of geovoronoi/branching_shape.hpp.

#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/detail/branching/update.hpp>
#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/search/cell_counts.hpp>
#include <geovoronoi/detail/search/sparse.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/distance_ratio.hpp>
#include <geovoronoi/detail/shape/natural_neighbours.hpp>
#include <geovoronoi/detail/shape/shape_functions.hpp>

#include <algorithm>
#include <array>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

namespace detail::branching {

/// Distance Ratio's kept searches on a branching grid (copy_weights::update_state): the regular
/// state, its lists over the searches' slots.
template <class T>
struct shape_state : shape::distance_ratio_state<T> {};

/// What the methods read of a regular grid, on a branching problem. The search's nodes are slots;
/// the diagram is moved to slots once (dist, lab). A face of the regular methods is a link of a
/// face direction of the coarse stencil (face_of[k] >= 0), with the coarse face's area (faces, made
/// by the regular faces_of on the coarse grid). vol is what Sibson's finish_weights reads of the grid:
/// the fine voxel volume, by which each stolen copy's fine voxel count is multiplied.
template <class P>
struct copy_graph {
  using T = typename P::value_type;
  static constexpr int Dim = P::dim;
  struct coarse_view {  // search::faces_of's view of the coarse grid and stencil
    static constexpr int dim = P::dim;
    static constexpr int neighbours = P::neighbours;
    grid<P::dim> geometry;
    stencil<T, P::dim, P::neighbours> edges;
  };
  struct fine_volume {  // finish_weights' view: the fine voxel's volume
    static constexpr int dim = P::dim;
    grid<P::dim> geometry;
  };
  const P& p;
  search::walker_t<P> walk;
  std::vector<search::face<Dim>> faces;
  std::array<int, 32> face_of{};
  fine_volume vol;
  std::vector<T> dist;      // per slot
  std::vector<label_t> lab;  // per slot
  std::vector<std::int64_t> count;  // per slot: its copy's fine voxels

  copy_graph(const P& problem, const node_diagram<T>& d) : p(problem), walk(problem) {
    const auto& bg = p.grid_of();
    faces = search::faces_of(coarse_view{bg.coarse(), p.edges});
    face_of.fill(-1);
    for (std::size_t f = 0; f < faces.size(); ++f) face_of[std::size_t(faces[f].edge)] = int(f);
    vol.geometry = bg.fine();
    const auto n = std::size_t(p.slots);
    dist.assign(n, std::numeric_limits<T>::infinity());
    lab.assign(n, no_label);
    count.assign(n, 0);
    for (index_t a = 0; a < bg.copies(); ++a) {
      const auto s = std::size_t(p.slot_of_copy[a]);
      dist[s] = d.distance[std::size_t(a)];
      lab[s] = d.label[std::size_t(a)];
      count[s] = bg.voxel_count()[std::size_t(a)];
    }
  }
  /// f(k, u, face) for each face link v -> u.
  template <class F>
  void for_each_face_link(index_t v, F&& f) const {
    walk.for_each_neighbour(p, v, [&](int k, index_t u) {
      const int fi = face_of[std::size_t(k)];
      if (fi >= 0) f(k, u, faces[std::size_t(fi)]);
    });
  }
};

/// The argument checks of shape_functions() on a branching grid.
template <class P, class T>
void validate(const P& p, const node_diagram<T>& d, const shape_options& opt) {
  const std::string who = "geovoronoi::shape_functions: ";
  if (opt.max_nodes_per_voxel < 1 || opt.max_nodes_per_voxel > max_nodes_per_voxel_limit)
    throw std::invalid_argument(who + "max_nodes_per_voxel (K) is " + std::to_string(opt.max_nodes_per_voxel) +
                                "; it must be between 1 and " + std::to_string(max_nodes_per_voxel_limit));
  if (opt.batch_size == 0) throw std::invalid_argument(who + "batch_size is 0; it must be >= 1");
  if (d.seeds.empty()) throw std::invalid_argument(who + "the diagram has no seeds, so there are no nodes");
  const index_t n = p.grid_of().copies();
  if (index_t(d.distance.size()) != n || index_t(d.label.size()) != n)
    throw std::invalid_argument(who + "the diagram has " + std::to_string(d.distance.size()) +
                                " entries but the branching grid has " + std::to_string(n) + " copies");
  const label_t nodes = label_t(d.seeds.size());
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const index_t s = d.seeds[i];
    if (s < 0 || s >= n)
      throw std::invalid_argument(who + "node " + std::to_string(i) + " is copy " + std::to_string(s) +
                                  ", not a copy of the branching grid");
    if (d.label[std::size_t(s)] != label_t(i))
      throw std::invalid_argument(who + "node " + std::to_string(i) + " (" + p.grid_of().copy_text(s) +
                                  ") carries label " + std::to_string(d.label[std::size_t(s)]) +
                                  " in the diagram; node i must carry label i (use geovoronoi::voronoi)");
  }
  for (index_t a = 0; a < n; ++a)
    if (d.label[std::size_t(a)] < no_label || d.label[std::size_t(a)] >= nodes)
      throw std::invalid_argument(who + "copy " + std::to_string(a) + " carries label " +
                                  std::to_string(d.label[std::size_t(a)]) + ", which is not a node index");
}

/// Node i's bound d_max (shape::node_bound on the copy graph): the largest distance over its cell and
/// the cell's face neighbours in other cells.
template <class G>
typename G::T node_bound(const G& g, label_t i, const index_t* cell, std::size_t cell_size) {
  using T = typename G::T;
  T dmax = T(0);
  for (std::size_t j = 0; j < cell_size; ++j) {
    const index_t x = cell[j];
    dmax = std::max(dmax, g.dist[std::size_t(x)]);
    g.for_each_face_link(x, [&](int, index_t y, const auto&) {
      if (g.lab[std::size_t(y)] != no_label && g.lab[std::size_t(y)] != i) dmax = std::max(dmax, g.dist[std::size_t(y)]);
    });
  }
  return dmax;
}

/// Node i's two searches (shape::node_searches on the copy graph, the frontier of
/// shape::frontier_sources across face links), in the search scratch @p sc.
template <class G, class Scratch>
shape::dr_node<typename G::T> node_searches(const G& g, Scratch& sc, label_t i, index_t node_slot, const index_t* cell,
                                            std::size_t cell_size, typename G::T dmax) {
  using T = typename G::T;
  shape::dr_node<T> s;
  s.dmax = dmax;
  auto di = search::bounded(g.p, sc.keys, sc.heap, std::vector<source<T>>{{node_slot, T(0), 0}}, T(2) * dmax);
  s.support = shape::share(std::move(di.voxel));
  s.di = shape::share(std::move(di.distance));
  std::vector<source<T>> frontier;
  for (std::size_t j = 0; j < cell_size; ++j) {
    const index_t x = cell[j];
    g.for_each_face_link(x, [&](int, index_t y, const auto&) {
      const label_t ly = g.lab[std::size_t(y)];
      if (ly == no_label || ly == i) return;
      shape::add_frontier_face(frontier, x, y, shape::sorted_at(*s.support, *s.di, y), g.dist[std::size_t(x)],
                               g.dist[std::size_t(y)], dmax);
    });
  }
  shape::sort_frontier(frontier);
  sparse_solution<T> db;
  if (!frontier.empty()) db = search::bounded(g.p, sc.keys, sc.heap, frontier, dmax);
  s.frontier = shape::share(std::move(db.voxel));
  s.db = shape::share(std::move(db.distance));
  return s;
}

/// One node's searches, or its kept ones: what Distance Ratio's node loop runs per node.
template <class G>
shape::dr_node<typename G::T> node_state(const G& g, label_t i, index_t node_slot, const shape::cell_lists& cells) {
  using T = typename G::T;
  const index_t* cell = cells.members.data() + cells.start[std::size_t(i)];
  const std::size_t cell_size = cells.start[std::size_t(i) + 1] - cells.start[std::size_t(i)];
  const T dmax = node_bound(g, i, cell, cell_size);
  if (!(dmax > T(0))) return shape::isolated_node(dmax, node_slot);
  search::sparse_scratch<T> sc;
  return node_searches(g, sc, i, node_slot, cell, cell_size, dmax);
}

/**
 * Distance Ratio rows over slots (shape::distance_ratio_rows on the copy graph): every node's state
 * from @p state_of(i) (its searches, run as parallel host tasks in groups of 8), merged into the rows
 * in node order, then each row of @p rows (slots) normalised. Rows not in @p rows are left as they are.
 */
template <class Policy, class G, class StateOf>
void distance_ratio_slots(const Policy& policy, const G& g, const std::vector<index_t>& seeds, int k,
                          const std::vector<index_t>& rows, std::vector<std::int64_t>& row_of, label_t* out_node,
                          typename G::T* out_weight, const shape_options& opt, StateOf&& state_of,
                          std::vector<shape::dr_node<typename G::T>>* keep) {
  const label_t nodes = label_t(seeds.size());
  std::vector<double> raw(rows.size() * std::size_t(k), 0.0);
  std::vector<label_t> slot_node(rows.size() * std::size_t(k), no_label);
  if (keep) keep->assign(std::size_t(nodes), shape::dr_node<typename G::T>{});
  constexpr label_t group = 8;
  std::vector<shape::dr_node<typename G::T>> states;
  states.resize(std::size_t{group});
  for (label_t g0 = 0; g0 < nodes; g0 += group) {
    const label_t g1 = std::min<label_t>(nodes, g0 + group);
    host_parallel_for(policy, index_t(g1 - g0), [&](index_t t) { states[std::size_t(t)] = state_of(g0 + label_t(t)); });
    for (label_t i = g0; i < g1; ++i) {
      auto& s = states[std::size_t(i - g0)];
      shape::node_raw_weights(s, g.lab.data(), i, [&](index_t x, double wx) {
        const std::int64_t r = row_of[std::size_t(x)];
        if (r >= 0)
          shape::insert_slot(slot_node.data() + std::size_t(r) * std::size_t(k), raw.data() + std::size_t(r) * std::size_t(k),
                             k, i, wx);
      });
      if (keep) (*keep)[std::size_t(i)] = std::move(s);
      shape::report(opt.progress, double(i + 1) / double(nodes));
    }
  }
  std::vector<shape::candidate> cand;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto v = std::size_t(rows[r]);
    const std::size_t at = r * std::size_t(k);
    std::copy(slot_node.begin() + std::ptrdiff_t(at), slot_node.begin() + std::ptrdiff_t(at) + k, out_node + at);
    shape::finish_row(g.lab[v], g.dist[v], k, out_node + at, out_weight + at, raw.data() + at, cand);
  }
}

/// One Sibson/Laplace row (query slot @p q of distance > 0): its new cell by the shared insert-query
/// search, the stolen volume per owner (fine voxel counts), Laplace's facets across face links; then
/// the regular methods' finish_weights and store.
template <class G, class Scratch>
void natural_neighbour_row(const G& g, Scratch& sc, search::accumulators& acc, std::vector<shape::candidate>& cand,
                           query_cells<typename G::T>& cells, bool laplace, index_t q, int k, label_t* node,
                           typename G::T* weight) {
  using T = typename G::T;
  cells.query.clear();
  cells.offsets.assign(1, 0);
  cells.voxel.clear();
  cells.distance.clear();
  cells.owner.clear();
  search::insert_queries(g.p, sc.keys, sc.heap, g.dist.data(), g.lab.data(), &q, 1, cells);
  const index_t* cell = cells.voxel.data();
  const std::size_t size = cells.voxel.size();
  acc.clear();
  for (std::size_t j = 0; j < size; ++j) {
    const label_t o = cells.owner[j];
    if (o < 0) continue;
    acc.touch(o);
    acc.volume[std::size_t(o)] += g.count[std::size_t(cell[j])];
  }
  bool any_facet = false;
  if (laplace)
    for (std::size_t j = 0; j < size; ++j) {
      const index_t v = cell[j];
      const T dq = cells.distance[j];
      const T fv = g.p.field[v];
      g.for_each_face_link(v, [&](int e, index_t w, const search::face<G::Dim>& f) {
        if (!g.p.inside(w)) return;
        const label_t kw = g.lab[std::size_t(w)];
        if (kw == no_label || std::binary_search(cell, cell + size, w)) return;
        search::add_facet_pair(g.p, acc, kw, f.axis, e, dq, fv, g.p.field[w], g.dist[std::size_t(w)]);
        any_facet = true;
      });
    }
  shape::finish_weights(g.vol, g.faces, laplace, any_facet, acc, cand);
  if (cand.empty()) {
    node[0] = g.lab[std::size_t(q)];
    weight[0] = T(1);
    return;
  }
  shape::store(cand, k, node, weight);
}

/// Sibson/Laplace rows of the slots @p rows (row r at r * k), each on its own, in parallel host tasks.
template <class Policy, class G>
void natural_neighbour_slots(const Policy& policy, const G& g, std::size_t nodes, bool laplace, int k,
                             const std::vector<index_t>& rows, label_t* node, typename G::T* weight,
                             const shape_options& opt) {
  using T = typename G::T;
  std::vector<std::size_t> queries;
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto v = std::size_t(rows[r]);
    if (g.lab[v] == no_label) continue;
    if (g.dist[v] > T(0))
      queries.push_back(r);
    else
      node[r * std::size_t(k)] = g.lab[v], weight[r * std::size_t(k)] = T(1);
  }
  constexpr std::size_t per_task = 64;
  const std::size_t total = queries.size();
  for (std::size_t start = 0; start < total; start += opt.batch_size) {
    const std::size_t end = std::min(total, start + opt.batch_size);
    host_parallel_for(policy, index_t((end - start + per_task - 1) / per_task), [&](index_t t) {
      search::sparse_scratch<T> sc;
      search::accumulators acc(nodes);
      std::vector<shape::candidate> cand;
      query_cells<T> cells;
      const std::size_t b = start + std::size_t(t) * per_task, e = std::min(end, b + per_task);
      for (std::size_t i = b; i < e; ++i) {
        const std::size_t r = queries[i];
        natural_neighbour_row(g, sc, acc, cand, cells, laplace, rows[r], k, node + r * std::size_t(k),
                              weight + r * std::size_t(k));
      }
    });
    shape::report(opt.progress, double(end) / double(total));
  }
}

/// Rows of the slots @p rows by the method of @p opt, into node/weight (row r at r * k, empty on
/// entry); Distance Ratio's searches kept in @p keep when given.
template <class Policy, class G>
void rows_of(const Policy& policy, const G& g, const std::vector<index_t>& seed_slots, const shape_options& opt,
             const std::vector<index_t>& rows, label_t* node, typename G::T* weight,
             std::vector<shape::dr_node<typename G::T>>* keep) {
  const int k = opt.max_nodes_per_voxel;
  switch (opt.method) {
    case shape_method::distance_ratio: {
      std::vector<std::int64_t> row_of(g.dist.size(), -1);
      for (std::size_t r = 0; r < rows.size(); ++r)
        if (row_of[std::size_t(rows[r])] < 0) row_of[std::size_t(rows[r])] = std::int64_t(r);
      // distinct rows only: a repeated slot copies its first row afterwards
      std::vector<index_t> distinct;
      std::vector<std::int64_t> first(rows.size());
      for (std::size_t r = 0; r < rows.size(); ++r) {
        const std::int64_t f = row_of[std::size_t(rows[r])];
        if (std::size_t(f) == r) row_of[std::size_t(rows[r])] = std::int64_t(distinct.size()), first[r] = -1, distinct.push_back(rows[r]);
        else first[r] = f;
      }
      std::vector<label_t> dn(distinct.size() * std::size_t(k), no_label);
      std::vector<typename G::T> dw(dn.size(), typename G::T(0));
      const shape::cell_lists cells = shape::cells_of(g.lab.data(), index_t(g.lab.size()), label_t(seed_slots.size()));
      distance_ratio_slots(policy, g, seed_slots, k, distinct, row_of, dn.data(), dw.data(), opt,
                           [&](label_t i) { return node_state(g, i, seed_slots[std::size_t(i)], cells); }, keep);
      for (std::size_t r = 0; r < rows.size(); ++r) {
        const std::size_t d = std::size_t(row_of[std::size_t(rows[r])]);
        std::copy(dn.begin() + std::ptrdiff_t(d * std::size_t(k)), dn.begin() + std::ptrdiff_t((d + 1) * std::size_t(k)),
                  node + r * std::size_t(k));
        std::copy(dw.begin() + std::ptrdiff_t(d * std::size_t(k)), dw.begin() + std::ptrdiff_t((d + 1) * std::size_t(k)),
                  weight + r * std::size_t(k));
      }
      break;
    }
    case shape_method::sibson:
    case shape_method::laplace:
      natural_neighbour_slots(policy, g, seed_slots.size(), opt.method == shape_method::laplace, k, rows, node, weight,
                              opt);
      break;
    default:
      throw std::invalid_argument("geovoronoi::shape_functions: unknown shape_method " +
                                  std::to_string(static_cast<int>(opt.method)));
  }
}

/// The seeds' slots.
template <class P, class T>
std::vector<index_t> seed_slots(const P& p, const node_diagram<T>& d) {
  std::vector<index_t> s;
  for (index_t c : d.seeds) s.push_back(p.slot_of_copy[c]);
  return s;
}

/// The fine voxel of each point: coordinates checked against the fine grid.
template <int Dim>
std::vector<index_t> fine_voxels_of(const grid<Dim>& fine, const std::vector<coord<Dim>>& pts) {
  std::vector<index_t> v;
  v.reserve(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!fine.contains(pts[i]))
      throw std::invalid_argument("geovoronoi::shape_functions_at: point " + std::to_string(i) + " at " +
                                  to_string<Dim>(pts[i]) + " lies outside the fine grid");
    v.push_back(fine.index(pts[i]));
  }
  return v;
}


/**
 * Distance Ratio after a cut from the kept searches before it (see update_shape_functions()). A node
 * runs its searches again when its seed is in a changed cell, when its support or frontier list (old)
 * holds a copy of a changed cell or a copy linked to one, or when its cell or a face neighbour of it
 * holds a copy whose key changed or that is new or gone (its label before or after). The other nodes'
 * searches are those of a full computation on the new grid: their balls hold no link whose weight or
 * existence changed, and their cells, bounds and frontiers read unchanged keys. Rows are merged again
 * where an affected node's support (old or new) reaches, and at copies whose key changed; the other
 * rows are the old ones. The kept lists are over slots; the slots of kept copies are renumbered.
 */
template <class Policy, class P, class T>
copy_weights<T> update_distance_ratio(const Policy& policy, const P& after, const branching_grid<P::dim, T, P::neighbours>& bgrid,
                                      const node_diagram<T>& bd, const node_diagram<T>& ad, const copy_weights<T>& bw,
                                      const shape_options& opt) {
  const auto& ag = after.grid_of();
  const auto m = map_copies(bgrid, ag);
  const auto& bw_state = *bw.update_state;
  const auto& bp = bgrid.walk_parts();
  const index_t bslots = index_t(bp.copy_of_slot.size());
  const index_t aslots = after.slots;
  const label_t nodes = label_t(ad.seeds.size());
  const int k = opt.max_nodes_per_voxel;
  // slot maps for kept copies (monotone: kept copies keep their order)
  std::vector<index_t> slot_after(std::size_t(bslots), -1);
  for (index_t s = 0; s < bslots; ++s) {
    const index_t a = bp.copy_of_slot[std::size_t(s)];
    if (a >= 0 && m.after_of[std::size_t(a)] >= 0) slot_after[std::size_t(s)] = after.slot_of_copy[m.after_of[std::size_t(a)]];
  }
  // marks over old slots: copies of changed cells and copies linked to them
  std::vector<char> near_change(std::size_t(bslots), 0);
  for (index_t c : m.changed)
    for (index_t a = bgrid.cell_begin()[std::size_t(c)]; a < bgrid.cell_begin()[std::size_t(c) + 1]; ++a) {
      near_change[std::size_t(bp.slot_of_copy[std::size_t(a)])] = 1;
      for (index_t i = bgrid.link_begin()[std::size_t(a)]; i < bgrid.link_begin()[std::size_t(a) + 1]; ++i)
        near_change[std::size_t(bp.slot_of_copy[std::size_t(bgrid.link_copy()[std::size_t(i)])])] = 1;
    }
  // the same after the cut, on the new slots (links of new copies into kept ones)
  for (index_t c : m.changed)
    for (index_t a = ag.cell_begin()[std::size_t(c)]; a < ag.cell_begin()[std::size_t(c) + 1]; ++a)
      for (index_t i = ag.link_begin()[std::size_t(a)]; i < ag.link_begin()[std::size_t(a) + 1]; ++i) {
        const index_t o = m.before_of[std::size_t(ag.link_copy()[std::size_t(i)])];
        if (o >= 0) near_change[std::size_t(bp.slot_of_copy[std::size_t(o)])] = 1;
      }
  // affected nodes
  std::vector<char> affected(std::size_t(nodes), 0);
  auto mark = [&](label_t l) {
    if (l >= 0) affected[std::size_t(l)] = 1;
  };
  for (label_t i = 0; i < nodes; ++i)
    if (m.before_of[std::size_t(ad.seeds[std::size_t(i)])] < 0 ||
        bd.seeds[std::size_t(i)] != m.before_of[std::size_t(ad.seeds[std::size_t(i)])])
      affected[std::size_t(i)] = 1;
  const copy_graph<P> g(after, ad);
  const search::walker_t<P> awalk(after);
  // copies whose key changed, new or gone: their labels and their face neighbours' labels
  std::vector<index_t> rows_changed;  // after copies
  auto mark_around_after = [&](index_t b) {
    mark(ad.label[std::size_t(b)]);
    g.for_each_face_link(after.slot_of_copy[b], [&](int, index_t u, const auto&) { mark(g.lab[std::size_t(u)]); });
  };
  for (index_t b = 0; b < ag.copies(); ++b) {
    const index_t a = m.before_of[std::size_t(b)];
    if (a >= 0 && bd.distance[std::size_t(a)] == ad.distance[std::size_t(b)] && bd.label[std::size_t(a)] == ad.label[std::size_t(b)])
      continue;
    rows_changed.push_back(b);
    mark_around_after(b);
    if (a >= 0) mark(bd.label[std::size_t(a)]);
  }
  // the old side: gone copies and changed keys, through the old face links
  {
    const auto bfaces = search::faces_of(typename copy_graph<P>::coarse_view{bgrid.coarse(), after.edges});
    std::array<int, 32> face_of{};
    face_of.fill(-1);
    for (std::size_t f = 0; f < bfaces.size(); ++f) face_of[std::size_t(bfaces[f].edge)] = int(f);
    for (index_t a = 0; a < bgrid.copies(); ++a) {
      const index_t b = m.after_of[std::size_t(a)];
      if (b >= 0 && bd.distance[std::size_t(a)] == ad.distance[std::size_t(b)] && bd.label[std::size_t(a)] == ad.label[std::size_t(b)])
        continue;
      mark(bd.label[std::size_t(a)]);
      for (index_t i = bgrid.link_begin()[std::size_t(a)]; i < bgrid.link_begin()[std::size_t(a) + 1]; ++i)
        if (face_of[bgrid.link_dir()[std::size_t(i)]] >= 0) mark(bd.label[std::size_t(bgrid.link_copy()[std::size_t(i)])]);
    }
  }
  for (label_t i = 0; i < nodes; ++i) {
    if (affected[std::size_t(i)]) continue;
    const auto& s = bw_state.nodes[std::size_t(i)];
    for (index_t v : *s.support)
      if (near_change[std::size_t(v)]) {
        affected[std::size_t(i)] = 1;
        break;
      }
    if (!affected[std::size_t(i)])
      for (index_t v : *s.frontier)
        if (near_change[std::size_t(v)]) {
          affected[std::size_t(i)] = 1;
          break;
        }
  }
  // rows to merge again: affected nodes' old supports (kept copies) and new ones, changed keys
  std::vector<std::int64_t> row_of(std::size_t(aslots), -1);
  std::vector<index_t> rows;
  auto add_row = [&](index_t slot) {
    if (slot >= 0 && row_of[std::size_t(slot)] < 0) row_of[std::size_t(slot)] = std::int64_t(rows.size()), rows.push_back(slot);
  };
  for (index_t b : rows_changed) add_row(after.slot_of_copy[b]);
  for (label_t i = 0; i < nodes; ++i)
    if (affected[std::size_t(i)])
      for (index_t v : *bw_state.nodes[std::size_t(i)].support) add_row(slot_after[std::size_t(v)]);
  // the new state: unaffected nodes' lists on the new slots, affected nodes' searches again
  auto remap = [&](const std::shared_ptr<const std::vector<index_t>>& l) {
    bool same = true;
    for (index_t v : *l)
      if (slot_after[std::size_t(v)] != v) {
        same = false;
        break;
      }
    if (same) return l;
    std::vector<index_t> out(l->size());
    for (std::size_t j = 0; j < l->size(); ++j) out[j] = slot_after[std::size_t((*l)[j])];
    return shape::share(std::move(out));
  };
  const shape::cell_lists cells = shape::cells_of(g.lab.data(), index_t(g.lab.size()), nodes);
  std::vector<index_t> seed_slot(static_cast<std::size_t>(nodes));
  for (label_t i = 0; i < nodes; ++i) seed_slot[std::size_t(i)] = after.slot_of_copy[ad.seeds[std::size_t(i)]];
  auto state = std::make_shared<shape_state<T>>();
  state->seeds = seed_slot;
  std::vector<shape::dr_node<T>> fresh(static_cast<std::size_t>(nodes));
  std::vector<label_t> todo;
  for (label_t i = 0; i < nodes; ++i)
    if (affected[std::size_t(i)]) todo.push_back(i);
  host_parallel_for(policy, index_t(todo.size()), [&](index_t t) {
    const label_t i = todo[std::size_t(t)];
    fresh[std::size_t(i)] = node_state(g, i, seed_slot[std::size_t(i)], cells);
  });
  for (label_t i : todo)
    for (index_t v : *fresh[std::size_t(i)].support) add_row(v);
  // merge the rows' raw weights, node by node in order, as a full computation does
  std::vector<label_t> rn(rows.size() * std::size_t(k), no_label);
  std::vector<T> rw(rn.size(), T(0));
  std::vector<double> raw(rn.size(), 0.0);
  state->nodes.resize(std::size_t(nodes));
  for (label_t i = 0; i < nodes; ++i) {
    shape::dr_node<T> s;
    if (affected[std::size_t(i)]) {
      s = std::move(fresh[std::size_t(i)]);
    } else {
      const auto& o = bw_state.nodes[std::size_t(i)];
      s = shape::dr_node<T>{o.dmax, remap(o.support), o.di, remap(o.frontier), o.db};
    }
    shape::node_raw_weights(s, g.lab.data(), i, [&](index_t x, double wx) {
      const std::int64_t r = row_of[std::size_t(x)];
      if (r >= 0)
        shape::insert_slot(rn.data() + std::size_t(r) * std::size_t(k), raw.data() + std::size_t(r) * std::size_t(k), k, i, wx);
    });
    state->nodes[std::size_t(i)] = std::move(s);
  }
  std::vector<shape::candidate> cand;
  copy_weights<T> w;
  w.copies = ag.copies();
  w.k = k;
  w.nodes = std::size_t(nodes);
  w.node.assign(std::size_t(w.copies) * std::size_t(k), no_label);
  w.weight.assign(w.node.size(), T(0));
  for (index_t b = 0; b < ag.copies(); ++b) {
    const index_t s = after.slot_of_copy[b];
    const auto at = std::size_t(b) * std::size_t(k);
    const std::int64_t r = row_of[std::size_t(s)];
    if (r >= 0) {
      const auto rat = std::size_t(r) * std::size_t(k);
      shape::finish_row(g.lab[std::size_t(s)], g.dist[std::size_t(s)], k, rn.data() + rat, rw.data() + rat, raw.data() + rat, cand);
      std::copy(rn.begin() + std::ptrdiff_t(rat), rn.begin() + std::ptrdiff_t(rat) + k, w.node.begin() + std::ptrdiff_t(at));
      std::copy(rw.begin() + std::ptrdiff_t(rat), rw.begin() + std::ptrdiff_t(rat) + k, w.weight.begin() + std::ptrdiff_t(at));
    } else {
      const auto bat = std::size_t(m.before_of[std::size_t(b)]) * std::size_t(k);
      std::copy(bw.node.begin() + std::ptrdiff_t(bat), bw.node.begin() + std::ptrdiff_t(bat) + k, w.node.begin() + std::ptrdiff_t(at));
      std::copy(bw.weight.begin() + std::ptrdiff_t(bat), bw.weight.begin() + std::ptrdiff_t(bat) + k, w.weight.begin() + std::ptrdiff_t(at));
    }
  }
  (void)awalk;
  if (opt.keep_update_state) w.update_state = std::move(state);
  return w;
}

}  // namespace detail::branching

template <class T>
Eigen::SparseMatrix<T, Eigen::RowMajor> copy_weights<T>::to_sparse_matrix() const {
  return detail::shape::slots_to_sparse(std::size_t(copies), k, nodes, node, weight,
                                        "geovoronoi::copy_weights::to_sparse_matrix");
}

template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> shape_functions(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                const node_diagram<T>& d, const shape_options& opt) {
  detail::require_policy<Policy>();
  detail::branching::validate(p, d, opt);
  using P = branching_problem<T, Dim, Metric, N>;
  const auto& bg = p.grid_of();
  copy_weights<T> w;
  w.copies = bg.copies();
  w.k = opt.max_nodes_per_voxel;
  w.nodes = d.seeds.size();
  w.node.assign(std::size_t(w.copies) * std::size_t(w.k), no_label);
  w.weight.assign(w.node.size(), T(0));
  const detail::branching::copy_graph<P> g(p, d);
  std::vector<index_t> rows(std::size_t(w.copies));
  for (index_t a = 0; a < w.copies; ++a) rows[std::size_t(a)] = p.slot_of_copy[a];
  std::shared_ptr<detail::branching::shape_state<T>> keep;
  if (opt.keep_update_state && opt.method == shape_method::distance_ratio) {
    keep = std::make_shared<detail::branching::shape_state<T>>();
    keep->seeds = detail::branching::seed_slots(p, d);
  }
  detail::with_threads(policy, opt.threads, [&] {
    detail::branching::rows_of(policy, g, detail::branching::seed_slots(p, d), opt, rows, w.node.data(),
                               w.weight.data(), keep ? &keep->nodes : nullptr);
    return 0;
  });
  w.update_state = std::move(keep);
  return w;
}

template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                    const node_diagram<T>& d,
                                    const std::vector<coord<branching_problem<T, Dim, Metric, N>::dim>>& fine_voxels,
                                    const shape_options& opt) {
  detail::require_policy<Policy>();
  detail::branching::validate(p, d, opt);
  using P = branching_problem<T, Dim, Metric, N>;
  const auto& bg = p.grid_of();
  point_weights<T> w;
  w.points = fine_voxels.size();
  w.k = opt.max_nodes_per_voxel;
  w.nodes = d.seeds.size();
  w.voxel = detail::branching::fine_voxels_of<Dim>(bg.fine(), fine_voxels);
  w.node.assign(w.points * std::size_t(w.k), no_label);
  w.weight.assign(w.node.size(), T(0));
  std::vector<index_t> rows;      // slots of the points in material
  std::vector<std::size_t> point;  // their points
  for (std::size_t i = 0; i < w.points; ++i) {
    const index_t c = bg.fine_copy()[w.voxel[i]];
    if (c < 0) continue;
    rows.push_back(p.slot_of_copy[c]);
    point.push_back(i);
  }
  if (rows.empty()) return w;
  const detail::branching::copy_graph<P> g(p, d);
  std::vector<label_t> node(rows.size() * std::size_t(w.k), no_label);
  std::vector<T> weight(node.size(), T(0));
  detail::with_threads(policy, opt.threads, [&] {
    detail::branching::rows_of(policy, g, detail::branching::seed_slots(p, d), opt, rows, node.data(), weight.data(),
                               nullptr);
    return 0;
  });
  const std::size_t k = std::size_t(w.k);
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t s = 0; s < k; ++s) {
      w.node[point[r] * k + s] = node[r * k + s];
      w.weight[point[r] * k + s] = weight[r * k + s];
    }
  return w;
}

template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                    const node_diagram<T>& d,
                                    const std::vector<point<branching_problem<T, Dim, Metric, N>::dim>>& world,
                                    const shape_options& opt) {
  detail::require_policy<Policy>();
  return shape_functions_at(policy, p, d, detail::shape::nearest_voxels(p.grid_of().fine(), world), opt);
}

template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const copy_weights<T>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values) {
  return detail::shape::interpolate_rows(w.node, w.weight, w.k, w.nodes, w.copies, "copies", nodal_values);
}

template <int Dim, class T, int N>
shape_weights<T, Dim> paint_fine(const branching_grid<Dim, T, N>& bg, const copy_weights<T>& w) {
  if (w.copies != bg.copies() || w.k < 0 || w.node.size() != std::size_t(w.copies) * std::size_t(w.k) ||
      w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::paint_fine: the weights have " + std::to_string(w.copies) +
                                " rows but the branching grid has " + std::to_string(bg.copies()) + " copies");
  shape_weights<T, Dim> out;
  out.geometry = bg.fine();
  out.k = w.k;
  out.nodes = w.nodes;
  const std::size_t k = std::size_t(w.k);
  out.node.assign(std::size_t(bg.fine().size()) * k, no_label);
  out.weight.assign(out.node.size(), T(0));
  const index_t* fc = bg.fine_copy().data();
  for (index_t v = 0; v < bg.fine().size(); ++v)
    if (fc[v] >= 0)
      for (std::size_t s = 0; s < k; ++s) {
        out.node[std::size_t(v) * k + s] = w.node[std::size_t(fc[v]) * k + s];
        out.weight[std::size_t(v) * k + s] = w.weight[std::size_t(fc[v]) * k + s];
      }
  return out;
}

template <class T, int Dim, int N>
branching_grid<Dim, T, N> make_branching_grid(const image<T, Dim>& fine, int factor, connectivity<N>,
                                              const cut_set<Dim>& cut, const branching_options& opt) {
  return branching_grid<Dim, T, N>(detail::branching::build<Dim, T, N>(
      image_view<const T, Dim>(fine.geometry(), fine.data()), factor, opt.reduction, &cut));
}

template <class Policy, class T, int Dim, class Metric, int N, class Seeds>
branching_diagram<T> update(const Policy&, const branching_problem<T, Dim, Metric, N>& after,
                            const branching_grid<Dim, T, N>& before_grid, const branching_diagram<T>& before,
                            const Seeds& seeds, update_stats* stats) {
  detail::require_policy<Policy>();
  const auto m = detail::branching::map_copies(before_grid, after.grid_of());
  const auto before_problem = make_problem(before_grid, after.metric);
  std::vector<index_t> s;
  for (const auto& c : seeds) {
    const std::size_t i = s.size();
    if (i >= before.seeds.size() || detail::branching::seed_copy(before_problem, c, i) != before.seeds[i])
      throw std::invalid_argument("geovoronoi::update: seed " + std::to_string(i) +
                                  " is not the diagram's seed (give the seeds the diagram was solved with)");
    s.push_back(detail::branching::seed_copy(after, c, i));
  }
  if (s.size() != before.seeds.size())
    throw std::invalid_argument("geovoronoi::update: " + std::to_string(s.size()) + " seeds given, the diagram has " +
                                std::to_string(before.seeds.size()));
  std::vector<index_t> sorted = s;
  std::sort(sorted.begin(), sorted.end());
  if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
    throw std::invalid_argument("geovoronoi::update: two seeds lie in the same copy of the grid after the cut");
  update_stats st;
  auto d = detail::branching::update_diagram(after, before_grid, before, s, m, st);
  if (stats) *stats = st;
  return d;
}

template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> update_shape_functions(const Policy& policy, const branching_problem<T, Dim, Metric, N>& after,
                                       const branching_grid<Dim, T, N>& before_grid,
                                       const branching_diagram<T>& before_diagram,
                                       const branching_diagram<T>& after_diagram,
                                       const copy_weights<T>& before_weights, const shape_options& opt) {
  detail::require_policy<Policy>();
  detail::branching::validate(after, after_diagram, opt);
  if (before_weights.copies != before_grid.copies() || before_weights.k != opt.max_nodes_per_voxel ||
      before_weights.nodes != after_diagram.seeds.size() ||
      index_t(before_diagram.label.size()) != before_grid.copies())
    throw std::invalid_argument("geovoronoi::update_shape_functions: the weights or the diagram before do not belong "
                                "to the grid before the cut (or were computed with another K or node list)");
  if (opt.method != shape_method::distance_ratio || !before_weights.update_state)
    return shape_functions(policy, after, after_diagram, opt);
  using P = branching_problem<T, Dim, Metric, N>;
  copy_weights<T> w;
  detail::with_threads(policy, opt.threads, [&] {
    w = detail::branching::update_distance_ratio(policy, after, before_grid, before_diagram, after_diagram,
                                                 before_weights, opt);
    return 0;
  });
  (void)sizeof(P);
  return w;
}

}  // namespace geovoronoi

#pragma once
// The update of a branching grid's diagram and Distance Ratio weights after a cut of its fine image
// (branching_shape.hpp's update() and update_shape_functions()).
//
// The grid after the cut differs from the grid before in the cells the cut crossed: their copies are
// split, renumbered, re-weighed. A cell is "changed" when its copies or their links differ in anything
// that does not depend on numbering (each copy's lowest fine voxel, voxel count, stiffness, and its
// links as (lowest fine voxel of the other copy, direction)); the copies of the other cells are "kept"
// and map one to one, in order. The argument of update.hpp then holds on the copy graph: a kept copy
// whose shortest-path tree chain holds no copy of a changed cell keeps a key that a path of the new
// graph still realises (the chain's links and stiffnesses are unchanged), an upper bound; the other
// kept copies and the changed cells' copies are solved again by the shared engine, seeded by the
// valid copies next to them and by the seeds in changed cells, and a key may be lowered anywhere (a
// split copy's stiffness changes, so a path through it may get shorter). Parents are recomputed with
// the library's rule wherever a key or an incident link changed, and next to it.

#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/change.hpp>
#include <geovoronoi/detail/search/engine.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/detail/search/parents.hpp>
#include <geovoronoi/detail/search/radix_heap.hpp>

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi::detail::branching {

/// How the copies of two branching grids of one fine image (before and after a cut) correspond.
struct copy_map {
  std::vector<char> changed_cell;     // per cell
  std::vector<index_t> after_of;      // per copy before: its copy after, -1 in a changed cell
  std::vector<index_t> before_of;     // per copy after: its copy before, -1 in a changed cell
  std::vector<index_t> changed;       // the changed cells
};

template <int Dim, class T, int N>
copy_map map_copies(const branching_grid<Dim, T, N>& a, const branching_grid<Dim, T, N>& b) {
  if (!(a.fine() == b.fine()) || a.factor() != b.factor())
    throw std::invalid_argument("geovoronoi::update: the grids before and after the cut differ in their fine grid or "
                                "factor");
  const index_t cells = a.coarse().size();
  copy_map m;
  m.changed_cell.assign(std::size_t(cells), 0);
  m.after_of.assign(std::size_t(a.copies()), -1);
  m.before_of.assign(std::size_t(b.copies()), -1);
  auto same_copy = [&](index_t x, index_t y) {
    const auto ux = std::size_t(x), uy = std::size_t(y);
    if (a.copy_voxel()[ux] != b.copy_voxel()[uy] || a.voxel_count()[ux] != b.voxel_count()[uy]) return false;
    if (!(a.stiffness()[ux] == b.stiffness()[uy])) return false;
    const index_t la = a.link_begin()[ux], ea = a.link_begin()[ux + 1];
    const index_t lb = b.link_begin()[uy], eb = b.link_begin()[uy + 1];
    if (ea - la != eb - lb) return false;
    for (index_t i = 0; i < ea - la; ++i) {
      const auto ia = std::size_t(la + i), ib = std::size_t(lb + i);
      if (a.link_dir()[ia] != b.link_dir()[ib] ||
          a.copy_voxel()[std::size_t(a.link_copy()[ia])] != b.copy_voxel()[std::size_t(b.link_copy()[ib])])
        return false;
    }
    return true;
  };
  for (index_t c = 0; c < cells; ++c) {
    const index_t a0 = a.cell_begin()[std::size_t(c)], a1 = a.cell_begin()[std::size_t(c) + 1];
    const index_t b0 = b.cell_begin()[std::size_t(c)], b1 = b.cell_begin()[std::size_t(c) + 1];
    bool same = a1 - a0 == b1 - b0;
    for (index_t i = 0; same && i < a1 - a0; ++i) same = same_copy(a0 + i, b0 + i);
    if (!same) {
      m.changed_cell[std::size_t(c)] = 1;
      m.changed.push_back(c);
      continue;
    }
    for (index_t i = 0; i < a1 - a0; ++i) m.after_of[std::size_t(a0 + i)] = b0 + i, m.before_of[std::size_t(b0 + i)] = a0 + i;
  }
  return m;
}

/// The diagram after the cut, per copy of the grid after (see the top of this file).
template <class P, class T>
node_diagram<T> update_diagram(const P& after, const branching_grid<P::dim, T, P::neighbours>& before_grid,
                               const node_diagram<T>& before, const std::vector<index_t>& seeds_after,
                               const copy_map& m, update_stats& st) {
  using kt = search::key_traits<T>;
  const auto& ag = after.grid_of();
  const index_t before_copies = before_grid.copies();
  const index_t copies = ag.copies();
  if (index_t(before.distance.size()) != before_copies || index_t(before.label.size()) != before_copies)
    throw std::invalid_argument("geovoronoi::update: the diagram does not belong to the grid before the cut");
  if (index_t(before.parent.size()) != before_copies)
    throw std::invalid_argument("geovoronoi::update: the diagram has no parents; compute it with "
                                "solve_options::with_parent (the update follows the shortest-path tree)");
  if (before.seeds.size() != seeds_after.size())
    throw std::invalid_argument("geovoronoi::update: the seeds are not the diagram's");
  // 1. invalid: the kept copies below a copy of a changed cell in the old tree (children found through
  // the old links), and every copy of a changed cell
  std::vector<char> invalid(std::size_t(before_copies), 0);
  std::vector<index_t> stack;
  for (index_t c : m.changed)
    for (index_t a = before_grid.cell_begin()[std::size_t(c)]; a < before_grid.cell_begin()[std::size_t(c) + 1]; ++a) {
      invalid[std::size_t(a)] = 1;
      stack.push_back(a);
      ++st.cut_tree_edges;
    }
  const auto& lb = before_grid.link_begin();
  const auto& lc = before_grid.link_copy();
  while (!stack.empty()) {
    const index_t x = stack.back();
    stack.pop_back();
    for (index_t i = lb[std::size_t(x)]; i < lb[std::size_t(x) + 1]; ++i) {
      const index_t y = lc[std::size_t(i)];
      if (!invalid[std::size_t(y)] && before.parent[std::size_t(y)] == x) {
        invalid[std::size_t(y)] = 1;
        ++st.invalidated;
        stack.push_back(y);
      }
    }
  }
  // 2. keys over the slots after: the valid copies' old keys, the rest unreached
  const index_t slots = after.slots;
  using node_t = search::walk_node<T>;
  std::vector<node_t> work(static_cast<std::size_t>(slots));
  const search::walker_t<P> walk(after);
  for (index_t s = 0; s < slots; ++s) {
    work[std::size_t(s)].set_key(kt::unreached);
    work[std::size_t(s)].field = after.field[s];
    work[std::size_t(s)].bits = walk.bits(s);
  }
  std::vector<char> fresh(std::size_t(copies), 0);  // after: a copy to solve again
  for (index_t b = 0; b < copies; ++b) {
    const index_t a = m.before_of[std::size_t(b)];
    if (a >= 0 && !invalid[std::size_t(a)]) {
      if (before.label[std::size_t(a)] != no_label)
        work[std::size_t(after.slot_of_copy[b])].set_key(kt::make(before.distance[std::size_t(a)], before.label[std::size_t(a)]));
    } else {
      fresh[std::size_t(b)] = 1;
    }
  }
  search::dense_keys<T, node_t> keys{work.data()};
  search::radix_heap<T> heap;
  // 3. seeds: those in fresh copies are sources again; the valid copies next to fresh ones seed the
  // re-solve with their keys
  for (std::size_t j = 0; j < seeds_after.size(); ++j) {
    const index_t s = after.slot_of_copy[seeds_after[j]];
    const auto k = kt::make(T(0), label_t(j));
    if (k < keys.get(s)) {
      keys.set(s, k);
      heap.push(k, s);
      ++st.sources_added;
    }
  }
  std::vector<char> queued(std::size_t(slots), 0);
  for (index_t b = 0; b < copies; ++b) {
    if (!fresh[std::size_t(b)]) continue;
    const index_t s = after.slot_of_copy[b];
    walk.for_each_neighbour(after, s, [&](int, index_t u) {
      const index_t cu = after.copy_of_slot[u];
      if (fresh[std::size_t(cu)] || queued[std::size_t(u)]) return;
      const auto k = keys.get(u);
      if (k == kt::unreached) return;
      queued[std::size_t(u)] = 1;
      heap.push(k, u);
      ++st.boundary;
    });
  }
  // 4. the re-solve: the shared engine, which may lower any key
  st.settled = search::run(after, keys, heap, [](index_t, T nd) { return nd < std::numeric_limits<T>::infinity(); });
  // 5. the diagram after, per copy; keys that changed
  node_diagram<T> d;
  d.distance.assign(std::size_t(copies), std::numeric_limits<T>::infinity());
  d.label.assign(std::size_t(copies), no_label);
  std::vector<T> sdist(std::size_t(slots), std::numeric_limits<T>::infinity());
  std::vector<label_t> slab(std::size_t(slots), no_label);
  for (index_t s = 0; s < slots; ++s) {
    const auto k = keys.get(s);
    if (k == kt::unreached) continue;
    sdist[std::size_t(s)] = kt::distance(k);
    slab[std::size_t(s)] = kt::label(k);
    const index_t c = after.copy_of_slot[s];
    d.distance[std::size_t(c)] = sdist[std::size_t(s)];
    d.label[std::size_t(c)] = slab[std::size_t(s)];
  }
  d.seeds = seeds_after;
  // 6. parents: mapped where nothing around a copy changed, else the library's rule
  std::vector<char> redo(std::size_t(copies), 0);
  for (index_t b = 0; b < copies; ++b) {
    const index_t a = m.before_of[std::size_t(b)];
    const bool moved = fresh[std::size_t(b)] || a < 0 || !(d.distance[std::size_t(b)] == before.distance[std::size_t(a)]) ||
                       d.label[std::size_t(b)] != before.label[std::size_t(a)];
    if (!moved) continue;
    if (a >= 0 && !fresh[std::size_t(b)]) ++st.lowered;
    redo[std::size_t(b)] = 1;
    walk.for_each_neighbour(after, after.slot_of_copy[b], [&](int, index_t u) { redo[std::size_t(after.copy_of_slot[u])] = 1; });
  }
  std::vector<char> is_seed(std::size_t(copies), 0);
  for (index_t s : seeds_after) is_seed[std::size_t(s)] = 1;
  d.parent.assign(std::size_t(copies), no_index);
  for (index_t b = 0; b < copies; ++b) {
    if (d.label[std::size_t(b)] == no_label || (is_seed[std::size_t(b)] && d.distance[std::size_t(b)] == T(0))) continue;
    if (redo[std::size_t(b)]) {
      ++st.reparented;
      const index_t ps = search::lowest_realiser(after, walk, sdist.data(), slab.data(), after.slot_of_copy[b]);
      d.parent[std::size_t(b)] = ps < 0 ? no_index : after.copy_of_slot[ps];
    } else {
      const index_t pa = before.parent[std::size_t(m.before_of[std::size_t(b)])];
      d.parent[std::size_t(b)] = pa < 0 ? no_index : m.after_of[std::size_t(pa)];
    }
  }
  return d;
}

}  // namespace geovoronoi::detail::branching

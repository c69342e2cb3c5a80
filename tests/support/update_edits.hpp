// Random edits for the incremental update (update.hpp): field edits (stiffer, softer, mixed, no-op,
// voxels leaving or entering the domain), carving, added voxels, node additions, removals, moves and
// reorders, and cuts, alone and together, in sequences. After each update the diagram must equal a
// full solve of the edited problem with the edited node list, bit for bit (distance bits, labels,
// parents, node list). Written once for any backend policy: the full solve runs on the same policy.
#pragma once

#include <doctest/doctest.h>

#include <geovoronoi/update.hpp>

#include "support/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <type_traits>

namespace gvtest {
inline bool edit_case_dbg = false;

/// A user metric that is not monotone in the field: a field value near 2 is the cheapest to leave.
struct wavy_cost {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T from, T to) const noexcept {
    return length * (T(0.25) + (from - T(2)) * (from - T(2))) / (T(0.5) + to);
  }
};

/// The metric's name in failure messages.
template <class Metric>
const char* metric_label() {
  namespace gv = geovoronoi;
  if constexpr (std::is_same_v<Metric, gv::min_stiffness>) return "min_stiffness";
  else if constexpr (std::is_same_v<Metric, gv::mean_stiffness>) return "mean_stiffness";
  else if constexpr (std::is_same_v<Metric, gv::mean_cost>) return "mean_cost";
  else if constexpr (std::is_same_v<Metric, gv::uniform>) return "uniform";
  else if constexpr (std::is_same_v<Metric, destination_cost>) return "destination_cost";
  else if constexpr (std::is_same_v<Metric, wavy_cost>) return "wavy_cost";
  else return "user metric";
}

/// Counters over all cases, so a run can show it was not vacuous.
struct edit_totals {
  std::size_t updates = 0, invalidated = 0, lowered = 0, sources = 0, removed = 0, repairs = 0;
};
inline edit_totals& totals() {
  static edit_totals t;
  return t;
}

template <class D>
void require_same_diagram(const D& a, const D& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.distance.size() == b.distance.size());
  REQUIRE(a.parent.size() == b.parent.size());
  CHECK(a.seeds == b.seeds);
  geovoronoi::index_t bad = -1;
  for (geovoronoi::index_t v = 0; v < a.distance.size() && bad < 0; ++v)
    if (bits(a.distance[v]) != bits(b.distance[v]) || a.label[v] != b.label[v] || a.parent[v] != b.parent[v]) bad = v;
  std::string where;
  if (bad >= 0)
    where = "first mismatch at voxel " + std::to_string(bad) + ": " + std::to_string(a.distance[bad]) + "/" +
            std::to_string(a.label[bad]) + "/" + std::to_string(a.parent[bad]) + " vs " +
            std::to_string(b.distance[bad]) + "/" + std::to_string(b.label[bad]) + "/" + std::to_string(b.parent[bad]);
  INFO(where);
  CHECK(bad < 0);
}

/// The default hook of edit_case: does nothing.
struct no_edit_hook {
  template <class... A>
  void operator()(const A&...) const noexcept {}
};

/// What one random step edits (bits): field values, carving, added voxels, node edits, cuts.
enum edit_kind : unsigned { field_edit = 1, carve_edit = 2, add_edit = 4, node_edits = 8, cut_edit = 16 };

/**
 * One random problem and `steps` random changes. `kinds` selects the edits (a mask of edit_kind;
 * each step draws a non-empty subset). `with_cuts` solves on a problem that carries cuts (and lets
 * steps add cuts). `hook(problem, d_before, d_after, change, what)` is called once on the first
 * diagram (d_before and d_after both that diagram, change null, what "start ...") and after every
 * update with the problem after the change, the diagrams before and after it (d_after the checked
 * update) and a pointer to the change; the problem is valid during the call only.
 */
template <class T, int Dim, class Metric, int N, class Policy, class Hook = no_edit_hook>
void edit_case(const Policy& policy, std::mt19937_64& rng, int trial, bool cost, int steps, unsigned kinds,
               bool with_cuts, Hook&& hook = Hook{}) {
  namespace gv = geovoronoi;
  using idx = gv::index_t;
  const auto g = random_grid<Dim>(rng, trial % 2 == 1);
  auto f = random_field<T>(rng, g.size(), trial % 3 != 2, trial % 4 == 0 ? 0.0 : 0.2, cost);
  const auto p0 = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds0 = random_seeds(rng, p0, 1 + int(rng() % 5));
  if (seeds0.empty()) return;
  gv::cut_set<Dim> all = with_cuts ? random_cuts(rng, g, gv::connectivity<N>{}, 0.08)
                                   : gv::cut_set<Dim>(g, gv::connectivity<N>{});
  gv::cut_table table(all);
  // the problems point at f (and at the current table), so they see every edit
  auto problem = [&] { return gv::make_problem(g, f, Metric{}, gv::connectivity<N>{}); };
  auto solve = [&](const std::vector<gv::coord<Dim>>& nodes) {
    if (with_cuts) return gv::voronoi(policy, gv::with_cuts(problem(), table), nodes, gv::solve_options{true});
    return gv::voronoi(policy, problem(), nodes, gv::solve_options{true});
  };
  auto d = solve(seeds0);
  const std::string name = "dim " + std::to_string(Dim) + " N " + std::to_string(N) + " " + metric_label<Metric>() +
                           (sizeof(T) == 4 ? " float" : " double") + (with_cuts ? " with cuts" : "") + " trial " + std::to_string(trial);
  if (with_cuts)
    hook(gv::with_cuts(problem(), table), d, d, static_cast<const gv::change<Dim>*>(nullptr), "start " + name);
  else
    hook(problem(), d, d, static_cast<const gv::change<Dim>*>(nullptr), "start " + name);
  std::uniform_real_distribution<double> u(0, 1);
  const T outside = cost ? T(-1) : T(0);
  auto is_node = [&](idx v) { return std::find(d.seeds.begin(), d.seeds.end(), v) != d.seeds.end(); };
  for (int s = 0; s < steps; ++s) {
    unsigned k = 0;
    while (k == 0) k = unsigned(rng()) & kinds;
    gv::change<Dim> c;
    // a random box of voxels to edit
    gv::coord<Dim> lo{}, ext{};
    for (int a = 0; a < Dim; ++a) {
      lo[a] = idx(rng() % std::uint64_t(g.extent(a)));
      ext[a] = 1 + idx(rng() % 3);
    }
    std::vector<idx> box;
    for (idx v = 0; v < g.size(); ++v) {
      const auto cv = g.coords(v);
      bool in = true;
      for (int a = 0; a < Dim; ++a) in = in && cv[a] >= lo[a] && cv[a] < lo[a] + ext[a];
      if (in) box.push_back(v);
    }
    const int mode = int(rng() % 4);  // field edits: 0 stiffer, 1 softer, 2 mixed / leave / enter, 3 no-op
    for (const idx v : box) {
      const bool in = gv::detail::inside<Metric>(f[std::size_t(v)]);
      const double r = u(rng);
      if ((k & field_edit) && r < 0.5) {
        T nv = f[std::size_t(v)];
        if (!in)
          nv = mode == 2 ? T(0.5 + 3 * u(rng)) : nv;  // masked voxels enter only in the mixed mode
        else if (mode == 0)
          nv = cost ? nv * T(0.5) : std::min(nv * T(2), T(50));
        else if (mode == 1)
          nv = cost ? std::min(nv * T(2), T(50)) : nv * T(0.5);
        else if (mode == 2)
          nv = u(rng) < 0.15 && !is_node(v) ? outside : T(0.25 + 4 * u(rng));
        f[std::size_t(v)] = nv;
        c.restiffened.push_back(v);
      } else if ((k & carve_edit) && r < 0.75 && in && !is_node(v)) {
        f[std::size_t(v)] = outside;
        c.carved.push_back(v);
      } else if ((k & add_edit) && !in) {
        f[std::size_t(v)] = T(0.25 + 4 * u(rng));
        c.added.push_back(v);
      }
    }
    std::vector<idx> nodes = d.seeds;
    if (k & node_edits) {
      std::vector<idx> free;
      for (idx v = 0; v < g.size(); ++v)
        if (gv::detail::inside<Metric>(f[std::size_t(v)]) && std::find(nodes.begin(), nodes.end(), v) == nodes.end())
          free.push_back(v);
      const int ne = 1 + int(rng() % 3);
      for (int e = 0; e < ne; ++e) {
        const int op = int(rng() % 4);  // add, remove, move, reorder (remove + add elsewhere)
        if ((op == 0 || op == 2) && !free.empty()) {
          const std::size_t fi = std::size_t(rng() % free.size());
          const idx v = free[fi];
          free.erase(free.begin() + std::ptrdiff_t(fi));
          if (op == 0) {
            const std::size_t at = u(rng) < 0.4 ? gv::node_edit<Dim>::append : std::size_t(rng() % (nodes.size() + 1));
            c.nodes.push_back(gv::node_edit<Dim>::add(g.coords(v), at));
            nodes.insert(nodes.begin() + std::ptrdiff_t(at == gv::node_edit<Dim>::append ? nodes.size() : at), v);
          } else {
            const std::size_t at = std::size_t(rng() % nodes.size());
            free.push_back(nodes[at]);
            c.nodes.push_back(gv::node_edit<Dim>::move(at, g.coords(v)));
            nodes[at] = v;
          }
        } else if (op == 1 && nodes.size() > 1) {
          const std::size_t at = std::size_t(rng() % nodes.size());
          free.push_back(nodes[at]);
          c.nodes.push_back(gv::node_edit<Dim>::remove(at));
          nodes.erase(nodes.begin() + std::ptrdiff_t(at));
        } else if (op == 3 && nodes.size() > 1) {
          const std::size_t from = std::size_t(rng() % nodes.size());
          const idx v = nodes[from];
          c.nodes.push_back(gv::node_edit<Dim>::remove(from));
          nodes.erase(nodes.begin() + std::ptrdiff_t(from));
          const std::size_t to = std::size_t(rng() % (nodes.size() + 1));
          c.nodes.push_back(gv::node_edit<Dim>::add(g.coords(v), to));
          nodes.insert(nodes.begin() + std::ptrdiff_t(to), v);
        }
      }
    }
    if (with_cuts && (k & cut_edit)) {
      auto added = random_cuts(rng, g, gv::connectivity<N>{}, 0.05);
      all.merge(added);
      c.cut = std::move(added);
    }
    gv::cut_table next(all);
    table = std::move(next);  // solve() and the problem after read the new table
    std::vector<gv::coord<Dim>> node_coords;
    for (const idx v : nodes) node_coords.push_back(g.coords(v));
    CHECK(gv::edited_nodes(g, d.seeds, c.nodes) == node_coords);
    const std::string what = name + " step " + std::to_string(s) + " kinds " + std::to_string(k) + " mode " +
                             std::to_string(mode) + " nodes " + std::to_string(c.nodes.size());
    gv::update_stats st;
    const auto updated = with_cuts ? gv::update(policy, gv::with_cuts(problem(), table), d, c, &st)
                                   : gv::update(policy, problem(), d, c, &st);
    const auto full = solve(node_coords);
    require_same_diagram(updated, full, what);
    if (edit_case_dbg) {
      std::string msg = what + " old seeds";
      for (auto v : d.seeds) msg += " " + std::to_string(v);
      msg += " edits";
      for (auto& x : c.nodes) msg += " [" + std::to_string(int(x.what)) + " " + std::to_string(x.position) + " " + gv::to_string<Dim>(x.voxel) + "]";
      msg += " new";
      for (auto v : nodes) msg += " " + std::to_string(v);
      MESSAGE(msg);
    }
    auto& t = totals();
    ++t.updates;
    t.invalidated += st.invalidated;
    t.lowered += st.lowered;
    t.sources += st.sources_added;
    t.removed += st.nodes_removed;
    t.repairs += st.repairs;
    if (with_cuts)
      hook(gv::with_cuts(problem(), table), d, updated, &c, what);
    else
      hook(problem(), d, updated, &c, what);
    d = updated;
  }
}

/// edit_case on every metric (`hook` as there, shared by all cases).
template <class T, int Dim, int N, class Policy, class Hook = no_edit_hook>
void edit_all_metrics(const Policy& policy, int trials, int steps, unsigned kinds, std::uint64_t seed = 0,
                      Hook&& hook = Hook{}) {
  namespace gv = geovoronoi;
  std::mt19937_64 rng(4242 + 31 * N + 100 * sizeof(T) + 7 * steps + kinds + seed);
  for (int t = 0; t < trials; ++t) {
    const bool cuts = t % 3 == 0;
    edit_case<T, Dim, gv::min_stiffness, N>(policy, rng, t, false, steps, kinds, cuts, hook);
    edit_case<T, Dim, gv::mean_stiffness, N>(policy, rng, t, false, steps, kinds, cuts, hook);
    edit_case<T, Dim, gv::mean_cost, N>(policy, rng, t, true, steps, kinds, cuts, hook);
    edit_case<T, Dim, destination_cost, N>(policy, rng, t, false, steps, kinds, cuts, hook);
    edit_case<T, Dim, wavy_cost, N>(policy, rng, t, false, steps, kinds, cuts, hook);
    edit_case<T, Dim, gv::uniform, N>(policy, rng, t, false, steps, kinds, cuts, hook);
  }
}

}  // namespace gvtest

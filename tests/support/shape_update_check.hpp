// Shape functions kept up to date along the random edit sequences of update_edits.hpp: a hook for
// edit_case that, at every step, updates weights of every method (Distance Ratio, Sibson, Laplace)
// with update_shape_functions(_in_place) and weights at random points with
// update_shape_functions_at(_in_place), then compares them bit for bit (nodes count, node and weight
// bits of every slot) with shape_functions / shape_functions_at on the problem after the change.
// The weights are kept across the steps of one case, so errors would accumulate. Written once for
// any backend policy: the full computation runs on the same policy.
#pragma once

#include <doctest/doctest.h>

#include <geovoronoi/shape_update.hpp>

#include "support/update_edits.hpp"

#include <array>
#include <cstddef>
#include <random>
#include <string>
#include <type_traits>
#include <vector>

namespace gvtest {

/// Counters over every shape update checked, so a run can show that it was not vacuous and that the
/// update recomputed fewer rows than a full computation.
struct shape_update_totals {
  std::size_t updates = 0;       // updates of voxel weights checked
  std::size_t point_updates = 0; // updates of point weights checked
  std::size_t partial = 0;       // voxel updates that recomputed strictly fewer rows than all
  std::size_t none = 0;          // voxel updates that recomputed no row
  std::size_t full = 0;          // voxel updates that reported stats.full
  std::size_t rows = 0, recomputed = 0, changed = 0;
  std::array<std::size_t, 3> per_method{};  // voxel updates per method
  std::array<std::size_t, 3> partial_per_method{};  // of which recomputed fewer rows than all
  std::size_t kept = 0;          // Distance Ratio updates of weights that keep the nodes' searches
  std::size_t kept_partial = 0;  // of which recomputed fewer rows than all (the searches repaired)
  std::size_t kept_node_edits = 0;  // of which repaired after node edits (nodes appended or moved)
};
inline shape_update_totals& shape_totals() {
  static shape_update_totals t;
  return t;
}

inline const char* method_name(geovoronoi::shape_method m) {
  return m == geovoronoi::shape_method::sibson    ? "sibson"
         : m == geovoronoi::shape_method::laplace ? "laplace"
                                                  : "distance_ratio";
}

/// Whether two weight arrays are the same: K, node count, every slot's node and weight bits.
template <class W>
bool same_weights(const W& a, const W& b) {
  if (a.k != b.k || a.nodes != b.nodes || a.node != b.node || a.weight.size() != b.weight.size()) return false;
  for (std::size_t i = 0; i < a.weight.size(); ++i)
    if (bits(a.weight[i]) != bits(b.weight[i])) return false;
  return true;
}

/// Checks that two weight arrays are the same; on a difference, names the first slot that differs.
template <class W>
void require_same_weights(const W& a, const W& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.k == b.k);
  CHECK(a.nodes == b.nodes);
  REQUIRE(a.node.size() == b.node.size());
  REQUIRE(a.weight.size() == b.weight.size());
  std::ptrdiff_t bad = -1;
  for (std::size_t i = 0; i < a.node.size() && bad < 0; ++i)
    if (a.node[i] != b.node[i] || bits(a.weight[i]) != bits(b.weight[i])) bad = std::ptrdiff_t(i);
  std::string where;
  if (bad >= 0) {
    const std::size_t row = std::size_t(bad) / std::size_t(a.k);
    where = "first mismatch at row " + std::to_string(row) + " slot " + std::to_string(std::size_t(bad) % std::size_t(a.k)) +
            ": updated";
    for (int s = 0; s < a.k; ++s)
      where += " " + std::to_string(a.node[row * std::size_t(a.k) + std::size_t(s)]) + ":" +
               std::to_string(a.weight[row * std::size_t(a.k) + std::size_t(s)]);
    where += " full";
    for (int s = 0; s < b.k; ++s)
      where += " " + std::to_string(b.node[row * std::size_t(b.k) + std::size_t(s)]) + ":" +
               std::to_string(b.weight[row * std::size_t(b.k) + std::size_t(s)]);
  }
  INFO(where);
  CHECK(bad < 0);
}

/// A readable account of a change (for failure messages).
template <int Dim>
std::string describe(const geovoronoi::change<Dim>& c) {
  auto list = [](const char* name, const std::vector<geovoronoi::index_t>& v) {
    std::string s = std::string(" ") + name + " {";
    for (const auto x : v) s += " " + std::to_string(x);
    return s + " }";
  };
  std::string s = list("carved", c.carved) + list("added", c.added) + list("restiffened", c.restiffened);
  s += " node edits {";
  for (const auto& e : c.nodes)
    s += " [" + std::to_string(int(e.what)) + " at " + std::to_string(e.position) + " " +
         geovoronoi::to_string<Dim>(e.voxel) + "]";
  s += " } cut edges " + std::to_string(c.cut ? c.cut->size() : 0);
  return s;
}

/**
 * The hook: per case (reset at "start"), weights of each method with K cycling through {1, 3, 4}
 * (the three methods get different K in one case, and every pair comes up over three cases; with
 * `all_k` every method runs with every K), and point weights of one method (cycling) at 1 to 8
 * random voxels, repeats and masked voxels included. The change goes to the update as a
 * geovoronoi::change, or, when it is only a cut or only a carving, now and then as the cut_set or the
 * carving itself.
 */
template <class T, int Dim, class Policy>
struct shape_tracker {
  Policy policy;
  bool all_k = false;
  std::mt19937_64 rng{12345};
  int cases = 0;
  struct slot {
    geovoronoi::shape_options opt;
    geovoronoi::shape_weights<T, Dim> w;
  };
  std::vector<slot> slots;
  geovoronoi::shape_options point_opt;
  std::vector<geovoronoi::coord<Dim>> points;
  geovoronoi::point_weights<T> pw;

  explicit shape_tracker(Policy p, bool every_k = false, std::uint64_t seed = 12345)
      : policy(p), all_k(every_k), rng(seed) {}

  template <class P, class D>
  void operator()(const P& p, const D& before, const D& after, const geovoronoi::change<Dim>* c,
                  const std::string& what) {
    namespace gv = geovoronoi;
    const gv::shape_method methods[] = {gv::shape_method::distance_ratio, gv::shape_method::sibson,
                                        gv::shape_method::laplace};
    const int ks[] = {1, 3, 4};
    if (!c) {  // a new case: weights of the first diagram
      slots.clear();
      for (int m = 0; m < 3; ++m)
        for (int j = 0; j < 3; ++j) {
          if (!all_k && j != (m + cases) % 3) continue;
          slot s;
          s.opt.method = methods[m];
          s.opt.max_nodes_per_voxel = ks[j];
          s.w = gv::shape_functions(policy, p, after, s.opt);
          slots.push_back(std::move(s));
        }
      {  // Distance Ratio keeping the nodes' searches with the weights (repaired by the updates)
        slot s;
        s.opt.method = gv::shape_method::distance_ratio;
        s.opt.max_nodes_per_voxel = ks[(cases + 1) % 3];
        s.opt.keep_update_state = true;
        s.w = gv::shape_functions(policy, p, after, s.opt);
        REQUIRE(s.w.update_state != nullptr);
        slots.push_back(std::move(s));
      }
      point_opt.method = methods[cases % 3];
      point_opt.max_nodes_per_voxel = ks[(cases / 3) % 3];
      points.clear();
      const int np = 1 + int(rng() % 8);
      for (int i = 0; i < np; ++i) {
        if (!points.empty() && rng() % 4 == 0)
          points.push_back(points[std::size_t(rng() % points.size())]);  // a repeat
        else
          points.push_back(p.geometry.coords(gv::index_t(rng() % std::uint64_t(p.geometry.size()))));
      }
      pw = gv::shape_functions_at(policy, p, after, points, point_opt);
      ++cases;
      return;
    }
    const bool cut_only = c->cut && c->carved.empty() && c->added.empty() && c->restiffened.empty() && c->nodes.empty();
    const bool carve_only = !c->cut && c->added.empty() && c->restiffened.empty() && c->nodes.empty();
    const int form = int(rng() % 3);  // 0: the change itself; 1: cut_set / carving when it is only that
    auto update = [&](auto& w, const gv::shape_options& opt, bool in_place) {
      gv::shape_update_stats s;
      auto run = [&](const auto& ch) {
        if constexpr (std::is_same_v<std::decay_t<decltype(w)>, gv::point_weights<T>>) {
          if (in_place)
            s = gv::update_shape_functions_at_in_place(policy, p, before, after, w, ch, opt);
          else
            w = gv::update_shape_functions_at(policy, p, before, after, w, ch, opt, &s);
        } else {
          if (in_place)
            s = gv::update_shape_functions_in_place(policy, p, before, after, w, ch, opt);
          else
            w = gv::update_shape_functions(policy, p, before, after, w, ch, opt, &s);
        }
      };
      if (form == 1 && cut_only)
        run(*c->cut);
      else if (form == 1 && carve_only)
        run(gv::carving{c->carved});
      else
        run(*c);
      return s;
    };
    auto& t = shape_totals();
    for (auto& sl : slots) {
      const std::string id = what + " method " + method_name(sl.opt.method) + (sl.opt.keep_update_state ? " (kept)" : "") +
                             " K " + std::to_string(sl.opt.max_nodes_per_voxel);
      const auto s = update(sl.w, sl.opt, t.updates % 2 == 0);
      const auto full = gv::shape_functions(policy, p, after, sl.opt);
      if (!same_weights(sl.w, full)) {
        require_same_weights(sl.w, full, id + describe(*c));
        sl.w = full;  // go on from the right weights, so one error is reported once
      }
      INFO(id);
      CHECK(s.rows == std::size_t(p.geometry.size()));
      CHECK(s.recomputed <= s.rows);
      CHECK(s.changed <= s.recomputed);
      CHECK(s.region_voxels == s.recomputed);  // one row per voxel
      CHECK(s.changed_voxels <= s.region_voxels);  // X lies in R
      if (s.full) CHECK(s.recomputed == s.rows);
      if (sl.opt.keep_update_state) {  // the searches are renewed (repaired, or run again after node edits)
        CHECK(sl.w.update_state != nullptr);
        ++t.kept;
        t.kept_partial += s.recomputed < s.rows;
        t.kept_node_edits += !s.full && c && !c->nodes.empty();
      } else {
        CHECK(sl.w.update_state == nullptr);
      }
      ++t.updates;
      const std::size_t mi = sl.opt.method == gv::shape_method::distance_ratio ? 0
                             : sl.opt.method == gv::shape_method::sibson       ? 1
                                                                                : 2;
      ++t.per_method[mi];
      t.partial_per_method[mi] += s.recomputed < s.rows;
      t.partial += s.recomputed < s.rows;
      t.none += s.recomputed == 0;
      t.full += s.full;
      t.rows += s.rows;
      t.recomputed += s.recomputed;
      t.changed += s.changed;
    }
    const std::string id = what + " points method " + method_name(point_opt.method) + " K " +
                           std::to_string(point_opt.max_nodes_per_voxel) + " (" + std::to_string(points.size()) +
                           " points)";
    const auto s = update(pw, point_opt, t.point_updates % 2 == 1);
    const auto full = gv::shape_functions_at(policy, p, after, points, point_opt);
    if (!same_weights(pw, full) || pw.voxel != full.voxel) {
      require_same_weights(pw, full, id + describe(*c));
      CHECK(pw.voxel == full.voxel);
      pw = full;
    }
    INFO(id);
    CHECK(s.rows == points.size());
    CHECK(s.recomputed <= s.rows);
    CHECK(s.changed_voxels <= s.region_voxels);
    CHECK(s.changed <= s.recomputed);
    ++t.point_updates;
  }
};

/// The metric's flag for edit_case: whether its field is a cost (outside the domain: -1, not 0).
template <class Metric>
constexpr bool cost_metric = std::is_same_v<Metric, geovoronoi::mean_cost>;

/**
 * edit_case with the shape tracker on the metrics listed (not all six, as edit_all_metrics: every
 * metric instantiates every method's shape functions twice, with and without cuts, which makes a
 * heavy translation unit). One tracker per (T, Dim, N), its state reset by every case.
 */
template <class T, int Dim, int N, class... Metrics, class Policy>
void shape_edits(const Policy& policy, int trials, int steps, unsigned kinds, std::uint64_t seed, bool all_k) {
  std::mt19937_64 rng(9000 + 31 * N + 100 * sizeof(T) + 7 * steps + kinds + seed);
  shape_tracker<T, Dim, Policy> hook(policy, all_k, 100 + seed);
  for (int t = 0; t < trials; ++t) {
    const bool cuts = t % 3 == 0;
    (edit_case<T, Dim, Metrics, N>(policy, rng, t, cost_metric<Metrics>, steps, kinds, cuts, hook), ...);
  }
}

}  // namespace gvtest

// Shape functions after a change (shape_update.hpp) on the sequential backend: along random
// sequences of edits (cuts, carving, added voxels, field edits, node edits; every metric, 2D and 3D),
// the updated weights of every method, K 1, 3 and 4, and weights at random points equal a full
// computation on the changed problem bit for bit, step after step (shape_update_check.hpp). Then
// edits that change nothing, the statistics, and refused input. Thrust policies run the same random
// sequences from backend/update_thrust.cmake.
#include <doctest/doctest.h>

#include <geovoronoi/shape_update.hpp>

#include "support/shape_update_check.hpp"

#include <string>
#include <vector>

namespace {
namespace gv = geovoronoi;
using gvtest::shape_totals;

constexpr unsigned every_edit =
    gvtest::field_edit | gvtest::carve_edit | gvtest::add_edit | gvtest::node_edits | gvtest::cut_edit;

using gvtest::destination_cost;
using gvtest::wavy_cost;

void report(const char* what, const gvtest::shape_update_totals& before) {
  const auto& t = shape_totals();
  MESSAGE(std::string(what) << ": " << t.updates - before.updates << " voxel updates (distance ratio "
               << t.per_method[0] - before.per_method[0] << ", sibson " << t.per_method[1] - before.per_method[1]
               << ", laplace " << t.per_method[2] - before.per_method[2] << "), " << t.point_updates - before.point_updates
               << " point updates; " << t.partial - before.partial << " recomputed fewer rows than all, "
               << t.none - before.none << " none (distance ratio / sibson / laplace: "
               << t.partial_per_method[0] - before.partial_per_method[0] << " / "
               << t.partial_per_method[1] - before.partial_per_method[1] << " / "
               << t.partial_per_method[2] - before.partial_per_method[2] << " fewer), " << t.full - before.full << " full; rows recomputed "
               << t.recomputed - before.recomputed << " of " << t.rows - before.rows << ", changed "
               << t.changed - before.changed);
}

}  // namespace

TEST_CASE("shape update after random sequences of edits equals a full recompute, bit for bit, step after step") {
  const auto before = shape_totals();
  // every metric once or more (asymmetric: destination_cost, wavy_cost), 2D and 3D, float and double
  gvtest::shape_edits<float, 2, 8, gv::min_stiffness, destination_cost, gv::mean_cost>(gv::seq, 24, 5, every_edit, 14, true);
  gvtest::shape_edits<double, 2, 4, wavy_cost>(gv::seq, 30, 4, every_edit, 15, false);
  gvtest::shape_edits<float, 3, 26, gv::mean_stiffness, wavy_cost, gv::uniform>(gv::seq, 18, 4, every_edit, 18, true);
  gvtest::shape_edits<float, 3, 6, destination_cost>(gv::seq, 30, 4, every_edit, 17, false);
  report("combined edits", before);
  const auto& t = shape_totals();
  CHECK(t.updates - before.updates > 2000);
  for (int m = 0; m < 3; ++m) CHECK(t.per_method[std::size_t(m)] > before.per_method[std::size_t(m)] + 500);
  // the update is incremental: many updates recompute strictly fewer rows than a full computation,
  // and over the run far fewer rows are recomputed than there are
  CHECK(t.partial - before.partial > (t.updates - before.updates) / 4);
  for (std::size_t m = 0; m < 3; ++m) {
    INFO("method " << m << " (0 distance ratio, 1 sibson, 2 laplace)");
    CHECK(t.partial_per_method[m] - before.partial_per_method[m] > (t.per_method[m] - before.per_method[m]) / 10);
  }
  CHECK(t.recomputed - before.recomputed < (t.rows - before.rows) * 3 / 4);
  CHECK(t.changed - before.changed > 0);
  // Distance Ratio with its searches kept: checked as often, and mostly repaired, not recomputed
  MESSAGE("distance ratio with kept searches: " << t.kept - before.kept << " updates, "
                                                << t.kept_partial - before.kept_partial << " recomputed fewer rows than all");
  CHECK(t.kept - before.kept > 500);
  CHECK(t.kept_partial - before.kept_partial > (t.kept - before.kept) / 4);
  // node edits that keep every label (appended or moved nodes) repair the kept searches too (the
  // others recompute every row)
  MESSAGE("of which " << t.kept_node_edits - before.kept_node_edits << " repaired after nodes were appended or moved");
  CHECK(t.kept_node_edits - before.kept_node_edits > 20);
}

TEST_CASE("shape update after one kind of edit at a time (cuts, carving, added voxels, field, nodes)") {
  for (const unsigned kind : {unsigned(gvtest::cut_edit | gvtest::field_edit), unsigned(gvtest::carve_edit),
                              unsigned(gvtest::add_edit), unsigned(gvtest::field_edit), unsigned(gvtest::node_edits)}) {
    const auto before = shape_totals();
    gvtest::shape_edits<float, 2, 8, gv::min_stiffness, destination_cost, gv::mean_cost>(gv::seq, 10, 3, kind, 20 + kind,
                                                                                        false);
    gvtest::shape_edits<float, 3, 26, gv::mean_stiffness, wavy_cost, gv::uniform>(gv::seq, 6, 2, kind, 40 + kind, false);
    report(("kinds " + std::to_string(kind)).c_str(), before);
    CHECK(shape_totals().updates > before.updates);
  }
}

TEST_CASE("shape update: an empty change and a restiffening to the same values change nothing") {
  const gv::grid<3> g({9, 7, 5});
  std::vector<float> f(std::size_t(g.size()));
  for (gv::index_t v = 0; v < g.size(); ++v) f[std::size_t(v)] = 1.0f + float(g.coords(v)[0] % 3);
  f[std::size_t(g.index({4, 3, 2}))] = 0.0f;  // a masked voxel
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> nodes{{0, 0, 0}, {8, 6, 4}, {2, 5, 1}, {7, 1, 3}};
  const auto d = gv::voronoi(gv::seq, p, nodes, gv::solve_options{true});
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace})
    for (const int k : {1, 3, 4}) {
      INFO(std::string(gvtest::method_name(m)) << " K " << k);
      gv::shape_options o;
      o.method = m;
      o.max_nodes_per_voxel = k;
      const auto w = gv::shape_functions(gv::seq, p, d, o);
      // an empty change: nothing recomputed, nothing changed
      auto u = w;
      auto s = gv::update_shape_functions_in_place(gv::seq, p, d, d, u, gv::change<3>{}, o);
      CHECK(s.rows == std::size_t(g.size()));
      CHECK(s.recomputed == 0);
      CHECK(s.changed == 0);
      CHECK(s.changed_voxels == 0);
      CHECK_FALSE(s.full);
      gvtest::require_same_weights(u, w, "empty change");
      // an empty cut set and an empty carving: the same
      s = gv::update_shape_functions_in_place(gv::seq, p, d, d, u, gv::cut_set<3>(g, gv::connectivity<26>{}), o);
      CHECK(s.recomputed == 0);
      s = gv::update_shape_functions_in_place(gv::seq, p, d, d, u, gv::carving{}, o);
      CHECK(s.recomputed == 0);
      gvtest::require_same_weights(u, w, "empty cut and carving");
      // voxels restiffened to the values they had: the rows around them are recomputed, none changes
      gv::change<3> same;
      same.restiffened = {g.index({4, 3, 1}), g.index({5, 3, 2})};
      const auto d2 = gv::update(gv::seq, p, d, same);
      gvtest::require_same_diagram(d2, d, "no-op restiffening");
      s = gv::update_shape_functions_in_place(gv::seq, p, d, d2, u, same, o);
      if (k == 4) MESSAGE(std::string(gvtest::method_name(m)) << " K " << k << ": a no-op restiffening of 2 voxels recomputed " << s.recomputed
                                     << " of " << s.rows << " rows");
      CHECK(s.changed_voxels == 2);
      CHECK(s.recomputed >= 2);
      // Sibson and Laplace redo the queries that can reach the two voxels; Distance Ratio redoes the
      // supports of the nodes whose cells border them, which here cover the grid
      if (m != gv::shape_method::distance_ratio) CHECK(s.recomputed < s.rows);
      CHECK(s.changed == 0);
      gvtest::require_same_weights(u, w, "no-op restiffening");
      // the same at points (a repeat and the masked voxel included)
      const std::vector<gv::coord<3>> pts{{4, 3, 2}, {1, 1, 1}, {1, 1, 1}, {6, 2, 3}};
      const auto pw = gv::shape_functions_at(gv::seq, p, d, pts, o);
      gv::shape_update_stats ps;
      auto pu = gv::update_shape_functions_at(gv::seq, p, d, d, pw, gv::change<3>{}, o, &ps);
      CHECK(ps.rows == pts.size());
      CHECK(ps.recomputed == 0);
      gvtest::require_same_weights(pu, pw, "empty change at points");
      pu = gv::update_shape_functions_at(gv::seq, p, d, d2, pw, same, o, &ps);
      CHECK(ps.changed == 0);
      gvtest::require_same_weights(pu, pw, "no-op restiffening at points");
    }
}

TEST_CASE("shape update: the statistics count what was recomputed and what changed") {
  // a 2D strip of three nodes and a cut between the right two: only rows near the cut are redone
  const gv::grid<2> g({24, 6});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const std::vector<gv::coord<2>> nodes{{1, 3}, {12, 3}, {22, 2}};
  const auto d = gv::voronoi(gv::seq, p, nodes, gv::solve_options{true});
  gv::cut_builder<2> b(g, gv::connectivity<8>{});
  constexpr auto offs = gv::connectivity<8>::offsets();
  for (gv::index_t y = 0; y < 4; ++y)  // cut every edge crossing x = 17.5 for y < 4
    for (int k = 0; k < 8; ++k)
      if (offs[k][0] == 1) {
        const gv::coord<2> a{17, y}, c{18, y + offs[k][1]};
        if (g.contains(c) && c[1] < 4) b.insert(g.index(a), k);
      }
  const auto cut = b.build();
  const gv::cut_table table(cut);
  const auto after = gv::with_cuts(p, table);
  const auto d2 = gv::update(gv::seq, after, d, cut);
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    INFO(std::string(gvtest::method_name(m)));
    gv::shape_options o;
    o.method = m;
    const auto w = gv::shape_functions(gv::seq, p, d, o);
    gv::shape_update_stats s;
    const auto u = gv::update_shape_functions(gv::seq, after, d, d2, w, cut, o, &s);
    gvtest::require_same_weights(u, gv::shape_functions(gv::seq, after, d2, o), "cut");
    std::size_t differ = 0;
    for (gv::index_t v = 0; v < g.size(); ++v) {
      bool same = true;
      for (int k = 0; k < o.max_nodes_per_voxel; ++k) {
        const std::size_t at = std::size_t(v) * std::size_t(o.max_nodes_per_voxel) + std::size_t(k);
        same = same && u.node[at] == w.node[at] && gvtest::bits(u.weight[at]) == gvtest::bits(w.weight[at]);
      }
      differ += !same;
    }
    MESSAGE(std::string(gvtest::method_name(m)) << ": " << s.changed_voxels << " voxels changed, " << s.recomputed << " of "
                                   << s.rows << " rows recomputed, " << s.changed << " changed (" << differ
                                   << " differ), nodes affected " << s.nodes_affected);
    CHECK(s.changed == differ);  // no node edits: a changed row is a row that differs
    CHECK(s.changed > 0);
    CHECK(s.recomputed < s.rows);
    CHECK(s.changed_voxels > 0);
    if (m == gv::shape_method::distance_ratio) CHECK(s.nodes_affected >= 1);
  }
}

TEST_CASE("shape update: weights of another grid, a K mismatch and a wrong node list are refused") {
  const gv::grid<2> g({8, 6});
  std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {7, 5}}, gv::solve_options{true});
  gv::shape_options o;
  o.method = gv::shape_method::sibson;
  o.max_nodes_per_voxel = 3;
  const auto w = gv::shape_functions(gv::seq, p, d, o);
  const gv::change<2> none;
  auto refused = [&](auto&& call, const char* text) {
    INFO(text);
    CHECK_THROWS_WITH_AS(call(), doctest::Contains(text), std::invalid_argument);
  };
  // weights of another grid (same voxel count, other extents; and another size)
  {
    const gv::grid<2> g2({6, 8});
    const auto p2 = gv::make_problem(g2, f, gv::min_stiffness{}, gv::connectivity<8>{});
    const auto d2 = gv::voronoi(gv::seq, p2, std::vector<gv::coord<2>>{{0, 0}, {5, 7}}, gv::solve_options{true});
    const auto w2 = gv::shape_functions(gv::seq, p2, d2, o);
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w2, none, o); }, "computed on another grid");
    auto bad = w;
    bad.node.pop_back();
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, bad, none, o); }, "computed on another grid");
    // a diagram before of another grid
    refused([&] { return gv::update_shape_functions(gv::seq, p, d2, d, w, none, o); }, "another grid");
  }
  // K of the weights and of the options differ
  {
    auto o4 = o;
    o4.max_nodes_per_voxel = 4;
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w, none, o4); }, "K = 3 slots");
    const auto pw = gv::shape_functions_at(gv::seq, p, d, std::vector<gv::coord<2>>{{3, 3}}, o);
    refused([&] { return gv::update_shape_functions_at(gv::seq, p, d, d, pw, none, o4); }, "K = 3 slots");
  }
  // weights of another node count than the diagram before
  {
    const auto d3 = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {7, 5}, {3, 3}}, gv::solve_options{true});
    refused([&] { return gv::update_shape_functions(gv::seq, p, d3, d3, w, none, o); }, "the weights have 2 nodes");
  }
  // the diagram after is not the diagram before with the node edits applied
  {
    gv::change<2> add;
    add.nodes = {gv::node_edit<2>::add({3, 3})};
    const auto d_add = gv::update(gv::seq, p, d, add);
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w, add, o); }, "node edits applied");
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d_add, w, none, o); }, "node edits applied");
    gv::change<2> mv;
    mv.nodes = {gv::node_edit<2>::move(1, {6, 5})};
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d_add, w, mv, o); }, "node edits applied");
    const auto pw = gv::shape_functions_at(gv::seq, p, d, std::vector<gv::coord<2>>{{3, 3}}, o);
    refused([&] { return gv::update_shape_functions_at(gv::seq, p, d, d, pw, add, o); }, "node edits applied");
    // ... and with the right diagram it works
    const auto u = gv::update_shape_functions(gv::seq, p, d, d_add, w, add, o);
    gvtest::require_same_weights(u, gv::shape_functions(gv::seq, p, d_add, o), "add a node");
  }
  // a change naming a voxel outside the grid; a point outside the grid
  {
    gv::change<2> out;
    out.restiffened = {g.size()};
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w, out, o); }, "outside the grid");
    auto pw = gv::shape_functions_at(gv::seq, p, d, std::vector<gv::coord<2>>{{3, 3}}, o);
    pw.voxel[0] = -1;
    refused([&] { return gv::update_shape_functions_at(gv::seq, p, d, d, pw, none, o); }, "outside the grid");
    // a cut of another connectivity
    gv::cut_set<2> c4(g, gv::connectivity<4>{});
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w, c4, o); }, "another grid or connectivity");
  }
  // bad options, as shape_functions
  {
    auto o0 = o;
    o0.max_nodes_per_voxel = 0;
    refused([&] { return gv::update_shape_functions(gv::seq, p, d, d, w, none, o0); }, "max_nodes_per_voxel");
  }
}

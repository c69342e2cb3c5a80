// Tests of geovoronoi/shape_functions.hpp on the sequential backend (the shared suite in
// tests/backend/shape/suite.hpp; other backends instantiate it from tests/backend/shape_<backend>.cmake hooks).
#include <geovoronoi.hpp>

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#define GEOVORONOI_SHAPE_BACKEND_NAME "seq"
#define GEOVORONOI_SHAPE_POLICY() ::geovoronoi::seq
#include "backend/shape/suite.hpp"

// Backend-independent checks of the weight containers (seq only).

TEST_CASE("shape functions: interpolate and to_sparse_matrix refuse a node index beyond the node count") {
  namespace gv = geovoronoi;
  gv::shape_weights<float, 2> w;
  w.geometry = gv::grid<2>({2, 1});
  w.k = 2;
  w.nodes = 2;
  w.node = {0, 1, 1, -1};
  w.weight = {0.5f, 0.5f, 1.0f, 0.0f};
  const Eigen::MatrixXf values = Eigen::MatrixXf::Ones(2, 3);
  CHECK(gv::interpolate(w, values).rows() == 2);
  CHECK(w.to_sparse_matrix().nonZeros() == 3);
  w.node[2] = 1000000;  // would read far past nodal_values
  CHECK_THROWS_WITH_AS(gv::interpolate(w, values), doctest::Contains("row 1, slot 0 names node 1000000"),
                       std::invalid_argument);
  CHECK_THROWS_WITH_AS(w.to_sparse_matrix(), doctest::Contains("names node 1000000, but there are 2 nodes"),
                       std::invalid_argument);
  w.node[2] = 2;  // one past the end
  CHECK_THROWS_AS(gv::interpolate(w, values), std::invalid_argument);
  CHECK_THROWS_AS(w.to_sparse_matrix(), std::invalid_argument);
  w.node[2] = -7;
  CHECK_THROWS_AS(gv::interpolate(w, values), std::invalid_argument);
  CHECK_THROWS_AS(w.to_sparse_matrix(), std::invalid_argument);
  w.node = {1, 1, 0, -1};  // the same node twice in a row
  CHECK_THROWS_WITH_AS(w.to_sparse_matrix(), doctest::Contains("names node 1 in slots 0 and 1"), std::invalid_argument);
  gv::point_weights<float> p;
  p.points = 1;
  p.k = 1;
  p.nodes = 1;
  p.voxel = {0};
  p.node = {3};
  p.weight = {1.0f};
  CHECK_THROWS_WITH_AS(p.to_sparse_matrix(), doctest::Contains("names node 3"), std::invalid_argument);
}

TEST_CASE("shape functions: max_nodes_per_voxel is capped at max_nodes_per_voxel_limit") {
  namespace gv = geovoronoi;
  static_assert(gv::max_nodes_per_voxel_limit == 1024);
  const gv::grid<2> g({6, 5});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {5, 4}});
  gv::shape_options o;
  o.max_nodes_per_voxel = gv::max_nodes_per_voxel_limit + 1;
  CHECK_THROWS_WITH_AS(gv::shape_functions(gv::seq, p, d, o), doctest::Contains("between 1 and 1024"),
                       std::invalid_argument);
  o.max_nodes_per_voxel = 2000000000;  // 30 voxels x 2e9 slots would be a 480 GB allocation
  CHECK_THROWS_AS(gv::shape_functions(gv::seq, p, d, o), std::invalid_argument);
  CHECK_THROWS_AS(gv::shape_functions_at(gv::seq, p, d, std::vector<gv::coord<2>>{{1, 1}}, o), std::invalid_argument);
  o.max_nodes_per_voxel = gv::max_nodes_per_voxel_limit;
  const auto w = gv::shape_functions(gv::seq, p, d, o);
  CHECK(w.k == 1024);
}

TEST_CASE("shape functions: a node at geodesic distance 0 from another (zero-cost field) is named as such") {
  // under mean_cost a field of 0 joins every voxel at distance 0: voronoi() gives node 1 no cell (the
  // lower index wins the tie), which is the field's doing, not a diagram from elsewhere
  namespace gv = geovoronoi;
  const gv::grid<2> g({6, 5});
  const std::vector<float> f(std::size_t(g.size()), 0.0f);
  const auto p = gv::make_problem(g, f, gv::mean_cost{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {5, 4}});
  for (const auto m : {gv::shape_method::sibson, gv::shape_method::laplace, gv::shape_method::distance_ratio}) {
    gv::shape_options o;
    o.method = m;
    std::string what;
    try {
      (void)gv::shape_functions(gv::seq, p, d, o);
    } catch (const std::invalid_argument& e) {
      what = e.what();
    }
    INFO(what);
    CHECK(what.find("node 1 (voxel 29) is at geodesic distance 0 from node 0") != std::string::npos);
    CHECK(what.find("zero-weight") != std::string::npos);
    CHECK(what.find("use geovoronoi::voronoi") == std::string::npos);
  }
  // a diagram whose node voxel carries another label at a positive distance did not come from voronoi()
  const std::vector<float> ones(std::size_t(g.size()), 1.0f);
  auto e = gv::voronoi(gv::seq, gv::make_problem(g, ones, gv::mean_cost{}, gv::connectivity<8>{}),
                       std::vector<gv::coord<2>>{{0, 0}, {5, 4}});
  e.label[29] = 0;
  e.distance[29] = 1.0f;
  CHECK_THROWS_WITH_AS(gv::shape_functions(gv::seq, p, e, gv::shape_options{}),
                       doctest::Contains("use geovoronoi::voronoi"), std::invalid_argument);
}

TEST_CASE("shape functions: world points whose voxel is outside the grid are named as given") {
  namespace gv = geovoronoi;
  const gv::grid<2> g({6, 5});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {5, 4}});
  const std::vector<gv::point<2>> ok{{1.0, 1.0}}, far{{1.0, 1.0}, {1e30, 2.0}},
      nan{{std::numeric_limits<double>::quiet_NaN(), 1.0}};
  CHECK(gv::shape_functions_at(gv::seq, p, d, ok).points == 1);
  CHECK_THROWS_WITH_AS(gv::shape_functions_at(gv::seq, p, d, far),
                       doctest::Contains("point 1: world point (1e+30, 2) lies outside the grid"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(gv::shape_functions_at(gv::seq, p, d, nan), doctest::Contains("world point (nan, 1)"),
                       std::invalid_argument);
}

namespace {
// The progress tests' problem: a 16^3 gradient, 8 nodes, min_stiffness, 26 neighbours; calls
// test(problem, diagram).
template <class Test>
void with_gradient16(Test&& test) {
  namespace gv = geovoronoi;
  const gv::grid<3> g({16, 16, 16});
  const auto f = gv::phantom::gradient(g);
  const auto p = gv::make_problem(g, f.values(), gv::min_stiffness{}, gv::connectivity<26>{});
  std::vector<gv::coord<3>> seeds;
  for (gv::index_t i = 0; i < 8; ++i) seeds.push_back({2 + 5 * (i % 3), 2 + 5 * ((i / 3) % 3), 2 + 4 * (i % 4)});
  test(p, gv::voronoi(gv::seq, p, seeds));
}
}  // namespace

TEST_CASE("shape functions: Sibson progress moves while the single-owner step searches") {
  // The single-owner step (skip_single_owner_rows, on by default) runs restricted searches for the
  // queries its short search leaves undecided; the bar must move through them too, then go on from
  // where they left it, never back.
  namespace gv = geovoronoi;
  with_gradient16([](const auto& p, const auto& d) {
    gv::shape_options o;
    o.method = gv::shape_method::sibson;
    const auto plain = gv::shape_functions(gv::seq, p, d, o);
    std::vector<double> seen;
    gv::shape_stats stats;
    o.batch_size = 16;  // a report every 16 queries, in the restricted searches too
    o.tuning.single_owner_pops = 0;  // every query of the step decided by a restricted search
    o.stats = &stats;
    o.progress = [&](double x) {
      seen.push_back(x);
      return true;
    };
    const auto w = gv::shape_functions(gv::seq, p, d, o);
    CHECK(w.node == plain.node);  // reporting changes no result
    CHECK(w.weight == plain.weight);
    INFO("single-owner rows " << stats.single_owner_rows << ", of them after a restricted search "
                              << stats.single_owner_restricted << ", reports " << seen.size());
    REQUIRE(stats.single_owner_rows > 0);  // the step ran (with single_owner_pops = 0, only restricted searches)
    REQUIRE(seen.size() > 10);
    CHECK(std::is_sorted(seen.begin(), seen.end()));
    CHECK(seen.back() == 1.0);
    // the restricted searches report many times; at most the first report of each search run is 0
    CHECK(std::count(seen.begin(), seen.end(), 0.0) <= 2);
  });
}

TEST_CASE("shape functions: Sibson and Laplace progress moves while the sample queries run") {
  // The query loop runs the first search of every task first (the sample of its estimate): a quarter of
  // all queries with the lane search. Progress must move during it, not jump at its end.
  namespace gv = geovoronoi;
  with_gradient16([](const auto& p, const auto& d) {
    for (const auto m : {gv::shape_method::laplace, gv::shape_method::sibson}) {
      gv::shape_options o;
      o.method = m;
      o.skip_single_owner_rows = false;
      const auto plain = gv::shape_functions(gv::seq, p, d, o);
      std::vector<double> seen;
      o.batch_size = 64;  // a report every 64 queries: about 60 here
      o.progress = [&](double x) {
        seen.push_back(x);
        return true;
      };
      const auto w = gv::shape_functions(gv::seq, p, d, o);
      CHECK(w.node == plain.node);  // reporting changes no result
      CHECK(w.weight == plain.weight);
      REQUIRE(seen.size() > 10);
      CHECK(std::is_sorted(seen.begin(), seen.end()));
      CHECK(seen.back() == 1.0);
      const auto first_moved = std::find_if(seen.begin(), seen.end(), [](double x) { return x > 0.0; });
      REQUIRE(first_moved != seen.end());
      INFO("first fraction above 0: " << *first_moved);
      CHECK(*first_moved < 0.05);
      CHECK(std::count_if(seen.begin(), seen.end(), [](double x) { return x > 0.0 && x < 0.2; }) >= 3);
    }
  });
}

// Tests of geovoronoi/shape_functions.hpp on the sequential backend (the shared suite in
// tests/backend/shape/suite.hpp; other backends instantiate it from tests/backend/shape_<backend>.cmake hooks).
#include <geovoronoi.hpp>

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

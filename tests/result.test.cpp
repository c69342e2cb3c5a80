// Tests of geovoronoi/result.hpp: defaults of the options and result types, and query_cells'
// compressed-row bookkeeping (cell_size, append).

#include <doctest/doctest.h>

#include <geovoronoi/result.hpp>

#include <cmath>
#include <type_traits>

namespace {
namespace gv = geovoronoi;

static_assert(std::is_trivially_copyable_v<gv::source<float>>);
// solve_options holds the progress callback (a std::function), so it is copyable but not trivially:
// the front end hands backends the radius and a solve_control, never the options themselves.
static_assert(std::is_copy_constructible_v<gv::solve_options>);

TEST_CASE("result: defaults") {
  const gv::solve_options o;
  CHECK_FALSE(o.with_parent);
  CHECK(std::isinf(o.max_distance));
  CHECK(o.max_distance > 0);
  const gv::query_cells<float> q;
  CHECK(q.size() == 0);
  CHECK(q.offsets == std::vector<std::size_t>{0});
  const gv::query_cell<double> c;
  CHECK(c.query == gv::no_index);
  CHECK(c.size() == 0);
  const gv::sparse_solution<float> s;
  CHECK(s.size() == 0);
  const gv::diagram<float, 3> d;
  CHECK(d.geometry() == gv::grid<3>());
}

gv::query_cells<float> batch(std::vector<gv::index_t> queries, std::vector<std::vector<gv::index_t>> cells) {
  gv::query_cells<float> b;
  b.query = queries;
  for (const auto& c : cells) {
    for (gv::index_t v : c) {
      b.voxel.push_back(v);
      b.distance.push_back(float(v) / 2);
      b.owner.push_back(gv::label_t(v % 3));
    }
    b.offsets.push_back(b.voxel.size());
  }
  return b;
}

TEST_CASE("query_cells: cell sizes and appending batches") {
  auto a = batch({4, 9}, {{1, 2, 3}, {}});
  CHECK(a.size() == 2);
  CHECK(a.cell_size(0) == 3);
  CHECK(a.cell_size(1) == 0);
  const auto b = batch({7, 8, 0}, {{10, 11}, {12}, {}});
  a.append(b);
  CHECK(a.size() == 5);
  CHECK(a.query == std::vector<gv::index_t>{4, 9, 7, 8, 0});
  CHECK(a.offsets == std::vector<std::size_t>{0, 3, 3, 5, 6, 6});
  CHECK(a.voxel == std::vector<gv::index_t>{1, 2, 3, 10, 11, 12});
  CHECK(a.distance == std::vector<float>{0.5f, 1.0f, 1.5f, 5.0f, 5.5f, 6.0f});
  CHECK(a.owner == std::vector<gv::label_t>{1, 2, 0, 1, 2, 0});
  CHECK(a.cell_size(2) == 2);
  CHECK(a.cell_size(3) == 1);
  CHECK(a.cell_size(4) == 0);
  // appending to an empty batch gives the other batch; appending an empty batch changes nothing
  gv::query_cells<float> e;
  e.append(b);
  CHECK(e.offsets == b.offsets);
  CHECK(e.voxel == b.voxel);
  const auto before = a.offsets;
  a.append(gv::query_cells<float>{});
  CHECK(a.offsets == before);
  CHECK(a.size() == 5);
}

}  // namespace

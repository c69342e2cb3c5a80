// Tests of geovoronoi/precision.hpp (which values survive the conversion to float, when a problem
// may overflow float) and of the front end's checks of values that round to 0 in the distance type.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/io/read.hpp>

#include "support/core_helpers.hpp"
#include "support/io_util.hpp"

#include <limits>
#include <vector>

namespace {
namespace gv = geovoronoi;

TEST_CASE("fits_in: finite non-zero values must stay finite and non-zero") {
  CHECK(gv::fits_in<float>(1.0));
  CHECK(gv::fits_in<float>(-3e38));
  CHECK(gv::fits_in<float>(1e-40));  // subnormal, not 0
  CHECK_FALSE(gv::fits_in<float>(1e300));
  CHECK_FALSE(gv::fits_in<float>(-1e39));
  CHECK_FALSE(gv::fits_in<float>(1e-50));
  CHECK_FALSE(gv::fits_in<float>(-1e-46));
  // 0, infinities and NaN keep their kind
  CHECK(gv::fits_in<float>(0.0));
  CHECK(gv::fits_in<float>(std::numeric_limits<double>::infinity()));
  CHECK(gv::fits_in<float>(std::numeric_limits<double>::quiet_NaN()));
  CHECK(gv::fits_in<double>(1e300));
  CHECK(gv::normal_in<float>(1e-30));
  CHECK_FALSE(gv::normal_in<float>(1e-40));
}

TEST_CASE("needs_double: fields whose distances could overflow float, or whose values float cannot hold") {
  const gv::grid<3> g({12, 10, 6});
  std::vector<double> f(g.size(), 1.0);
  CHECK_FALSE(gv::needs_double(g, f.data(), f.size(), gv::min_stiffness{}, gv::connectivity<26>{}));
  CHECK(gv::distance_bound(g, f.data(), f.size(), gv::min_stiffness{}, gv::connectivity<26>{}) > 0);
  // stiffness 1e-38: an edge weighs up to sqrt(3) * 1e38, far beyond float over 720 voxels
  std::vector<double> soft(g.size(), 1e-38);
  CHECK(gv::needs_double(g, soft.data(), soft.size(), gv::min_stiffness{}, gv::connectivity<26>{}));
  CHECK_FALSE(gv::may_overflow<double>(g, soft.data(), soft.size(), gv::min_stiffness{}, gv::connectivity<26>{}));
  // cost 1e38 under mean_cost
  std::vector<double> cost(g.size(), 1e38);
  CHECK(gv::needs_double(g, cost.data(), cost.size(), gv::mean_cost{}, gv::connectivity<6>{}));
  // a value that float would round to 0 or +inf, even where the bound is small
  f[5] = 1e-50;
  CHECK(gv::needs_double(g, f.data(), f.size(), gv::uniform{}, gv::connectivity<6>{}));
  f[5] = 1e300;
  CHECK(gv::needs_double(g, f.data(), f.size(), gv::uniform{}, gv::connectivity<6>{}));
  // masked values do not count (stiffness rule: <= 0 is outside)
  f[5] = -1e300;
  CHECK_FALSE(gv::needs_double(g, f.data(), f.size(), gv::min_stiffness{}, gv::connectivity<6>{}));
  // spacing 1e38
  const gv::grid<3> wide({12, 10, 6}, {1e38, 1e38, 1e38});
  std::vector<double> one(wide.size(), 1.0);
  CHECK(gv::needs_double(wide, one.data(), one.size(), gv::min_stiffness{}, gv::connectivity<6>{}));
}

TEST_CASE("solvers: a positive max_distance that rounds to 0 in float is rejected") {
  const gv::grid<2> g({4, 3});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const std::vector<gv::coord<2>> seeds{{0, 0}};
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds, gv::solve_options{false, 1e-50}), "max_distance", "rounds to 0");
  // in double it is a valid (tiny) bound: only the seed
  const std::vector<double> fd(g.size(), 1.0);
  const auto pd = gv::make_problem(g, fd, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, pd, seeds, gv::solve_options{false, 1e-50});
  CHECK(d.label[0] == 0);
  CHECK(d.label[1] == gv::no_label);
  // 0, negative and beyond-range bounds keep their meaning
  CHECK_NOTHROW(gv::voronoi(gv::seq, p, seeds, gv::solve_options{false, 0.0}));
  CHECK_NOTHROW(gv::voronoi(gv::seq, p, seeds, gv::solve_options{false, 1e300}));
}

TEST_CASE("overflow_error is a geovoronoi::error") {
  const gv::overflow_error e("x");
  const gv::error& base = e;
  CHECK(std::string(base.what()) == "x");
}

TEST_CASE("overflow_error: double overflows too, and names double") {
  const gv::grid<2> g({40, 2});
  const std::vector<double> f(g.size(), 1e-307);  // every edge weighs 1e307: the 18th voxel is beyond 1.8e308
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{});
  std::string msg;
  try {
    (void)gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}});
  } catch (const gv::overflow_error& e) {
    msg = e.what();
  }
  CHECK(msg.find("overflows double") != std::string::npos);
  CHECK(msg.find("rescale") != std::string::npos);
  // computing in double is what it already does: the advice is to rescale, never "use double"
  CHECK(msg.find("compute in double") == std::string::npos);
  CHECK(msg.find("double field") == std::string::npos);
}

TEST_CASE("overflow_error: a double field of 5e-324 (an edge weight of +inf in double) advises rescaling only") {
  const gv::grid<2> g({4, 1});
  std::vector<double> f(g.size(), 1.0);
  f[2] = 5e-324;  // the smallest subnormal: 1 / 5e-324 is +inf
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{});
  std::string msg;
  try {
    (void)gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}});
  } catch (const gv::overflow_error& e) {
    msg = e.what();
  }
  INFO(msg);
  CHECK(msg.find("is +inf in double") != std::string::npos);
  CHECK(msg.find("rescale the field") != std::string::npos);
  CHECK(msg.find("compute in double") == std::string::npos);
  // in float the same advice names double first
  const std::vector<float> ff(g.size(), 1e-45f);
  const auto q = gv::make_problem(g, ff, gv::min_stiffness{}, gv::connectivity<4>{});
  msg.clear();
  try {
    (void)gv::voronoi(gv::seq, q, std::vector<gv::coord<2>>{{0, 0}});
  } catch (const gv::overflow_error& e) {
    msg = e.what();
  }
  CHECK(msg.find("compute in double") != std::string::npos);
}

TEST_CASE("seq: a cancelled bounded solve leaves the workspace ready for the next call") {
  const gv::grid<3> g({30, 30, 30});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::source<float>> src{{g.index({15, 15, 15}), 0.0f, 0}};
  gv::seq_workspace ws;
  int calls = 0;
  gv::solve_options stop;
  stop.progress = [&](double) { return ++calls < 2; };  // stop at the first tick inside the search
  CHECK_THROWS_AS(gv::bounded_solve(gv::seq(ws), p, src, 12.0f, stop), gv::cancelled);
  CHECK(calls == 2);
  const auto again = gv::bounded_solve(gv::seq(ws), p, src, 12.0f);
  const auto fresh = gv::bounded_solve(gv::seq, p, src, 12.0f);
  CHECK(again.voxel == fresh.voxel);
  CHECK(again.distance == fresh.distance);
  CHECK(again.label == fresh.label);
}

TEST_CASE("readers: a double value that float would turn into 0 or infinity is an error, not a mask") {
  namespace gio = geovoronoi::io;
  const gv::grid<3> g({3, 2, 1});
  for (double bad : {1e300, -1e300, 1e-50}) {
    gv::image<double, 3> f(g, 1.0);
    f[4] = bad;
    const std::string path = io_test::scratch("precision_f.mhd");
    gio::write_metaimage(path, f);
    std::string msg;
    try {
      (void)gio::read_volume<float>(path);
    } catch (const gio::io_error& e) {
      msg = e.what();
    }
    INFO(msg);
    CHECK(msg.find("element 4") != std::string::npos);
    CHECK(msg.find(bad > 1 || bad < -1 ? "infinite" : "would become 0") != std::string::npos);
    // read in double, the value is kept
    CHECK(gio::read_volume<double>(path).data[4] == bad);
  }
  // values float holds (subnormal ones too), zeros and infinities convert as before
  gv::image<double, 3> ok(g, 1.0);
  ok[0] = 1e-40;
  ok[1] = 0.0;
  ok[2] = std::numeric_limits<double>::infinity();
  ok[3] = -2.5e38;
  gio::write_metaimage(io_test::scratch("precision_ok.mhd"), ok);
  const auto v = gio::read_volume<float>(io_test::scratch("precision_ok.mhd"));
  CHECK(v.data[0] > 0.0f);
  CHECK(v.data[1] == 0.0f);
  CHECK(v.data[2] == std::numeric_limits<float>::infinity());
  CHECK(v.data[3] == -2.5e38f);
}

TEST_CASE("overflow_error: the issue's case, stiffness 1e-38 on 720 connected voxels, is an error in float, fine in double") {
  // before: 588 of the 720 voxels came out unreachable (label -1), without a word
  const gv::grid<3> g({12, 10, 6});
  const std::vector<float> f(g.size(), 1e-38f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> seeds{{1, 1, 1}, {10, 8, 4}};
  CHECK_THROWS_AS(gv::voronoi(gv::seq, p, seeds), gv::overflow_error);
  CHECK(gv::needs_double(g, f.data(), f.size(), gv::min_stiffness{}, gv::connectivity<26>{}));
  const std::vector<double> fd(g.size(), 1e-38);
  const auto pd = gv::make_problem(g, fd, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, pd, seeds);
  for (gv::index_t v = 0; v < g.size(); ++v) CHECK(d.label[v] != gv::no_label);
}

}  // namespace

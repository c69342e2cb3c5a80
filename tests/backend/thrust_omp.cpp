// The shared backend suite on the Thrust backend, OMP system (an explicit execution policy).
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

#define GEOVORONOI_TEST_BACKEND_NAME "thrust_omp"
#define GEOVORONOI_TEST_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)
#include "backend/suite.hpp"
#include "backend/thrust_extra.hpp"

#ifdef _OPENMP
#include <omp.h>

TEST_CASE("thrust_omp: solve_options::threads is the OpenMP team of the call, and is restored after") {
  namespace gv = geovoronoi;
  const gv::grid<3> g({40, 30, 20});
  std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> seeds{{0, 0, 0}, {39, 29, 19}};
  const int before = omp_get_max_threads();
  omp_set_num_threads(3);
  std::vector<int> seen;
  gv::solve_options opt;
  opt.threads = 2;
  opt.progress = [&](double) {
    seen.push_back(omp_get_max_threads());
    return true;
  };
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, opt);
  REQUIRE_FALSE(seen.empty());
  for (int t : seen) CHECK(t == 2);
  CHECK(omp_get_max_threads() == 3);
  // and after a cancelled call
  opt.progress = [&](double) { return false; };
  CHECK_THROWS_AS(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, seeds, opt), gv::cancelled);
  CHECK(omp_get_max_threads() == 3);
  omp_set_num_threads(before);
  CHECK(d.label[0] == 0);
}

TEST_CASE("thrust_omp: shape_options::threads 1 and 2 give the same weights") {
  namespace gv = geovoronoi;
  const gv::grid<3> g({14, 12, 9});
  std::vector<float> f(g.size());
  for (gv::index_t v = 0; v < g.size(); ++v) f[v] = 1.0f + float((g.coords(v)[0] * 5 + g.coords(v)[2]) % 4);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> nodes{{1, 1, 1}, {12, 2, 3}, {6, 10, 7}, {3, 8, 2}};
  const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY(), p, nodes);
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    gv::shape_options a, b;
    a.method = b.method = m;
    a.threads = 1;
    b.threads = 2;
    const auto wa = gv::shape_functions(GEOVORONOI_TEST_POLICY(), p, d, a);
    const auto wb = gv::shape_functions(GEOVORONOI_TEST_POLICY(), p, d, b);
    CHECK(wa.node == wb.node);
    CHECK(wa.weight == wb.weight);
    const auto ws = gv::shape_functions(gv::seq, p, d, a);
    CHECK(wa.weight == ws.weight);
  }
}
#endif

// Thrust-specific checks, added to each system's suite: the default policy (THRUST_DEVICE_SYSTEM),
// tiny batches (many threshold raises, maximal re-queuing), the work counters, bad weights.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <doctest/doctest.h>

#include "oracle.hpp"

#include <random>
#include <string>
#include <type_traits>

namespace gvthrust {
namespace gv = geovoronoi;

static_assert(std::is_trivially_copyable_v<gv::thrust::par_t>, "par_t is a small value type");

struct negative_weight {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T to) const noexcept {
    return to > T(1.5) ? -length : length;
  }
};

TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": batch sizes and the default policy agree with seq") {
  GV_SUITE_PREAMBLE();
  const gv::grid<3> g({23, 17, 11}, {1.0, 1.3, 0.8});
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<float> u(0.5f, 4.0f);
  std::vector<float> f(g.size());
  for (auto& x : f) x = u(rng);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto seeds = gvtest::random_seeds(rng, p, 7);
  const auto ref = gv::voronoi(gv::seq, p, seeds);
  for (std::size_t batch : {std::size_t(1), std::size_t(7), std::size_t(100), std::size_t(1) << 20}) {
    gv::thrust::stats st;
    const auto d = gv::voronoi(GEOVORONOI_TEST_POLICY().with_batch(batch).with_stats(&st), p, seeds);
    gvsuite::require_same_diagram(d, ref, "batch " + std::to_string(batch));
    CHECK(st.reached == std::uint64_t(g.size()));
    CHECK(st.expansions >= st.reached);
    CHECK(st.splits >= 1);
  }
  gv::thrust::stats st;
  const auto d = gv::voronoi(gv::thrust::par.with_stats(&st), p, seeds);
  gvsuite::require_same_diagram(d, ref, "thrust::par (THRUST_DEVICE_SYSTEM)");
  CHECK(st.expansions_per_voxel() >= 1.0);
}

TEST_CASE("thrust " GEOVORONOI_TEST_BACKEND_NAME ": a negative edge weight is an error") {
  GV_SUITE_PREAMBLE();
  const gv::grid<2> g({9, 9});
  std::vector<float> f(g.size(), 1.0f);
  f[g.index({6, 6})] = 2.0f;
  const auto p = gv::make_problem(g, f, negative_weight{}, gv::connectivity<8>{});
  CHECK_THROWS_AS(gv::voronoi(GEOVORONOI_TEST_POLICY(), p, std::vector<gv::coord<2>>{{0, 0}}), gv::metric_error);
}

}  // namespace gvthrust

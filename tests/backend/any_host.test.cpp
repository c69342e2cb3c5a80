// any_host_policy (backend/any_host.hpp): the wrapped host backend's results, bit for bit, through one
// policy type; its hooks (threads, host loop, cancellation, errors) reach the wrapped backend.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/any_host.hpp>
#if defined(GEOVORONOI_TEST_WITH_THRUST)
#include <geovoronoi/backend/thrust.hpp>
#endif

#include <doctest/doctest.h>

#include "support/oracle.hpp"

#include <atomic>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace gv = geovoronoi;

namespace {

template <class T>
bool same_bits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

/// Everything a shape-function program runs, with the backend's own policy and through
/// any_host_policy: the diagram, the three methods on the grid and at points, an update after a cut.
template <class Policy, class P>
void compare(const Policy& policy, const P& p, const std::vector<gv::coord<P::dim>>& seeds, const std::string& what) {
  INFO(what);
  using T = typename P::value_type;
  const gv::any_host_policy<P> any(policy);
  gv::solve_options so;
  so.with_parent = true;
  const auto d = gv::voronoi(policy, p, seeds, so);
  const auto e = gv::voronoi(any, p, seeds, so);
  CHECK(same_bits(d.distance.values(), e.distance.values()));
  CHECK(d.label.values() == e.label.values());
  CHECK(d.parent.values() == e.parent.values());
  std::vector<gv::coord<P::dim>> points;
  for (gv::index_t v = 0; v < p.geometry.size(); v += 7) points.push_back(p.geometry.coords(v));
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    gv::shape_options o;
    o.method = m;
    o.max_nodes_per_voxel = 3;
    o.batch_size = 17;
    const auto a = gv::shape_functions(policy, p, d, o);
    const auto b = gv::shape_functions(any, p, d, o);
    CHECK(a.node == b.node);
    CHECK(same_bits(a.weight, b.weight));
    const auto pa = gv::shape_functions_at(policy, p, d, points, o);
    const auto pb = gv::shape_functions_at(any, p, d, points, o);
    CHECK(pa.node == pb.node);
    CHECK(same_bits(pa.weight, pb.weight));
  }
  (void)sizeof(T);
}

template <class Policy>
void compare_all(const Policy& policy, const std::string& name) {
  std::mt19937_64 rng(2026);
  {
    const gv::grid<3> g({9, 8, 6}, {1.0, 0.75, 1.5});
    const auto f = gvtest::random_field<float>(rng, g.size(), false, 0.1, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    compare(policy, p, gvtest::random_seeds(rng, p, 5), name + " 3D float 26");
    const gv::cut_table cuts(gvtest::random_cuts(rng, g, gv::connectivity<26>{}, 0.2));
    compare(policy, gv::with_cuts(p, cuts), gvtest::random_seeds(rng, p, 4), name + " 3D float 26, cuts");
    const std::vector<double> fd(f.begin(), f.end());
    const auto pd = gv::make_problem(g, fd, gv::mean_stiffness{}, gv::connectivity<6>{});
    compare(policy, pd, gvtest::random_seeds(rng, pd, 4), name + " 3D double 6");
  }
  {
    const gv::grid<2> g({21, 17});
    const auto f = gvtest::random_field<float>(rng, g.size(), true, 0.1, false);
    const auto p = gv::make_problem(g, f, gv::mean_cost{}, gv::connectivity<8>{});
    compare(policy, p, gvtest::random_seeds(rng, p, 6), name + " 2D float 8");
  }
}

struct negative_metric {
  template <class T>
  T operator()(T length, T, T) const noexcept {
    return -length;
  }
};

}  // namespace

TEST_CASE("any_host_policy: the wrapped backend's results, bit for bit") {
  compare_all(gv::seq, "seq");
#if defined(GEOVORONOI_TEST_WITH_THRUST)
  compare_all(gv::thrust::par, "thrust");
#endif
}

TEST_CASE("any_host_policy: hooks reach the wrapped backend") {
  const gv::grid<3> g({12, 10, 8});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  using P = std::decay_t<decltype(p)>;
  const gv::any_host_policy<P> any_seq(gv::seq);
  CHECK(gv::detail::host_threads(any_seq) == 1u);
  static_assert(gv::is_backend_policy_v<gv::any_host_policy<P>>);
  static_assert(gv::detail::hooks::queries_on_host<gv::any_host_policy<P>>::value);
  // the host loop visits every index once
  std::vector<int> hits(100, 0);
  gv::detail::host_parallel_for(any_seq, 100, [&](gv::index_t i) { ++hits[std::size_t(i)]; });
  CHECK(std::count(hits.begin(), hits.end(), 1) == 100);
  // with_threads returns the callable's value
  CHECK(gv::detail::with_threads(any_seq, 3, [] { return 42; }) == 42);
#if defined(GEOVORONOI_TEST_WITH_THRUST)
  const gv::any_host_policy<P> any_thrust(gv::thrust::par);
  CHECK(gv::detail::host_threads(any_thrust) == gv::detail::host_threads(gv::thrust::par));
  std::atomic<int> sum{0};
  gv::detail::host_parallel_for(any_thrust, 1000, [&](gv::index_t i) { sum += int(i); });
  CHECK(sum.load() == 999 * 1000 / 2);
  // an exception thrown in the loop comes back to the caller
  CHECK_THROWS_AS(gv::detail::host_parallel_for(any_thrust, 64, [](gv::index_t i) {
                    if (i == 33) throw std::runtime_error("x");
                  }),
                  std::runtime_error);
#endif
  // cancellation and the metric's errors come through
  const auto d = gv::voronoi(any_seq, p, std::vector<gv::coord<3>>{{1, 1, 1}, {9, 8, 6}});
  gv::shape_options o;
  o.method = gv::shape_method::sibson;
  o.progress = [](double x) { return x < 0.5; };
  CHECK_THROWS_AS(gv::shape_functions(any_seq, p, d, o), gv::cancelled);
  const auto bad = gv::make_problem(g, f, negative_metric{}, gv::connectivity<26>{});
  const gv::any_host_policy<std::decay_t<decltype(bad)>> any_bad(gv::seq);
  CHECK_THROWS_AS(gv::voronoi(any_bad, bad, std::vector<gv::coord<3>>{{1, 1, 1}}), gv::metric_error);
}

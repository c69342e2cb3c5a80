// Tests of geovoronoi/policy.hpp: which types are backend policies, and a user's own backend (a
// policy type with the tag and the three hooks) running through the front end. That misuse does not
// compile is checked by tests/compile_fail/.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>

#include <limits>
#include <type_traits>
#include <vector>

namespace mine {
namespace gv = geovoronoi;

/// A backend that counts its calls and forwards them to seq.
struct par_t {
  using backend_policy_tag = void;
  int* calls = nullptr;
};
struct derived_t : par_t {};

template <class P>
gv::diagram<typename P::value_type, P::dim> backend_solve(const par_t& pol, const P& p,
                                                          const std::vector<gv::source<typename P::value_type>>& s,
                                                          typename P::value_type radius) {
  ++*pol.calls;
  return backend_solve(gv::seq, p, s, radius);
}
template <class P>
gv::sparse_solution<typename P::value_type> backend_bounded(const par_t& pol, const P& p,
                                                            const std::vector<gv::source<typename P::value_type>>& s,
                                                            typename P::value_type radius) {
  ++*pol.calls;
  return backend_bounded(gv::seq, p, s, radius);
}
template <class P>
gv::query_cells<typename P::value_type> backend_insert_queries(const par_t& pol, const P& p,
                                                               const gv::diagram<typename P::value_type, P::dim>& d,
                                                               const std::vector<gv::index_t>& q) {
  ++*pol.calls;
  return backend_insert_queries(gv::seq, p, d, q);
}
}  // namespace mine

namespace {
namespace gv = geovoronoi;

static_assert(gv::is_backend_policy_v<gv::seq_t>);
static_assert(gv::is_backend_policy_v<const gv::seq_t&>);
static_assert(gv::is_backend_policy_v<mine::par_t> && gv::is_backend_policy_v<mine::derived_t>);
static_assert(!gv::is_backend_policy_v<int> && !gv::is_backend_policy_v<gv::grid<3>>);
static_assert(!gv::is_backend_policy_v<gv::problem<float, 3, gv::uniform, 6>>);

TEST_CASE("policy: a user's backend runs through every entry point, with the checks of the front end") {
  const gv::grid<2> g({9, 7});
  const std::vector<float> f(std::size_t(g.size()), 1.0f);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<8>{});
  const std::vector<gv::coord<2>> seeds{{0, 0}, {8, 6}};
  int calls = 0;
  const mine::par_t pol{&calls};
  const auto d = gv::voronoi(pol, p, seeds, gv::solve_options{true, 1e300});
  const auto ref = gv::voronoi(gv::seq, p, seeds, gv::solve_options{true});
  CHECK(d.distance.values() == ref.distance.values());
  CHECK(d.label.values() == ref.label.values());
  CHECK(d.parent.values() == ref.parent.values());  // added by the front end, whatever the backend
  CHECK(d.seeds == ref.seeds);
  const auto b = gv::single_source(pol, p, seeds[0], 3.0f);
  CHECK(b.voxel == gv::single_source(gv::seq, p, seeds[0], 3.0f).voxel);
  const auto c = gv::insert_query(pol, p, d, gv::coord<2>{4, 3});
  CHECK(c.voxel == gv::insert_query(gv::seq, p, ref, gv::coord<2>{4, 3}).voxel);
  CHECK(calls == 3);
  // bad input never reaches the backend
  CHECK_THROWS_AS(gv::voronoi(pol, p, std::vector<gv::coord<2>>{{9, 0}}), std::invalid_argument);
  CHECK_THROWS_AS(gv::single_source(pol, p, seeds[0], std::numeric_limits<float>::quiet_NaN()), std::invalid_argument);
  CHECK_THROWS_AS(gv::insert_queries(pol, p, d, std::vector<gv::index_t>{-1}), std::invalid_argument);
  CHECK(calls == 3);
}

}  // namespace

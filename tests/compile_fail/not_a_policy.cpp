// voronoi() with something that is not a backend policy first: one static_assert naming the
// requirement (is_backend_policy), not a cascade of lookup errors from inside the library.
#include <geovoronoi.hpp>

#include <vector>

namespace gv = geovoronoi;

void solve_with_a_number() {
  const gv::grid<2> g({4, 4});
  const std::vector<float> f(16, 1.0f);
  const auto p = gv::make_problem(g, f);
  const std::vector<gv::coord<2>> s{{0, 0}};
  static_assert(gv::is_backend_policy_v<decltype(gv::seq)>);
  static_assert(!gv::is_backend_policy_v<int>);
#ifdef GEOVORONOI_COMPILE_FAIL
  (void)gv::voronoi(42, p, s);
#else
  (void)gv::voronoi(gv::seq, p, s);
#endif
}

// make_problem keeps a pointer to the field: from a temporary vector it would point at freed memory
// after the statement, so that overload is deleted.
#include <geovoronoi.hpp>

#include <vector>

namespace gv = geovoronoi;

float field_outlives_problem() {
  const gv::grid<2> g({4, 4});
#ifdef GEOVORONOI_COMPILE_FAIL
  const auto p = gv::make_problem(g, std::vector<float>(16, 1.0f));
#else
  const std::vector<float> f(16, 1.0f);
  const auto p = gv::make_problem(g, f);
#endif
  return p.field[0];
}

// The sequential backend's entry points for the backend table (backends.cpp).
#include "solve.hpp"

namespace gvcli {

gv::diagram<float, 3> seq_voronoi(const problem_spec& s) { return solve_voronoi(gv::seq, s); }

gv::shape_weights<float, 3> seq_shape(const problem_spec& s, const gv::diagram<float, 3>& d,
                                      const gv::shape_options& opt) {
  return solve_shape(gv::seq, s, d, opt);
}

gv::point_weights<float> seq_shape_at(const problem_spec& s, const gv::diagram<float, 3>& d, const point_spec& at,
                                const gv::shape_options& opt) {
  return solve_shape_at(gv::seq, s, d, at, opt);
}

}  // namespace gvcli

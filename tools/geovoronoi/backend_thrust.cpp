// The Thrust backend's entry points for the backend table (backends.cpp), on the device system of
// the CMake target linked (geovoronoi::thrust_omp: OpenMP host threads). Built only with that target.
#include "solve.hpp"

#include <geovoronoi/backend/thrust.hpp>

namespace gvcli {

gv::diagram<float, 3> thrust_voronoi(const problem_spec& s) { return solve_voronoi(gv::thrust::par, s); }

gv::shape_weights<float, 3> thrust_shape(const problem_spec& s, const gv::diagram<float, 3>& d,
                                         const gv::shape_options& opt) {
  return solve_shape(gv::thrust::par, s, d, opt);
}

gv::point_weights<float> thrust_shape_at(const problem_spec& s, const gv::diagram<float, 3>& d, const point_spec& at,
                                   const gv::shape_options& opt) {
  return solve_shape_at(gv::thrust::par, s, d, at, opt);
}

}  // namespace gvcli

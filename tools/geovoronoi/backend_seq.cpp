// The sequential backend's entry points for the backend table (backends.cpp).
#include "solve.hpp"

namespace gvcli {

template <class T>
gv::diagram<T, 3> seq_voronoi(const problem_spec<T>& s) {
  return solve_voronoi(gv::seq, s);
}

template <class T>
gv::shape_weights<T, 3> seq_shape(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const gv::shape_options& opt) {
  return solve_shape(gv::seq, s, d, opt);
}

template <class T>
gv::point_weights<T> seq_shape_at(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const point_spec& at,
                                  const gv::shape_options& opt) {
  return solve_shape_at(gv::seq, s, d, at, opt);
}

template <class T>
gv::shape_update_stats seq_shape_update(const problem_spec<T>& s, const gv::diagram<T, 3>& d_before,
                                        const gv::diagram<T, 3>& d_after, gv::shape_weights<T, 3>& w,
                                        const gv::change<3>& c, const gv::shape_options& opt) {
  return update_shape(gv::seq, s, d_before, d_after, w, c, opt);
}

template gv::diagram<float, 3> seq_voronoi(const problem_spec<float>&);
template gv::shape_weights<float, 3> seq_shape(const problem_spec<float>&, const gv::diagram<float, 3>&,
                                                const gv::shape_options&);
template gv::point_weights<float> seq_shape_at(const problem_spec<float>&, const gv::diagram<float, 3>&,
                                               const point_spec&, const gv::shape_options&);
template gv::shape_update_stats seq_shape_update(const problem_spec<float>&, const gv::diagram<float, 3>&,
                                                const gv::diagram<float, 3>&, gv::shape_weights<float, 3>&,
                                                const gv::change<3>&, const gv::shape_options&);

// the lean build (GEOVORONOI_TOOL_LEAN, what scripts/demo.sh builds) computes in float only
#if !defined(GEOVORONOI_CLI_LEAN)
template gv::diagram<double, 3> seq_voronoi(const problem_spec<double>&);
template gv::shape_weights<double, 3> seq_shape(const problem_spec<double>&, const gv::diagram<double, 3>&,
                                                 const gv::shape_options&);
template gv::point_weights<double> seq_shape_at(const problem_spec<double>&, const gv::diagram<double, 3>&,
                                                const point_spec&, const gv::shape_options&);
template gv::shape_update_stats seq_shape_update(const problem_spec<double>&, const gv::diagram<double, 3>&,
                                                const gv::diagram<double, 3>&, gv::shape_weights<double, 3>&,
                                                const gv::change<3>&, const gv::shape_options&);
#endif

}  // namespace gvcli

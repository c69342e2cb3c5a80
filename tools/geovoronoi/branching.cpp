// See branching.hpp. The unit that instantiates the library's branching grids and their solves for
// the front end (branching_shape.cpp adds the shape functions): 3D, float and double, every metric and connectivity of kinds.hpp, on seq and
// (when built) the Thrust backend on OpenMP host threads.
#include "branching.hpp"

#include "branching_impl.hpp"
#include "usage_error.hpp"

#include <algorithm>

namespace gvcli {

gv::stiffness_reduction parse_reduction(const std::string& name) {
  if (name == "mean") return gv::stiffness_reduction::mean;
  if (name == "min") return gv::stiffness_reduction::min;
  if (name == "max") return gv::stiffness_reduction::max;
  if (name == "harmonic" || name == "harmonic_mean") return gv::stiffness_reduction::harmonic_mean;
  throw usage_error("--reduction must be mean, min, max or harmonic, got '" + name + "'");
}

const char* reduction_name(gv::stiffness_reduction r) noexcept {
  switch (r) {
    case gv::stiffness_reduction::mean: return "mean";
    case gv::stiffness_reduction::min: return "min";
    case gv::stiffness_reduction::max: return "max";
    case gv::stiffness_reduction::harmonic_mean: return "harmonic";
  }
  return "?";
}

using detail::arrays_of;
using detail::grid_of;
using detail::with_branching_policy;

template <class T>
branching_arrays<T> build_branching(gv::image_view<const T, 3> fine, int factor, int connectivity,
                                    gv::stiffness_reduction reduction) {
  branching_arrays<T> out;
  with_connectivity<3>(check_connectivity(connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    out = arrays_of(grid_of<T, N>(fine, factor, reduction));
  });
  return out;
}

template <class T>
branching_solution<T> solve_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                      const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                      const gv::cut_set<3>* cut) {
  branching_solution<T> out;
  // the backend first: a refusal before any work
  with_branching_policy(key.backend, [](auto) {});
  with_connectivity<3>(check_connectivity(key.connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    const auto bg = grid_of<T, N>(fine, key.factor, key.reduction, cut);
    with_metric(key.metric, [&](auto metric) {
      const auto p = gv::make_problem(bg, metric);
      with_branching_policy(key.backend, [&](auto policy) { detail::solve_into(out, bg, p, policy, seeds, opt); });
    });
  });
  return out;
}

template branching_arrays<float> build_branching(gv::image_view<const float, 3>, int, int, gv::stiffness_reduction);
template branching_arrays<double> build_branching(gv::image_view<const double, 3>, int, int, gv::stiffness_reduction);
template branching_solution<float> solve_branching(const branching_key&, gv::image_view<const float, 3>,
                                                   const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                   const gv::cut_set<3>*);
template branching_solution<double> solve_branching(const branching_key&, gv::image_view<const double, 3>,
                                                    const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                    const gv::cut_set<3>*);

}  // namespace gvcli

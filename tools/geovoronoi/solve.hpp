#pragma once
// The solving part of the geovoronoi command-line tool, written once for every backend.
//
// A problem is described by plain host data (problem_spec: the field image, the seeds, the metric's
// name and the connectivity); solve_voronoi() / solve_shape() turn the names into the library's
// policy types and call it with the given backend policy. Each backend instantiates them in its own
// translation unit (backend_seq.cpp, backend_thrust.cpp, cuda.cu compiled by nvcc) and exposes the
// plain functions declared at the end of this file, which backends.cpp puts in the backend table;
// so no other file includes a backend header, and only cuda.cu needs nvcc.

#include <geovoronoi.hpp>
#include <geovoronoi/shape_functions.hpp>

#include "usage_error.hpp"

#include <string>
#include <vector>

namespace gvcli {

namespace gv = geovoronoi;

/// Calls f with the metric object named @p name.
template <class F>
void with_metric(const std::string& name, F&& f) {
  if (name == "min_stiffness") return f(gv::min_stiffness{});
  if (name == "mean_stiffness") return f(gv::mean_stiffness{});
  if (name == "mean_cost") return f(gv::mean_cost{});
  if (name == "uniform") return f(gv::uniform{});
  throw usage_error("unknown metric '" + name + "' (min_stiffness, mean_stiffness, mean_cost or uniform)");
}

/// Calls f with the 3D connectivity of @p n neighbours.
template <class F>
void with_connectivity(int n, F&& f) {
  if (n == 6) return f(gv::connectivity<6>{});
  if (n == 18) return f(gv::connectivity<18>{});
  if (n == 26) return f(gv::connectivity<26>{});
  throw usage_error("connectivity must be 6, 18 or 26, got " + std::to_string(n));
}

/// One problem as plain host data; the referenced field and seeds outlive every solve that uses it.
struct problem_spec {
  const gv::image<float, 3>& field;
  const std::vector<gv::coord<3>>& seeds;
  std::string metric = "min_stiffness";
  int connectivity = 26;
};

/// Calls f(problem) with the library's problem object for @p s.
template <class F>
void with_problem(const problem_spec& s, F&& f) {
  with_metric(s.metric, [&](auto metric) {
    with_connectivity(s.connectivity, [&](auto conn) { f(gv::make_problem(s.field.geometry(), s.field, metric, conn)); });
  });
}

/// The Voronoi diagram of @p s on the backend @p policy.
template <class Policy>
gv::diagram<float, 3> solve_voronoi(const Policy& policy, const problem_spec& s) {
  gv::diagram<float, 3> d;
  with_problem(s, [&](const auto& p) { d = gv::voronoi(policy, p, s.seeds); });
  return d;
}

/// The shape functions of @p s on the backend @p policy, given its diagram @p d.
template <class Policy>
gv::shape_weights<float, 3> solve_shape(const Policy& policy, const problem_spec& s, const gv::diagram<float, 3>& d,
                                        const gv::shape_options& opt) {
  gv::shape_weights<float, 3> w;
  with_problem(s, [&](const auto& p) { w = gv::shape_functions(policy, p, d, opt); });
  return w;
}

/// Points at which shape_functions_at() evaluates: voxel coordinates, or world points when @p world.
struct point_spec {
  std::vector<gv::coord<3>> voxels;
  std::vector<gv::point<3>> world_points;
  bool world = false;
};

/// The shape functions of @p s at the points @p at on the backend @p policy, given its diagram @p d.
template <class Policy>
gv::point_weights<float> solve_shape_at(const Policy& policy, const problem_spec& s, const gv::diagram<float, 3>& d,
                                        const point_spec& at, const gv::shape_options& opt) {
  gv::point_weights<float> w;
  with_problem(s, [&](const auto& p) {
    w = at.world ? gv::shape_functions_at(policy, p, d, at.world_points, opt)
                 : gv::shape_functions_at(policy, p, d, at.voxels, opt);
  });
  return w;
}

// ---- each backend's entry points (backend_seq.cpp, backend_thrust.cpp, cuda.cu) ----------------
// Defined only when that backend is built (see backends.cpp, the table that uses them).

gv::diagram<float, 3> seq_voronoi(const problem_spec& s);
gv::shape_weights<float, 3> seq_shape(const problem_spec& s, const gv::diagram<float, 3>& d,
                                      const gv::shape_options& opt);
gv::point_weights<float> seq_shape_at(const problem_spec& s, const gv::diagram<float, 3>& d, const point_spec& at,
                                const gv::shape_options& opt);
gv::diagram<float, 3> thrust_voronoi(const problem_spec& s);
gv::shape_weights<float, 3> thrust_shape(const problem_spec& s, const gv::diagram<float, 3>& d,
                                         const gv::shape_options& opt);
gv::point_weights<float> thrust_shape_at(const problem_spec& s, const gv::diagram<float, 3>& d, const point_spec& at,
                                   const gv::shape_options& opt);
/// Whether a CUDA device can be used: an empty string when it can (then @p device holds its name),
/// else why not (no device, no driver, ...). Never throws.
std::string cuda_unavailable_reason(std::string* device = nullptr);
gv::diagram<float, 3> cuda_voronoi(const problem_spec& s);
gv::shape_weights<float, 3> cuda_shape(const problem_spec& s, const gv::diagram<float, 3>& d,
                                       const gv::shape_options& opt);
gv::point_weights<float> cuda_shape_at(const problem_spec& s, const gv::diagram<float, 3>& d, const point_spec& at,
                                 const gv::shape_options& opt);

}  // namespace gvcli

#pragma once
// The solving part of the geovoronoi command-line tool, written once for every backend.
//
// A problem is described by plain host data (problem_spec<T>: the field image in the distance type
// T, float or double, the seeds, the metric's name and the connectivity); solve_voronoi() /
// solve_shape() turn the names into the library's policy types and call it with the given backend
// policy. Each backend instantiates them in its own
// translation unit (backend_seq.cpp, backend_thrust.cpp, cuda.cu compiled by nvcc) and exposes the
// plain functions declared at the end of this file, which backends.cpp puts in the backend table;
// so no other file includes a backend header, and only cuda.cu needs nvcc.

#include <geovoronoi.hpp>
#include <geovoronoi/shape_functions.hpp>
#include <geovoronoi/shape_update.hpp>

#include "usage_error.hpp"

#include <functional>
#include <string>
#include <vector>

namespace gvcli {

namespace gv = geovoronoi;

// Every solve is instantiated once per metric and connectivity (and cut or not, float or double).
// A lean build (CMake option GEOVORONOI_TOOL_LEAN, what scripts/demo.sh builds) instantiates only
// what `demo` uses, the metrics min_stiffness and uniform with 26 neighbours in float, and says so
// when asked for another metric, connectivity or double precision.
#if defined(GEOVORONOI_CLI_LEAN)
inline const char* lean_note() {
  return " is not compiled into this lean build (GEOVORONOI_TOOL_LEAN, as scripts/demo.sh builds it: metrics "
         "min_stiffness and uniform, 26 neighbours, float); build the target geovoronoi_tool without it";
}
#endif

/// Calls f with the metric object named @p name.
template <class F>
void with_metric(const std::string& name, F&& f) {
  if (name == "min_stiffness") return f(gv::min_stiffness{});
  if (name == "uniform") return f(gv::uniform{});
#if defined(GEOVORONOI_CLI_LEAN)
  if (name == "mean_stiffness" || name == "mean_cost") throw usage_error("metric '" + name + "'" + lean_note());
#else
  if (name == "mean_stiffness") return f(gv::mean_stiffness{});
  if (name == "mean_cost") return f(gv::mean_cost{});
#endif
  throw usage_error("unknown metric '" + name + "' (min_stiffness, mean_stiffness, mean_cost or uniform)");
}

/// Calls f with the 3D connectivity of @p n neighbours.
template <class F>
void with_connectivity(int n, F&& f) {
  if (n == 26) return f(gv::connectivity<26>{});
#if defined(GEOVORONOI_CLI_LEAN)
  if (n == 6 || n == 18) throw usage_error("connectivity " + std::to_string(n) + lean_note());
#else
  if (n == 6) return f(gv::connectivity<6>{});
  if (n == 18) return f(gv::connectivity<18>{});
#endif
  throw usage_error("connectivity must be 6, 18 or 26, got " + std::to_string(n));
}

/// One problem as plain host data, in the distance type T (float or double, `--precision`); the
/// referenced field and seeds outlive every solve that uses it.
template <class T>
struct problem_spec {
  const gv::image<T, 3>& field;
  const std::vector<gv::coord<3>>& seeds;
  std::string metric = "min_stiffness";
  int connectivity = 26;
  /// Host threads of the thrust backend (solve_options::threads, shape_options::threads); 0: default.
  unsigned threads = 0;
  /// The diagram's progress (solve_options::progress); may be empty.
  std::function<bool(double)> progress = nullptr;
  /// The cut edges of `--cut` (built for this grid and connectivity), or null without cuts.
  const gv::cut_table* cuts = nullptr;
  /// Whether the diagram keeps its parent image (solve_options::with_parent; `cut` needs it).
  bool with_parent = false;
};

/// Calls f(problem) with the library's problem object for @p s: a problem with cuts (one type per
/// metric and connectivity: the cut_view does not depend on either) when @p s has cuts, else the
/// plain problem, which keeps the no-cut path and the shape functions' shortcuts as they are.
template <class T, class F>
void with_problem(const problem_spec<T>& s, F&& f) {
  with_metric(s.metric, [&](auto metric) {
    with_connectivity(s.connectivity, [&](auto conn) {
      const auto p = gv::make_problem(s.field.geometry(), s.field, metric, conn);
      if (s.cuts)
        f(gv::with_cuts(p, *s.cuts));
      else
        f(p);
    });
  });
}

/// The Voronoi diagram of @p s on the backend @p policy.
template <class Policy, class T>
gv::diagram<T, 3> solve_voronoi(const Policy& policy, const problem_spec<T>& s) {
  gv::diagram<T, 3> d;
  gv::solve_options opt;
  opt.threads = s.threads;
  opt.progress = s.progress;
  opt.with_parent = s.with_parent;
  with_problem(s, [&](const auto& p) { d = gv::voronoi(policy, p, s.seeds, opt); });
  return d;
}

/// The shape functions of @p s on the backend @p policy, given its diagram @p d.
template <class Policy, class T>
gv::shape_weights<T, 3> solve_shape(const Policy& policy, const problem_spec<T>& s, const gv::diagram<T, 3>& d,
                                    gv::shape_options opt) {
  gv::shape_weights<T, 3> w;
  opt.threads = s.threads;
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
template <class Policy, class T>
gv::point_weights<T> solve_shape_at(const Policy& policy, const problem_spec<T>& s, const gv::diagram<T, 3>& d,
                                    const point_spec& at, gv::shape_options opt) {
  gv::point_weights<T> w;
  opt.threads = s.threads;
  with_problem(s, [&](const auto& p) {
    w = at.world ? gv::shape_functions_at(policy, p, d, at.world_points, opt)
                 : gv::shape_functions_at(policy, p, d, at.voxels, opt);
  });
  return w;
}

/// The shape functions @p w of the problem before a change (computed on @p d_before) updated in place
/// into those of @p s, the problem after it, whose diagram is @p d_after; @p c is the change.
/// update_shape_functions_in_place() with @p policy (shape_update.hpp).
template <class Policy, class T>
gv::shape_update_stats update_shape(const Policy& policy, const problem_spec<T>& s, const gv::diagram<T, 3>& d_before,
                                    const gv::diagram<T, 3>& d_after, gv::shape_weights<T, 3>& w,
                                    const gv::change<3>& c, gv::shape_options opt) {
  gv::shape_update_stats st;
  opt.threads = s.threads;
  with_problem(s, [&](const auto& p) { st = gv::update_shape_functions_in_place(policy, p, d_before, d_after, w, c, opt); });
  return st;
}

/// One backend's entry points for one distance type (the backend table holds one set per type).
template <class T>
struct solver_fns {
  gv::diagram<T, 3> (*voronoi)(const problem_spec<T>&) = nullptr;
  gv::shape_weights<T, 3> (*shape)(const problem_spec<T>&, const gv::diagram<T, 3>&, const gv::shape_options&) = nullptr;
  gv::point_weights<T> (*shape_at)(const problem_spec<T>&, const gv::diagram<T, 3>&, const point_spec&,
                                   const gv::shape_options&) = nullptr;
  /// update_shape_functions_in_place() on this backend (`cut --method`, `demo`)
  gv::shape_update_stats (*shape_update)(const problem_spec<T>&, const gv::diagram<T, 3>&, const gv::diagram<T, 3>&,
                                         gv::shape_weights<T, 3>&, const gv::change<3>&,
                                         const gv::shape_options&) = nullptr;
  /// the backend shape_update runs on (the CUDA entry uses seq's host update)
  const char* shape_update_backend = nullptr;
};

// ---- each backend's entry points (backend_seq.cpp, backend_thrust.cpp, cuda.cu) ----------------
// Defined (and instantiated for float and double) only when that backend is built (see backends.cpp,
// the table that uses them).

template <class T>
gv::diagram<T, 3> seq_voronoi(const problem_spec<T>& s);
template <class T>
gv::shape_weights<T, 3> seq_shape(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const gv::shape_options& opt);
template <class T>
gv::point_weights<T> seq_shape_at(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const point_spec& at,
                                  const gv::shape_options& opt);
/// The shape functions' update after a change (update_shape()) with gv::seq. Each
/// backend's update sits beside its shape functions (seq_shape(), thrust_shape()), so that the row
/// computations they share are compiled once; the CUDA backend's table entry uses the seq one (a host
/// update, like the diagram's).
template <class T>
gv::shape_update_stats seq_shape_update(const problem_spec<T>& s, const gv::diagram<T, 3>& d_before,
                                        const gv::diagram<T, 3>& d_after, gv::shape_weights<T, 3>& w,
                                        const gv::change<3>& c, const gv::shape_options& opt);
template <class T>
gv::diagram<T, 3> thrust_voronoi(const problem_spec<T>& s);
template <class T>
gv::shape_weights<T, 3> thrust_shape(const problem_spec<T>& s, const gv::diagram<T, 3>& d,
                                     const gv::shape_options& opt);
template <class T>
gv::point_weights<T> thrust_shape_at(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const point_spec& at,
                                     const gv::shape_options& opt);
template <class T>
gv::shape_update_stats thrust_shape_update(const problem_spec<T>& s, const gv::diagram<T, 3>& d_before,
                                           const gv::diagram<T, 3>& d_after, gv::shape_weights<T, 3>& w,
                                           const gv::change<3>& c, const gv::shape_options& opt);
/// Whether a CUDA device can be used: an empty string when it can (then @p device holds its name),
/// else why not (no device, no driver, ...). Never throws.
std::string cuda_unavailable_reason(std::string* device = nullptr);
template <class T>
gv::diagram<T, 3> cuda_voronoi(const problem_spec<T>& s);
template <class T>
gv::shape_weights<T, 3> cuda_shape(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const gv::shape_options& opt);
template <class T>
gv::point_weights<T> cuda_shape_at(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const point_spec& at,
                                   const gv::shape_options& opt);

/// The entry points of backend @p prefix (seq, thrust, cuda) for type T, for the table, with the
/// shape functions' update of backend @p update (seq or thrust).
#define GEOVORONOI_CLI_FNS(prefix, update, T)                                                    \
  ::gvcli::solver_fns<T> {                                                                        \
    prefix##_voronoi<T>, prefix##_shape<T>, prefix##_shape_at<T>, update##_shape_update<T>, #update \
  }
/// The same in double; none in the lean build, which computes in float only (load_job() refuses
/// double there).
#if defined(GEOVORONOI_CLI_LEAN)
#define GEOVORONOI_CLI_FNS_DOUBLE(prefix, update) ::gvcli::solver_fns<double> {}
#else
#define GEOVORONOI_CLI_FNS_DOUBLE(prefix, update) GEOVORONOI_CLI_FNS(prefix, update, double)
#endif

}  // namespace gvcli

#pragma once
// Names to types: the one table of the front end (the geovoronoi tool and the Python extension).
// A run's metric, connectivity, shape-function method and backend are named by the user; they are
// checked once, when the run is set up (parse_metric(), check_connectivity(), parse_method(),
// backends.hpp's parse_backend()), and kept as these small values. with_metric() and
// with_connectivity() turn them into the library's policy types: where the typed problems are
// instantiated (typed_problem_impl.hpp) and in the few light templates outside them (the backend
// rule, --precision auto, cut sets).
//
// A lean build (CMake option GEOVORONOI_TOOL_LEAN, what scripts/demo.sh builds) compiles only what
// `demo` uses, the metrics min_stiffness and uniform with 26 neighbours in float, and says so when
// asked for anything else.

#include "usage_error.hpp"

#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/metric.hpp>
#include <geovoronoi/shape_functions.hpp>

#include <stdexcept>
#include <string>

namespace gvcli {

namespace gv = geovoronoi;

enum class metric_id { min_stiffness, mean_stiffness, mean_cost, uniform };

/// The library's backends as the front end names them: `seq`, `thrust` (OpenMP host threads), `cuda`.
enum class backend_id { seq, thrust, cuda };

/// The metric named @p name; a usage_error naming the metrics when it is unknown (or, in the lean
/// build, not compiled in).
metric_id parse_metric(const std::string& name);
/// "min_stiffness", "mean_stiffness", "mean_cost" or "uniform".
const char* metric_name(metric_id m) noexcept;

/// @p n when it is a connectivity of a @p dim-dimensional grid (4 or 8 in 2D; 6, 18 or 26 in 3D);
/// else a usage_error.
int check_connectivity(int n, int dim);

/// "seq", "thrust" or "cuda".
const char* backend_name(backend_id b) noexcept;

/// The shape-function method named @p m: distance-ratio (or distance_ratio), sibson or laplace; else
/// a usage_error.
gv::shape_method parse_method(const std::string& m);
/// The method's name on the command line and as the demo's folder name.
const char* method_name(gv::shape_method m) noexcept;

#if defined(GEOVORONOI_CLI_LEAN)
/// The end of the lean build's refusals.
const char* lean_note() noexcept;
#endif

/// Calls f with the metric object of @p m (checked by parse_metric()).
template <class F>
decltype(auto) with_metric(metric_id m, F&& f) {
  switch (m) {
    case metric_id::min_stiffness: return f(gv::min_stiffness{});
    case metric_id::uniform: return f(gv::uniform{});
#if !defined(GEOVORONOI_CLI_LEAN)
    case metric_id::mean_stiffness: return f(gv::mean_stiffness{});
    case metric_id::mean_cost: return f(gv::mean_cost{});
#else
    default: break;
#endif
  }
  throw std::logic_error("geovoronoi: a metric that parse_metric() refuses");
}

/// Calls f with the connectivity<n> of a @p Dim-dimensional grid (n checked by check_connectivity()).
template <int Dim, class F>
decltype(auto) with_connectivity(int n, F&& f) {
  if constexpr (Dim == 2) {
    if (n == 4) return f(gv::connectivity<4>{});
    if (n == 8) return f(gv::connectivity<8>{});
  } else {
    if (n == 26) return f(gv::connectivity<26>{});
#if !defined(GEOVORONOI_CLI_LEAN)
    if (n == 6) return f(gv::connectivity<6>{});
    if (n == 18) return f(gv::connectivity<18>{});
#endif
  }
  throw std::logic_error("geovoronoi: a connectivity that check_connectivity() refuses");
}

}  // namespace gvcli

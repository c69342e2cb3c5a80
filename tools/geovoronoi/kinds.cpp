// See kinds.hpp.
#include "kinds.hpp"

namespace gvcli {

#if defined(GEOVORONOI_CLI_LEAN)
const char* lean_note() noexcept {
  return " is not compiled into this lean build (GEOVORONOI_TOOL_LEAN, as scripts/demo.sh builds it: metrics "
         "min_stiffness and uniform, 26 neighbours, float); build the target geovoronoi_tool without it";
}
#endif

metric_id parse_metric(const std::string& name) {
  if (name == "min_stiffness") return metric_id::min_stiffness;
  if (name == "uniform") return metric_id::uniform;
  if (name == "mean_stiffness" || name == "mean_cost") {
#if defined(GEOVORONOI_CLI_LEAN)
    throw usage_error("metric '" + name + "'" + lean_note());
#else
    return name == "mean_stiffness" ? metric_id::mean_stiffness : metric_id::mean_cost;
#endif
  }
  throw usage_error("unknown metric '" + name + "' (min_stiffness, mean_stiffness, mean_cost or uniform)");
}

const char* metric_name(metric_id m) noexcept {
  switch (m) {
    case metric_id::min_stiffness: return "min_stiffness";
    case metric_id::mean_stiffness: return "mean_stiffness";
    case metric_id::mean_cost: return "mean_cost";
    case metric_id::uniform: return "uniform";
  }
  return "?";
}

int check_connectivity(int n, int dim) {
  if (dim == 2) {
    if (n == 4 || n == 8) return n;
    throw usage_error("connectivity of a 2D grid must be 4 or 8, got " + std::to_string(n));
  }
  if (n == 26) return n;
  if (n == 6 || n == 18) {
#if defined(GEOVORONOI_CLI_LEAN)
    throw usage_error("connectivity " + std::to_string(n) + lean_note());
#else
    return n;
#endif
  }
  throw usage_error("connectivity must be 6, 18 or 26, got " + std::to_string(n));
}

const char* backend_name(backend_id b) noexcept {
  switch (b) {
    case backend_id::seq: return "seq";
    case backend_id::thrust: return "thrust";
    case backend_id::cuda: return "cuda";
  }
  return "?";
}

gv::shape_method parse_method(const std::string& m) {
  if (m == "distance-ratio" || m == "distance_ratio") return gv::shape_method::distance_ratio;
  if (m == "sibson") return gv::shape_method::sibson;
  if (m == "laplace") return gv::shape_method::laplace;
  throw usage_error("unknown method '" + m + "' (distance-ratio, sibson or laplace)");
}

const char* method_name(gv::shape_method m) noexcept {
  return m == gv::shape_method::distance_ratio ? "distance-ratio" : m == gv::shape_method::sibson ? "sibson" : "laplace";
}

}  // namespace gvcli

// The backend table of the geovoronoi tool (see backends.hpp). The only place that knows which
// backends are compiled in: GEOVORONOI_CLI_THRUST and GEOVORONOI_CLI_CUDA come from CMake when
// backend_thrust.cpp and cuda.cu are part of the binary.
#include "backends.hpp"

#include "errors.hpp"  // max_threads

#include <thread>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace gvcli {

namespace {

std::string threads_text() {
  return "OpenMP on " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
}
std::string runs_here() { return {}; }
bool always() { return true; }
bool several_threads() { return std::thread::hardware_concurrency() > 1; }

#if defined(GEOVORONOI_CLI_CUDA)
/// Asks the CUDA runtime once.
std::string cuda_problem() {
  static const std::string why = cuda_unavailable_reason();
  return why;
}
std::string cuda_text() { return cuda_problem().empty() ? "device present" : "unusable here: " + cuda_problem(); }
bool cuda_usable() { return cuda_problem().empty(); }
#endif

}  // namespace

const std::vector<backend>& backends() {
  static const std::vector<backend> table = {
      {"seq", true, [] { return std::string("sequential Dijkstra"); }, runs_here, always,
       GEOVORONOI_CLI_FNS(seq, seq, float), GEOVORONOI_CLI_FNS_DOUBLE(seq, seq)},
#if defined(GEOVORONOI_CLI_THRUST)
      {"thrust", true, threads_text, runs_here, several_threads, GEOVORONOI_CLI_FNS(thrust, thrust, float),
       GEOVORONOI_CLI_FNS_DOUBLE(thrust, thrust)},
#else
      {"thrust", false, nullptr, nullptr, nullptr, {}, {}},
#endif
#if defined(GEOVORONOI_CLI_CUDA)
      {"cuda", true, cuda_text, cuda_problem, cuda_usable, GEOVORONOI_CLI_FNS(cuda, seq, float),
       GEOVORONOI_CLI_FNS_DOUBLE(cuda, seq)},
#else
      {"cuda", false, nullptr, nullptr, nullptr, {}, {}},
#endif
  };
  return table;
}

std::string built_backend_names() {
  std::string s;
  for (const auto& b : backends())
    if (b.built) s += (s.empty() ? "" : ", ") + std::string(b.name);
  return s;
}

const backend& default_backend() {
  const auto& t = backends();
  for (auto it = t.rbegin(); it != t.rend(); ++it)
    if (it->built && it->unavailable().empty() && it->worth_default()) return *it;
  return t.front();
}

const backend& pick_backend(const arguments& a) {
  if (!a.has("--backend")) return default_backend();
  const std::string name = a.get("--backend");
  std::string known;
  for (const auto& b : backends()) {
    known += (known.empty() ? "" : ", ") + std::string(b.name);
    if (name != b.name) continue;
    if (!b.built)
      throw usage_error("backend '" + name + "' is not built into this geovoronoi (built: " + built_backend_names() + ")");
    if (const std::string why = b.unavailable(); !why.empty()) throw usage_error("backend '" + name + "': " + why);
    return b;
  }
  throw usage_error("unknown backend '" + name + "' (" + known + ")");
}

unsigned thrust_threads() {
#if defined(_OPENMP)
  return unsigned(omp_get_max_threads());
#else
  return std::thread::hardware_concurrency();
#endif
}

unsigned use_threads(const arguments& a) {
  if (!a.has("--threads")) return 0;
  const int n = int(a.integer("--threads", 0, 1, max_threads()));
#if defined(_OPENMP)
  omp_set_num_threads(n);
#endif
  return unsigned(n);
}

}  // namespace gvcli

// The backend table and the backend rule of the front end (see backends.hpp). Which backends are
// built is what registered its typed problems (typed_problem.hpp); cuda.cu registers the CUDA probe.
#include "backends.hpp"

#include "errors.hpp"  // max_threads
#include "typed_problem.hpp"

#include <geovoronoi/backend/choose.hpp>
#include <geovoronoi/problem.hpp>

#include <array>
#include <mutex>
#include <optional>
#include <thread>

#if defined(_OPENMP)
#include <omp.h>
#endif

namespace gvcli {

namespace {

/// The backend's probe's answer, asked once per process (a CUDA runtime query is slow).
std::string probe_once(backend_id b) {
  const device_probe probe = registered_device_probe(b);
  if (!probe) return {};
  static std::mutex mutex;
  static std::array<std::optional<std::string>, 3> answers;
  const std::lock_guard<std::mutex> lock(mutex);
  auto& why = answers[std::size_t(b)];
  if (!why) why = probe(nullptr);
  return *why;
}

/// Whether @p b is worth choosing by default when it is built and can run here.
bool worth_default(backend_id b) {
  return b != backend_id::thrust || std::thread::hardware_concurrency() > 1;
}

}  // namespace

bool backend::built() const noexcept { return backend_registered(id); }

std::string backend::describe() const {
  switch (id) {
    case backend_id::seq: return "sequential Dijkstra";
    case backend_id::thrust:
      return "OpenMP on " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
    case backend_id::cuda: {
      const std::string why = unavailable();
      return why.empty() ? "device present" : "unusable here: " + why;
    }
  }
  return {};
}

std::string backend::unavailable() const { return built() ? probe_once(id) : std::string(); }

const std::vector<backend>& backends() {
  static const std::vector<backend> table = {
      {backend_id::seq, "seq"}, {backend_id::thrust, "thrust"}, {backend_id::cuda, "cuda"}};
  return table;
}

const backend& find_backend(backend_id b) { return backends()[std::size_t(b)]; }

std::string built_backend_names() {
  std::string s;
  for (const auto& b : backends())
    if (b.built()) s += (s.empty() ? "" : ", ") + std::string(b.name);
  return s;
}

const backend* parse_backend(const std::string& name, bool allow_auto) {
  if (allow_auto && name == "auto") return nullptr;
  std::string known = allow_auto ? "auto" : "";
  for (const auto& b : backends()) {
    known += (known.empty() ? "" : ", ") + std::string(b.name);
    if (name != b.name) continue;
    if (!b.built())
      throw usage_error("backend '" + name + "' is not built into this geovoronoi (built: " + built_backend_names() + ")");
    if (const std::string why = b.unavailable(); !why.empty()) throw usage_error("backend '" + name + "': " + why);
    return &b;
  }
  throw usage_error("unknown backend '" + name + "' (" + known + ")");
}

const backend& default_backend() {
  const auto& t = backends();
  for (auto it = t.rbegin(); it != t.rend(); ++it)
    if (it->built() && it->unavailable().empty() && worth_default(it->id)) return *it;
  return t.front();
}

template <class T, int Dim>
backend_id choose_backend(metric_id metric, int connectivity, gv::image_view<const T, Dim> field, unsigned threads,
                          bool shape_functions) {
  const backend& cuda = find_backend(backend_id::cuda);
  const bool gpu = cuda.built() && cuda.unavailable().empty();
  const unsigned t = threads > 0 ? threads : thrust_threads();
  gv::backend_kind k = gv::backend_kind::sequential;
  with_metric(metric, [&](auto m) {
    with_connectivity<Dim>(connectivity, [&](auto conn) {
      const auto p = gv::make_problem(field.geometry(), field, m, conn);
      k = shape_functions ? gv::recommended_shape_backend(p, t, gpu) : gv::recommended_backend(p, t, gpu);
    });
  });
  for (const auto& b : backends())
    if (b.name == std::string(gv::to_string(k)) && b.built() && b.unavailable().empty()) return b.id;
  return default_backend().id;
}

template backend_id choose_backend(metric_id, int, gv::image_view<const float, 2>, unsigned, bool);
template backend_id choose_backend(metric_id, int, gv::image_view<const double, 2>, unsigned, bool);
template backend_id choose_backend(metric_id, int, gv::image_view<const float, 3>, unsigned, bool);
template backend_id choose_backend(metric_id, int, gv::image_view<const double, 3>, unsigned, bool);

unsigned thrust_threads() {
#if defined(_OPENMP)
  return unsigned(omp_get_max_threads());
#else
  return std::thread::hardware_concurrency();
#endif
}

const backend& pick_backend(const arguments& a) {
  if (!a.has("--backend")) return default_backend();
  return *parse_backend(a.get("--backend"));
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

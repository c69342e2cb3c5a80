// See typed_problem.hpp: the registry of the instance units' makers and the factory.
#include "typed_problem.hpp"

#include <array>
#include <stdexcept>
#include <type_traits>

namespace gvcli {

namespace {

constexpr std::size_t backend_count = 3;

/// The makers of one T and Dim, by backend and cuts-or-not. A function-local static, so that it
/// exists before the first registration whatever order the static initializers run in.
template <class T, int Dim>
std::array<std::array<problem_maker<T, Dim>, 2>, backend_count>& makers() noexcept {
  static std::array<std::array<problem_maker<T, Dim>, 2>, backend_count> table{};
  return table;
}

std::array<bool, backend_count>& registered() noexcept {
  static std::array<bool, backend_count> table{};
  return table;
}

std::array<device_probe, backend_count>& probes() noexcept {
  static std::array<device_probe, backend_count> table{};
  return table;
}

}  // namespace

template <class T, int Dim>
bool register_problem_maker(backend_id b, bool cuts, problem_maker<T, Dim> make) noexcept {
  makers<T, Dim>()[std::size_t(b)][cuts ? 1 : 0] = make;
  registered()[std::size_t(b)] = true;
  return true;
}

bool backend_registered(backend_id b) noexcept { return registered()[std::size_t(b)]; }

bool register_device_probe(backend_id b, device_probe probe) noexcept {
  probes()[std::size_t(b)] = probe;
  return true;
}

device_probe registered_device_probe(backend_id b) noexcept { return probes()[std::size_t(b)]; }

template <class T, int Dim>
std::unique_ptr<typed_problem<T, Dim>> make_typed_problem(const problem_key& key, gv::image_view<const T, Dim> field,
                                                          const gv::cut_table* cuts) {
  if (key.cuts != (cuts != nullptr))
    throw std::logic_error("geovoronoi: make_typed_problem: a cut table is given exactly when the key has cuts");
  const problem_maker<T, Dim> make = makers<T, Dim>()[std::size_t(key.backend)][key.cuts ? 1 : 0];
  if (!make)
    throw usage_error(std::string("backend '") + backend_name(key.backend) + "' has no " + std::to_string(Dim) +
                      "D problems in " + (std::is_same_v<T, float> ? "float" : "double") +
                      " built into this geovoronoi");
  std::unique_ptr<typed_problem<T, Dim>> host;
  if (key.backend != backend_id::seq) {
    problem_key h = key;
    h.backend = backend_id::seq;
    host = make_typed_problem<T, Dim>(h, field, cuts);
  }
  return make(key, field, cuts, std::move(host));
}

#define GEOVORONOI_CLI_REGISTRY(T, DIM)                                                                  \
  template bool register_problem_maker<T, DIM>(backend_id, bool, problem_maker<T, DIM>) noexcept;        \
  template std::unique_ptr<typed_problem<T, DIM>> make_typed_problem<T, DIM>(                            \
      const problem_key&, gv::image_view<const T, DIM>, const gv::cut_table*);
GEOVORONOI_CLI_REGISTRY(float, 2)
GEOVORONOI_CLI_REGISTRY(double, 2)
GEOVORONOI_CLI_REGISTRY(float, 3)
GEOVORONOI_CLI_REGISTRY(double, 3)
#undef GEOVORONOI_CLI_REGISTRY

}  // namespace gvcli

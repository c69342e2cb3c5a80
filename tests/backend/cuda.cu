// The shared backend suite, instantiated for the CUDA kernel backend (built with nvcc).
//
// main() asks the CUDA runtime for a device before running anything (and not at all when doctest is
// only listing or counting cases). Without a device it says why and exits 77, which CTest reports
// as skipped: the kernels are then compiled but not exercised.
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/backend/cuda.cuh>

#include "support/oracle.hpp"

#include <cuda_runtime.h>

#include <cstdio>
#include <cstring>
#include <type_traits>

// The oracle's test metric has a host-only call operator; give the kernels an equivalent one
// (the same expression and mask rule), through the backend's customisation point.
namespace gvcuda_test {
struct destination_cost_device {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T to) const noexcept {
    return length * to;
  }
  template <class T>
  GEOVORONOI_HOST_DEVICE static bool inside(T v) noexcept {
    return v > T(0) && v < T(100);
  }
};
}  // namespace gvcuda_test
template <>
struct geovoronoi::cuda::device_metric<gvtest::destination_cost> {
  using type = gvcuda_test::destination_cost_device;
  static GEOVORONOI_HOST_DEVICE type convert(const gvtest::destination_cost&) noexcept { return {}; }
};

// What goes into a kernel is a small trivially copyable view.
namespace gvcuda_test {
namespace cd = geovoronoi::cuda::detail;
static_assert(std::is_trivially_copyable_v<cd::tiling>, "tiling must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::worklist_view>, "worklist_view must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::seed_word>, "seed_word must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::label_seed>, "label_seed must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::rule_voronoi>, "rule_voronoi must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::rule_distance<double>>, "rule_distance must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::rule_insert<float>>, "rule_insert must be trivially copyable");
static_assert(std::is_trivially_copyable_v<cd::query_out<float>>, "query_out must be trivially copyable");
static_assert(std::is_trivially_copyable_v<geovoronoi::problem<float, 3, geovoronoi::min_stiffness, 26>>,
              "problem must be trivially copyable");
static_assert(std::is_trivially_copyable_v<geovoronoi::problem<double, 2, geovoronoi::mean_cost, 8>>,
              "problem must be trivially copyable");
static_assert(std::is_trivially_copyable_v<geovoronoi::cuda::par_t>, "the policy is passed by value");

bool& device_missing() {
  static bool missing = true;
  return missing;
}
}  // namespace gvcuda_test

#define GEOVORONOI_TEST_BACKEND_NAME "cuda"
#define GEOVORONOI_TEST_POLICY() ::geovoronoi::cuda::par
#define GEOVORONOI_TEST_SKIP_IF_NO_DEVICE() ::gvcuda_test::device_missing()
#include "backend/suite.hpp"

namespace {
bool only_lists(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    // doctest's listing, counting, help and version options, short and long, with and without "dt-"
    for (const char* flag : {"-ltc", "-lts", "-lr", "-c", "-h", "-?", "-v", "--list", "--count", "--help", "--version",
                             "-dt-ltc", "-dt-lts", "-dt-lr", "-dt-c", "-dt-h", "-dt-v", "--dt-list", "--dt-count",
                             "--dt-help", "--dt-version"}) {
      const std::size_t n = std::strlen(flag);
      // a short flag must match exactly (or be followed by '='), so "-c" does not catch other options
      if (std::strncmp(a, flag, n) == 0 && (flag[1] == '-' || a[n] == '\0' || a[n] == '=')) return true;
    }
  }
  return false;
}
}  // namespace

int main(int argc, char** argv) {
  doctest::Context context;
  context.applyCommandLine(argc, argv);
  if (!only_lists(argc, argv)) {
    int devices = 0;
    const cudaError_t e = cudaGetDeviceCount(&devices);
    if (e != cudaSuccess || devices == 0) {
      std::printf("test_backend_cuda: skipped, no CUDA device (%s)\n",
                  e != cudaSuccess ? cudaGetErrorString(e) : "cudaGetDeviceCount reported 0 devices");
      return 77;
    }
    gvcuda_test::device_missing() = false;
  }
  return context.run();
}

// The shared backend suite on the Thrust backend, CUDA system (compiled by nvcc), and branching grids
// on it (branching_thrust_cuda.hpp). Without a device
// every case reports itself skipped and the executable exits with 77 (ctest: skipped, never passed).
// Nothing touches the CUDA runtime before doctest runs a case. This file has its own main().
#define DOCTEST_CONFIG_IMPLEMENT
#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <cuda_runtime.h>
#include <thrust/system/cpp/execution_policy.h>
#include <thrust/system/cuda/execution_policy.h>

#include "support/oracle.hpp"

namespace gvcuda {
namespace gv = geovoronoi;

int skipped = 0;  // cases that found no device
int ran = 0;      // cases that found one

inline bool no_device() {
  int n = 0;
  const bool none = cudaGetDeviceCount(&n) != cudaSuccess || n == 0;
  ++(none ? skipped : ran);
  return none;
}

using cuda_exec = std::decay_t<decltype(::thrust::cuda::par)>;

/// The CUDA-system policy, except for the test-only metric gvtest::destination_cost, whose call
/// operator is host-only (tests/oracle.hpp does not mark it GEOVORONOI_HOST_DEVICE): problems with
/// that metric run on the CPP system so that the rest of the suite can be compiled for the device.
struct policy : gv::thrust::par_on_t<cuda_exec> {
  policy() : gv::thrust::par_on_t<cuda_exec>(gv::thrust::par_t{}, ::thrust::cuda::par) {}
};
template <class T, int Dim, int N>
gv::diagram<T, Dim> backend_solve(const policy&, const gv::problem<T, Dim, gvtest::destination_cost, N>& p,
                                  const std::vector<gv::source<T>>& s, T radius,
                                  const gv::detail::solve_control& ctl = {}) {
  return gv::thrust::backend_solve(gv::thrust::par_on(::thrust::cpp::par), p, s, radius, ctl);
}
}  // namespace gvcuda

#define GEOVORONOI_TEST_BACKEND_NAME "thrust_cuda"
#define GEOVORONOI_TEST_POLICY() ::gvcuda::policy()
#define GEOVORONOI_TEST_SKIP_IF_NO_DEVICE() ::gvcuda::no_device()
#include "backend/suite.hpp"
#include "backend/thrust_extra.hpp"
#include "backend/branching_thrust_cuda.hpp"

int main(int argc, char** argv) {
  doctest::Context ctx(argc, argv);
  const int rc = ctx.run();
  if (ctx.shouldExit() || rc != 0) return rc;
  return gvcuda::skipped > 0 && gvcuda::ran == 0 ? 77 : 0;  // 77: ctest reports the test skipped
}

// Error path of the CUDA backend that can be checked without a GPU: with no usable device, every
// entry point must throw geovoronoi::cuda::cuda_error (a geovoronoi::error) whose message names the
// failing call and carries CUDA's description, and argument errors must still be reported first as
// std::invalid_argument by the front end. With a device present the test reports itself skipped
// (exit 77); the shared suite covers that case.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/cuda.cuh>

#include <cuda_runtime.h>

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

namespace {
namespace gv = geovoronoi;
int failures = 0;

void expect(bool ok, const char* what) {
  if (!ok) {
    std::printf("FAILED: %s\n", what);
    ++failures;
  }
}

template <class F>
void expect_cuda_error(F&& f, const char* what) {
  try {
    f();
    expect(false, what);
  } catch (const gv::cuda::cuda_error& e) {
    const std::string m = e.what();
    std::printf("%s: cuda_error: %s\n", what, m.c_str());
    expect(m.find("geovoronoi::cuda") != std::string::npos, "message names the backend");
    expect(m.find("failed at") != std::string::npos, "message names the call site");
    expect(m.find(cudaGetErrorString(e.code())) != std::string::npos, "message carries CUDA's error string");
    expect(e.code() != cudaSuccess, "error code is kept");
    const gv::error* base = &e;
    expect(base != nullptr, "cuda_error is a geovoronoi::error");
  } catch (const std::exception& e) {
    std::printf("%s: unexpected exception: %s\n", what, e.what());
    expect(false, what);
  }
}
}  // namespace

int main() {
  int devices = 0;
  const cudaError_t probe = cudaGetDeviceCount(&devices);
  if (probe == cudaSuccess && devices > 0) {
    std::printf("test_cuda_errors: skipped, a CUDA device is present (the shared suite runs there)\n");
    return 77;
  }
  const gv::grid<3> g({12, 10, 9});
  const std::vector<float> f(g.size(), 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const std::vector<gv::coord<3>> seeds{{0, 0, 0}, {11, 9, 8}};

  // the front end validates before any device work
  try {
    (void)gv::voronoi(gv::cuda::par, p, std::vector<gv::coord<3>>{{0, 0, 0}, {0, 0, 0}});
    expect(false, "duplicate seeds rejected");
  } catch (const std::invalid_argument&) {
  }
  expect_cuda_error([&] { (void)gv::voronoi(gv::cuda::par, p, seeds); }, "voronoi");
  expect_cuda_error([&] { (void)gv::single_source(gv::cuda::par, p, gv::coord<3>{3, 3, 3}, 4.0f); }, "single_source");
  const auto d = gv::voronoi(gv::seq, p, seeds);
  expect_cuda_error([&] { (void)gv::insert_queries(gv::cuda::par, p, d, std::vector<gv::index_t>{5, 77}); },
                    "insert_queries");
  // repeated failures keep failing cleanly (nothing half-initialised is left behind)
  expect_cuda_error([&] { (void)gv::voronoi(gv::cuda::par, p, seeds); }, "voronoi again");
  if (failures) return 1;
  std::printf("test_cuda_errors: passed\n");
  return 0;
}

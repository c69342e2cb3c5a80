// The front end's CUDA backend: the only translation unit that includes the CUDA headers (built by
// nvcc when the geovoronoi::cuda target exists, and linked into the tool only; see
// tools/geovoronoi/CMakeLists.txt). It registers the typed problems of the CUDA kernel backend in 3D
// (their shape-function and diagram updates are the host's, on seq) and the probe that says whether
// a device answers, so the rest of the front end stays ordinary C++.

#include "typed_problem_impl.hpp"

#include <geovoronoi/backend/cuda.cuh>

#include <cuda_runtime.h>

namespace gvcli {

namespace {

/// Whether a CUDA device can be used: empty when it can (then @p device holds its name), else why not
/// (no device, no driver, ...). Never throws.
std::string cuda_unavailable_reason(std::string* device) {
  int count = 0;
  const cudaError_t e = cudaGetDeviceCount(&count);
  if (e != cudaSuccess) {
    (void)cudaGetLastError();  // clear the sticky error state of this thread
    return std::string("no usable CUDA device (") + cudaGetErrorString(e) + ")";
  }
  if (count <= 0) return "no CUDA device";
  if (device) {
    cudaDeviceProp prop{};
    if (cudaGetDeviceProperties(&prop, 0) == cudaSuccess) *device = prop.name;
    else (void)cudaGetLastError();
  }
  return {};
}

template <class T, bool Cuts>
bool register_cuda() noexcept {
  return register_problem_maker<T, 3>(backend_id::cuda, Cuts, &make_typed_problem_on<gv::cuda::par_t, T, 3, Cuts, true>);
}

// the lean build (GEOVORONOI_TOOL_LEAN, what scripts/demo.sh builds) computes in float only; so does
// a build in which no GPU will run this unit (GEOVORONOI_TEST_CUDA_REDUCED_MATRIX: it only proves
// that the code compiles, and the double problems are the float ones' templates)
[[maybe_unused]] const bool registered = register_device_probe(backend_id::cuda, &cuda_unavailable_reason) &&
                                         register_cuda<float, false>() && register_cuda<float, true>()
#if !defined(GEOVORONOI_CLI_LEAN) && !defined(GEOVORONOI_CLI_CUDA_FLOAT_ONLY)
                                         && register_cuda<double, false>() && register_cuda<double, true>()
#endif
    ;

}  // namespace

}  // namespace gvcli

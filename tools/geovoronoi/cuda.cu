// The geovoronoi tool's CUDA backend: the only translation unit that includes the CUDA headers
// (built by nvcc when the geovoronoi::cuda target exists; see tools/geovoronoi/CMakeLists.txt). It exposes
// plain host functions (solve.hpp) so the rest of the tool stays ordinary C++.

#include "solve.hpp"

#include <geovoronoi/backend/cuda.cuh>

#include <cuda_runtime.h>

namespace gvcli {

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

template <class T>
gv::diagram<T, 3> cuda_voronoi(const problem_spec<T>& s) {
  return solve_voronoi(gv::cuda::par, s);
}

template <class T>
gv::shape_weights<T, 3> cuda_shape(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const gv::shape_options& opt) {
  return solve_shape(gv::cuda::par, s, d, opt);
}

template <class T>
gv::point_weights<T> cuda_shape_at(const problem_spec<T>& s, const gv::diagram<T, 3>& d, const point_spec& at,
                                   const gv::shape_options& opt) {
  return solve_shape_at(gv::cuda::par, s, d, at, opt);
}

template gv::diagram<float, 3> cuda_voronoi(const problem_spec<float>&);
template gv::diagram<double, 3> cuda_voronoi(const problem_spec<double>&);
template gv::shape_weights<float, 3> cuda_shape(const problem_spec<float>&, const gv::diagram<float, 3>&,
                                               const gv::shape_options&);
template gv::shape_weights<double, 3> cuda_shape(const problem_spec<double>&, const gv::diagram<double, 3>&,
                                                const gv::shape_options&);
template gv::point_weights<float> cuda_shape_at(const problem_spec<float>&, const gv::diagram<float, 3>&,
                                              const point_spec&, const gv::shape_options&);
template gv::point_weights<double> cuda_shape_at(const problem_spec<double>&, const gv::diagram<double, 3>&,
                                               const point_spec&, const gv::shape_options&);

}  // namespace gvcli

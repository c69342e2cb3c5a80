#pragma once
// CUDA errors as exceptions, and RAII owners of device memory and events. Every runtime call of the
// backend goes through GEOVORONOI_CUDA_CHECK, so a failure (no device, out of memory, a faulting
// kernel) surfaces as geovoronoi::cuda::cuda_error naming the call and carrying CUDA's message; the
// owners release what was allocated on every path, exceptional or not.

#include <geovoronoi/error.hpp>

#include <cuda_runtime.h>

#include <cstddef>
#include <string>
#include <utility>

/// Kernels have hidden visibility, so two shared libraries built from these headers do not share
/// (and mix up) instantiations.
#define GEOVORONOI_KERNEL __global__ __attribute__((visibility("hidden")))

namespace geovoronoi::cuda {

/// A CUDA runtime error: the failing call, where it was made, and CUDA's own description.
class cuda_error : public geovoronoi::error {
 public:
  cuda_error(cudaError_t code, const std::string& what)
      : geovoronoi::error(what), code_(code) {}
  /// The CUDA error code.
  cudaError_t code() const noexcept { return code_; }

 private:
  cudaError_t code_;
};

namespace detail {

inline void check(cudaError_t e, const char* call, const char* file, int line) {
  if (e == cudaSuccess) return;
  // clear a non-sticky error so that later, unrelated calls do not report it again
  (void)cudaGetLastError();
  throw cuda_error(e, std::string("geovoronoi::cuda: ") + call + " failed at " + file + ":" + std::to_string(line) +
                          ": " + cudaGetErrorName(e) + ": " + cudaGetErrorString(e));
}

#define GEOVORONOI_CUDA_CHECK(call) ::geovoronoi::cuda::detail::check((call), #call, __FILE__, __LINE__)
/// After a kernel launch: configuration errors are reported at once, faults at the next sync.
#define GEOVORONOI_CUDA_CHECK_LAUNCH(name) \
  ::geovoronoi::cuda::detail::check(cudaGetLastError(), "launch of " name, __FILE__, __LINE__)

/// Owner of `count` elements of T in device memory (cudaMalloc, never managed memory). Move-only.
template <class T>
class device_buffer {
 public:
  device_buffer() = default;
  explicit device_buffer(std::size_t count) : size_(count) {
    if (count) {
      const cudaError_t e = cudaMalloc(reinterpret_cast<void**>(&ptr_), count * sizeof(T));
      if (e != cudaSuccess) {
        ptr_ = nullptr;
        size_ = 0;
        check(e, ("cudaMalloc of " + std::to_string(count * sizeof(T)) + " bytes").c_str(), __FILE__, __LINE__);
      }
    }
  }
  device_buffer(const device_buffer&) = delete;
  device_buffer& operator=(const device_buffer&) = delete;
  device_buffer(device_buffer&& o) noexcept : ptr_(std::exchange(o.ptr_, nullptr)), size_(std::exchange(o.size_, 0)) {}
  device_buffer& operator=(device_buffer&& o) noexcept {
    if (this != &o) {
      release();
      ptr_ = std::exchange(o.ptr_, nullptr);
      size_ = std::exchange(o.size_, 0);
    }
    return *this;
  }
  ~device_buffer() { release(); }

  T* data() const noexcept { return ptr_; }
  std::size_t size() const noexcept { return size_; }
  std::size_t bytes() const noexcept { return size_ * sizeof(T); }

  void upload(const T* host, std::size_t count, cudaStream_t s) {
    if (count) GEOVORONOI_CUDA_CHECK(cudaMemcpyAsync(ptr_, host, count * sizeof(T), cudaMemcpyHostToDevice, s));
  }
  void download(T* host, std::size_t count, cudaStream_t s) const {
    if (count) GEOVORONOI_CUDA_CHECK(cudaMemcpyAsync(host, ptr_, count * sizeof(T), cudaMemcpyDeviceToHost, s));
  }
  /// Sets every byte to @p byte.
  void fill_bytes(int byte, cudaStream_t s) {
    if (size_) GEOVORONOI_CUDA_CHECK(cudaMemsetAsync(ptr_, byte, bytes(), s));
  }

 private:
  void release() noexcept {
    // cudaFree synchronises; its error (e.g. a sticky fault already reported) cannot be thrown here
    if (ptr_) (void)cudaFree(ptr_);
    ptr_ = nullptr;
  }
  T* ptr_ = nullptr;
  std::size_t size_ = 0;
};

/// Owner of a CUDA event.
class event {
 public:
  event() { GEOVORONOI_CUDA_CHECK(cudaEventCreate(&e_)); }
  event(const event&) = delete;
  event& operator=(const event&) = delete;
  ~event() { (void)cudaEventDestroy(e_); }
  cudaEvent_t get() const noexcept { return e_; }

 private:
  cudaEvent_t e_ = nullptr;
};

/// Waits for @p s and reports any fault of the work queued on it.
inline void sync(cudaStream_t s, const char* what) {
  check(cudaStreamSynchronize(s), what, __FILE__, __LINE__);
}

}  // namespace detail
}  // namespace geovoronoi::cuda

#pragma once
// Volume-sized scratch arrays. Random access over hundreds of megabytes thrashes the TLB with 4 KiB
// pages, so on Linux a large allocation is 2 MiB aligned and advised to use transparent huge pages
// (where the system's policy is `madvise`, the common default, nothing else asks for them).

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace geovoronoi::detail {

/// Allocates @p bytes (free with std::free): from 2 MiB up, 2 MiB aligned and advised to use
/// transparent huge pages; below that, plain malloc. Null for 0 bytes; std::bad_alloc on failure.
inline void* allocate_big(std::size_t bytes) {
  if (bytes == 0) return nullptr;
  constexpr std::size_t huge = std::size_t(2) << 20;
  void* p = nullptr;
  if (bytes >= huge) {
    const std::size_t rounded = (bytes + huge - 1) / huge * huge;
    p = std::aligned_alloc(huge, rounded);
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (p) ::madvise(p, rounded, MADV_HUGEPAGE);
#endif
  } else {
    p = std::malloc(bytes);
  }
  if (!p) throw std::bad_alloc();
  return p;
}

/// A standard allocator over allocate_big(): for std::vector working arrays that are indexed at
/// random over a whole volume (the Thrust backend's keys, flags and lists on host systems).
template <class T>
struct huge_page_allocator {
  using value_type = T;
  huge_page_allocator() noexcept = default;
  template <class U>
  huge_page_allocator(const huge_page_allocator<U>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_alloc();
    return static_cast<T*>(allocate_big(n * sizeof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept { std::free(p); }
  template <class U>
  bool operator==(const huge_page_allocator<U>&) const noexcept {
    return true;
  }
  template <class U>
  bool operator!=(const huge_page_allocator<U>&) const noexcept {
    return false;
  }
};

/// A volume-sized array of trivially copyable values, uninitialised, on allocate_big().
template <class T>
class big_array {
  static_assert(std::is_trivially_copyable_v<T>, "big_array holds trivially copyable values only");

 public:
  big_array() = default;
  explicit big_array(std::size_t n) : p_(static_cast<T*>(allocate_big(n * sizeof(T)))), n_(n) {}
  big_array(const big_array&) = delete;
  big_array& operator=(const big_array&) = delete;
  big_array(big_array&& o) noexcept : p_(o.p_), n_(o.n_) { o.p_ = nullptr, o.n_ = 0; }
  big_array& operator=(big_array&& o) noexcept {
    if (this != &o) {
      std::free(p_);
      p_ = o.p_, n_ = o.n_;
      o.p_ = nullptr, o.n_ = 0;
    }
    return *this;
  }
  ~big_array() { std::free(p_); }

  T* data() noexcept { return p_; }
  const T* data() const noexcept { return p_; }
  std::size_t size() const noexcept { return n_; }
  T& operator[](std::size_t i) noexcept { return p_[i]; }
  const T& operator[](std::size_t i) const noexcept { return p_[i]; }

 private:
  T* p_ = nullptr;
  std::size_t n_ = 0;
};

}  // namespace geovoronoi::detail

#pragma once
// Volume-sized scratch arrays. Random access over hundreds of megabytes thrashes the TLB with 4 KiB
// pages, so on Linux the allocation is 2 MiB aligned and advised to use transparent huge pages.

#include <cstddef>
#include <cstdlib>
#include <new>
#include <type_traits>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace geovoronoi::detail {

template <class T>
class big_array {
  static_assert(std::is_trivially_copyable_v<T>, "big_array holds trivially copyable values only");

 public:
  big_array() = default;
  explicit big_array(std::size_t n) : n_(n) {
    if (n == 0) return;
    constexpr std::size_t huge = std::size_t(2) << 20;
    const std::size_t bytes = n * sizeof(T);
    if (bytes >= huge) {
      const std::size_t rounded = (bytes + huge - 1) / huge * huge;
      p_ = static_cast<T*>(std::aligned_alloc(huge, rounded));
#if defined(__linux__) && defined(MADV_HUGEPAGE)
      if (p_) ::madvise(p_, rounded, MADV_HUGEPAGE);
#endif
    } else {
      p_ = static_cast<T*>(std::malloc(bytes));
    }
    if (!p_) throw std::bad_alloc();
  }
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

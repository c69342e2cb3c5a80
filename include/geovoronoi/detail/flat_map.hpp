#pragma once
// An open-addressing hash map from voxel index to a small value, for searches whose scratch memory
// must be bounded by what they visit rather than by the volume (insert-query, bounded solves).

#include <geovoronoi/config.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi::detail {

template <class V>
class flat_map {
 public:
  explicit flat_map(std::size_t expected = 64) { reset(expected); }

  void reset(std::size_t expected = 64) {
    std::size_t cap = 16;
    while (cap < 2 * expected) cap <<= 1;
    slots_.assign(cap, slot{no_index, V{}});
    size_ = 0;
  }
  std::size_t size() const noexcept { return size_; }

  /// Pointer to the value of @p k, or nullptr.
  V* find(index_t k) noexcept {
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash(k) & mask;; i = (i + 1) & mask) {
      if (slots_[i].key == k) return &slots_[i].value;
      if (slots_[i].key == no_index) return nullptr;
    }
  }
  /// The value of @p k, inserting @p init first if absent.
  V& get_or_insert(index_t k, const V& init) {
    if (2 * (size_ + 1) > slots_.size()) grow();
    const std::size_t mask = slots_.size() - 1;
    for (std::size_t i = hash(k) & mask;; i = (i + 1) & mask) {
      if (slots_[i].key == k) return slots_[i].value;
      if (slots_[i].key == no_index) {
        slots_[i] = {k, init};
        ++size_;
        return slots_[i].value;
      }
    }
  }
  template <class F>
  void for_each(F&& f) const {
    for (const auto& s : slots_)
      if (s.key != no_index) f(s.key, s.value);
  }

 private:
  struct slot {
    index_t key;
    V value;
  };
  static std::size_t hash(index_t k) noexcept {
    std::uint64_t x = std::uint64_t(k) * 0x9E3779B97F4A7C15ull;
    return std::size_t(x ^ (x >> 29));
  }
  void grow() {
    std::vector<slot> old;
    old.swap(slots_);
    slots_.assign(old.size() * 2, slot{no_index, V{}});
    size_ = 0;
    const std::size_t mask = slots_.size() - 1;
    for (const auto& s : old)
      if (s.key != no_index) {
        std::size_t i = hash(s.key) & mask;
        while (slots_[i].key != no_index) i = (i + 1) & mask;
        slots_[i] = s;
        ++size_;
      }
  }
  std::vector<slot> slots_;
  std::size_t size_ = 0;
};

}  // namespace geovoronoi::detail

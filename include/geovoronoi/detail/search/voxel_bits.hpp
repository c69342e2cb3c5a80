#pragma once
// A set of voxels as one bit each: the membership tests of the update and of the shape functions'
// update (invalidated, lowered, changed voxels; rows to recompute).

#include <geovoronoi/config.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi::detail::search {

class voxel_bits {
 public:
  explicit voxel_bits(index_t n) : w_(std::size_t((n + 63) / 64), 0) {}
  bool test(index_t v) const noexcept { return (w_[std::size_t(v >> 6)] >> (v & 63)) & 1u; }
  /// Sets the bit; true when it was clear.
  bool insert(index_t v) noexcept {
    auto& w = w_[std::size_t(v >> 6)];
    const std::uint64_t b = std::uint64_t(1) << (v & 63);
    if (w & b) return false;
    w |= b;
    return true;
  }
  void erase(index_t v) noexcept { w_[std::size_t(v >> 6)] &= ~(std::uint64_t(1) << (v & 63)); }
  /// The words (bit v of word v / 64), for loops that keep the pointer in a register.
  std::uint64_t* words() noexcept { return w_.data(); }

 private:
  std::vector<std::uint64_t> w_;
};

}  // namespace geovoronoi::detail::search

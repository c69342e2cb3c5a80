#pragma once
// The monotone radix heap of every host search.
//
// Bucket b > 0 holds the items whose key first differs from the last extracted key at bit b-1;
// bucket 0 holds keys equal to it. Extracting from an empty bucket 0 redistributes the lowest
// non-empty bucket around its minimum, and every item moves to a strictly lower bucket each time, so
// each item is touched O(key bits) times at most, and in practice about twice. Keys pushed must not
// be smaller than the last extracted key (Dijkstra guarantees it for non-negative weights).
//
// One template, two instances: radix_heap<T> orders packed (distance, label) keys with 64-bit voxel
// indices (the engines, the update); distance_heap<T> orders distances alone with 32-bit voxel
// indices (the count-only insert-queries on the padded grid, 8-byte items for float).

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/key.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi::detail::search {

/// @tparam Key     key_traits<T> or distance_key<T>: key_type, bits, bucket(a, b).
/// @tparam Payload the voxel index type carried by an item.
template <class Key, class Payload>
class basic_radix_heap {
 public:
  using key_type = typename Key::key_type;
  struct item {
    key_type key;
    Payload voxel;
  };
  static constexpr int nbuckets = Key::bits + 1;

  bool empty() const noexcept { return size_ == 0; }
  std::size_t size() const noexcept { return size_; }

  /// @pre !(key < last extracted key)
  void push(key_type key, Payload voxel) {
    const int b = Key::bucket(key, last_);
    buckets_[b].push_back({key, voxel});
    mask_[b >> 6] |= std::uint64_t(1) << (b & 63);
    ++size_;
  }

  /// Remove and return an item with the smallest key. @pre !empty()
  item pop() {
    if (buckets_[0].empty()) refill();
    const item x = buckets_[0].back();
    buckets_[0].pop_back();
    if (buckets_[0].empty()) mask_[0] &= ~std::uint64_t(1);
    --size_;
    return x;
  }

  /// The item pop() would return next if it is already known without a refill, else nullptr.
  const item* peek_ready() const noexcept { return buckets_[0].empty() ? nullptr : &buckets_[0].back(); }

  void clear() {
    for (auto& b : buckets_) b.clear();
    for (auto& m : mask_) m = 0;
    size_ = 0;
    last_ = key_type{};
  }

 private:
  void refill() {
    int b = 0;
    for (int w = 0; w < nmask; ++w)
      if (mask_[w]) {
        b = w * 64 + __builtin_ctzll(mask_[w]);
        break;
      }
    auto& src = buckets_[b];
    key_type m = src[0].key;
    for (const auto& x : src) m = x.key < m ? x.key : m;
    last_ = m;
    for (const auto& x : src) {
      const int nb = Key::bucket(x.key, last_);
      buckets_[nb].push_back(x);
      mask_[nb >> 6] |= std::uint64_t(1) << (nb & 63);
    }
    src.clear();
    mask_[b >> 6] &= ~(std::uint64_t(1) << (b & 63));
  }

  static constexpr int nmask = (nbuckets + 63) / 64;
  std::vector<item> buckets_[nbuckets];
  std::uint64_t mask_[nmask] = {};
  key_type last_{};
  std::size_t size_ = 0;
};

/// Packed (distance, label) keys, 64-bit voxel indices.
template <class T>
using radix_heap = basic_radix_heap<key_traits<T>, index_t>;

/// Distances alone, 32-bit voxel indices (grids of fewer than 2^32 voxels).
template <class T>
using distance_heap = basic_radix_heap<distance_key<T>, std::uint32_t>;

}  // namespace geovoronoi::detail::search

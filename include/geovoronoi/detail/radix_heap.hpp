#pragma once
// A monotone radix heap keyed on packed (distance bits, label) keys.
//
// Bucket b > 0 holds the items whose key first differs from the last extracted key at bit b-1;
// bucket 0 holds keys equal to it. Extracting from an empty bucket 0 redistributes the lowest
// non-empty bucket around its minimum, and every item moves to a strictly lower bucket each time, so
// each item is touched O(key bits) times at most, and in practice about twice. Keys pushed must not
// be smaller than the last extracted key (Dijkstra guarantees it for non-negative weights).

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/key.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi::detail {

template <class T>
class radix_heap {
 public:
  using traits = key_traits<T>;
  using key_type = typename traits::key_type;
  struct item {
    key_type key;
    index_t voxel;
  };
  static constexpr int nbuckets = traits::bits + 1;

  bool empty() const noexcept { return size_ == 0; }
  std::size_t size() const noexcept { return size_; }

  /// @pre !(key < last extracted key)
  void push(key_type key, index_t voxel) {
    const int b = traits::bucket(key, last_);
    buckets_[b].push_back({key, voxel});
    mask_[b >> 6] |= std::uint64_t(1) << (b & 63);
    ++size_;
  }

  /// Remove and return an item with the smallest key. @pre !empty()
  item pop() {
    if (buckets_[0].empty()) refill();
    item x = buckets_[0].back();
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
    for (const auto& x : src)
      if (x.key < m) m = x.key;
    last_ = m;
    for (const auto& x : src) {
      const int nb = traits::bucket(x.key, last_);
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

}  // namespace geovoronoi::detail

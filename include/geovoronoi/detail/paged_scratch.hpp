#pragma once
// Sparse per-voxel scratch for searches that visit a small part of a large grid (insert-query,
// bounded solves), with the lookup cost of a dense array.
//
// The linear voxel index is cut into pages of 2^PageBits consecutive voxels. A page table with one
// 32-bit entry per page of the grid maps a page to its slot in a pool of dense pages (the entry is
// the slot's first index into the pool, so a lookup needs no multiplication); a page is
// handed out, and filled by the caller, the first time one of its voxels is touched. A lookup is a
// shift, a mask and one indirection: no hashing, no probing. clear() resets only the table entries
// of the pages handed out, so one scratch serves any number of searches at a cost proportional to
// what each visits; the table is the only per-grid allocation (4 bytes per 2^PageBits voxels) and is
// made once per grid size.

#include <geovoronoi/config.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace geovoronoi::detail {

template <class Value, int PageBits = 6>
class paged_scratch {
  static_assert(std::is_trivially_copyable_v<Value>, "paged_scratch holds trivially copyable values only");
  static_assert(PageBits >= 0 && PageBits <= 16, "paged_scratch: PageBits must be in [0, 16]");

 public:
  static constexpr int page_bits = PageBits;
  static constexpr index_t page_size = index_t(1) << PageBits;
  static constexpr index_t offset_mask = page_size - 1;

  paged_scratch() = default;
  paged_scratch(const paged_scratch&) = delete;
  paged_scratch& operator=(const paged_scratch&) = delete;
  // moving a vector keeps its buffer, so the cached pointers stay right; a moved-from scratch
  // re-derives them on its next prepare() and page
  paged_scratch(paged_scratch&&) noexcept = default;
  paged_scratch& operator=(paged_scratch&&) noexcept = default;

  /// Prepare for searches over voxels [0, n), forgetting every page of an earlier search (one
  /// interrupted by an exception, say). The table is kept if it covers exactly as many pages (it is
  /// all-empty between searches); otherwise it is reallocated.
  void prepare(index_t n) {
    if (n < 0) throw std::invalid_argument("paged_scratch: negative voxel count");
    clear();
    const index_t pages = (n + offset_mask) >> PageBits;
    if (std::size_t(pages) != table_store_.size()) {
      table_store_.assign(std::size_t(pages), 0u);
      table_store_.shrink_to_fit();
      table_ = table_store_.data();
    }
    voxels_ = n;
  }
  /// Number of voxels prepare() was given.
  index_t voxels() const noexcept { return voxels_; }

  /// The value of voxel @p v, or nullptr if its page was not handed out. @pre 0 <= v < voxels()
  const Value* find(index_t v) const noexcept {
    const std::uint32_t e = table_[std::size_t(v >> PageBits)];
    return e ? pool_ + (std::size_t(e) + std::size_t(v & offset_mask)) : nullptr;
  }

  /**
   * The value of voxel @p v, handing out its page first if needed: then
   * fill(first_voxel, values, count) must initialise the page's values (count is page_size except
   * for the grid's last page, whose values past the grid are never read). The reference stays valid
   * until the next page is handed out. @pre 0 <= v < voxels()
   */
  template <class Fill>
  Value& touch(index_t v, Fill&& fill) {
    std::uint32_t& e = table_[std::size_t(v >> PageBits)];
    if (__builtin_expect(e == 0, 0)) e = allocate(v >> PageBits, fill);
    return pool_[std::size_t(e) + std::size_t(v & offset_mask)];
  }

  /// Number of pages handed out since the last clear().
  std::size_t pages() const noexcept { return touched_.size(); }
  bool empty() const noexcept { return touched_.empty(); }

  /// Calls f(first_voxel, values, count) for each page handed out, in increasing voxel order. Pages,
  /// not voxels, are ordered: by walking the table between the lowest and the highest page handed
  /// out when that span is at most 8 times their number (a search's pages are clustered), else by
  /// sorting their numbers; either way in O(pages handed out) or O(p log p).
  template <class F>
  void for_each_page_sorted(F&& f) {
    if (touched_.empty()) return;
    if (std::size_t(high_ - low_) < 8 * touched_.size()) {
      for (index_t page = low_; page <= high_; ++page)
        if (const std::uint32_t e = table_[std::size_t(page)]) {
          const index_t first = page << PageBits;
          f(first, pool_ + std::size_t(e), std::min(page_size, voxels_ - first));
        }
      return;
    }
    std::sort(touched_.begin(), touched_.end());
    for (const index_t page : touched_) {
      const index_t first = page << PageBits;
      f(first, pool_ + std::size_t(table_[std::size_t(page)]), std::min(page_size, voxels_ - first));
    }
  }

  /// Forget every value: only the table entries of the pages handed out are reset.
  void clear() noexcept {
    for (const index_t page : touched_) table_[std::size_t(page)] = 0u;
    touched_.clear();
    used_ = 1;
  }

  /// Bytes held (table, pool, page list): what the scratch costs between searches.
  std::size_t bytes() const noexcept {
    return table_store_.capacity() * sizeof(std::uint32_t) + pool_store_.capacity() * sizeof(Value) +
           touched_.capacity() * sizeof(index_t);
  }

 private:
  template <class Fill>
  /// Hands out a slot for @p page, fills it, and returns its first index into the pool.
  std::uint32_t allocate(index_t page, Fill& fill) {
    // table entries hold a slot's first index into the pool, which must fit in 32 bits
    if ((std::uint64_t(used_) + 1) << PageBits > std::uint64_t(UINT32_MAX))
      throw std::length_error("paged_scratch: one search touched more than 2^32 voxels' worth of pages");
    const std::size_t base = std::size_t(used_) << PageBits;
    if (pool_store_.size() < base + std::size_t(page_size)) {
      pool_store_.resize(std::max(base + std::size_t(page_size), 2 * pool_store_.size()));
      pool_ = pool_store_.data();
    }
    if (touched_.empty()) low_ = high_ = page;
    low_ = std::min(low_, page);
    high_ = std::max(high_, page);
    touched_.push_back(page);
    const index_t first = page << PageBits;
    fill(first, pool_ + base, std::min(page_size, voxels_ - first));
    ++used_;
    return std::uint32_t(base);
  }

  std::vector<Value> pool_store_;       ///< page slot s at [s << PageBits, (s + 1) << PageBits); slot 0 unused
  std::vector<std::uint32_t> table_store_;  ///< page -> index of its slot's first value in the pool, 0 = none
  Value* pool_ = nullptr;               ///< pool_store_.data(), table_store_.data(): read in every lookup
  std::uint32_t* table_ = nullptr;
  std::vector<index_t> touched_;        ///< pages handed out since clear(), in allocation order
  std::uint32_t used_ = 1;              ///< pool slots in use, unused slot 0 included
  index_t voxels_ = 0;
  index_t low_ = 0, high_ = 0;          ///< lowest and highest page handed out since clear()
};

}  // namespace geovoronoi::detail

#pragma once
// Sparse per-voxel scratch for searches that visit a small part of a large grid (insert-query,
// bounded solves), with the lookup cost of a dense array.
//
// The linear voxel index is cut into pages of 2^PageBits consecutive voxels. A page table with one
// pointer per page of the grid points at the page's values in a pool, or is null; a page is handed
// out, and filled by the caller, the first time one of its voxels is touched. A lookup is a shift,
// one load, a test and a masked index: no hashing, no probing. The pool grows in chunks that never
// move, so a value's address is stable until clear(). clear() resets only the table entries of the
// pages handed out, so one scratch serves any number of searches at a cost proportional to what
// each visits; the table is the only per-grid allocation (8 bytes per 2^PageBits voxels) and is made
// once per grid size.

#include <geovoronoi/config.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace geovoronoi::detail::search {

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
  paged_scratch(paged_scratch&&) noexcept = default;  // chunks and the table move with their buffers
  paged_scratch& operator=(paged_scratch&&) noexcept = default;

  /// Prepare for searches over voxels [0, n), forgetting every page of an earlier search (one
  /// interrupted by an exception, say). The table is kept if it covers exactly as many pages (it is
  /// all-null between searches); otherwise it is reallocated.
  void prepare(index_t n) {
    if (n < 0) throw std::invalid_argument("paged_scratch: negative voxel count");
    clear();
    const index_t pages = (n + offset_mask) >> PageBits;
    if (std::size_t(pages) != table_.size()) {
      table_.assign(std::size_t(pages), nullptr);
      table_.shrink_to_fit();
    }
    voxels_ = n;
  }
  /// Number of voxels prepare() was given.
  index_t voxels() const noexcept { return voxels_; }

  /// The value of voxel @p v, or nullptr if its page was not handed out. @pre 0 <= v < voxels()
  const Value* find(index_t v) const noexcept {
    const Value* page = table_[std::size_t(v >> PageBits)];
    return page ? page + (v & offset_mask) : nullptr;
  }

  /**
   * The value of voxel @p v, handing out its page first if needed: then
   * fill(first_voxel, values, count) must initialise the page's values (count is page_size except
   * for the grid's last page, whose values past the grid are never read). The reference stays valid
   * until clear(). @pre 0 <= v < voxels()
   */
  template <class Fill>
  Value& touch(index_t v, Fill&& fill) {
    Value*& page = table_[std::size_t(v >> PageBits)];
    if (__builtin_expect(page == nullptr, 0)) page = allocate(v >> PageBits, fill);
    return page[v & offset_mask];
  }

  /// Number of pages handed out since the last clear().
  std::size_t pages() const noexcept { return touched_.size(); }
  bool empty() const noexcept { return touched_.empty(); }

  /// Calls f(first_voxel, values, count) for each page handed out, in increasing voxel order. Pages,
  /// not voxels, are ordered: by walking the table between the lowest and the highest page handed
  /// out when that span is under 8 times their number (a search's pages are clustered), else by
  /// sorting their numbers.
  template <class F>
  void for_each_page_sorted(F&& f) {
    if (touched_.empty()) return;
    auto visit = [&](index_t page, const Value* values) {
      const index_t first = page << PageBits;
      f(first, values, std::min(page_size, voxels_ - first));
    };
    if (std::size_t(high_ - low_) < 8 * touched_.size()) {
      for (index_t page = low_; page <= high_; ++page)
        if (const Value* values = table_[std::size_t(page)]) visit(page, values);
      return;
    }
    std::sort(touched_.begin(), touched_.end());
    for (const index_t page : touched_) visit(page, table_[std::size_t(page)]);
  }

  /// Forget every value: only the table entries of the pages handed out are reset.
  void clear() noexcept {
    for (const index_t page : touched_) table_[std::size_t(page)] = nullptr;
    touched_.clear();
  }

  /// Bytes held (table, pool, page list): what the scratch costs between searches.
  std::size_t bytes() const noexcept {
    return table_.capacity() * sizeof(Value*) + chunks_.size() * chunk_values * sizeof(Value) +
           touched_.capacity() * sizeof(index_t);
  }

 private:
  static constexpr std::size_t chunk_pages = 64;
  static constexpr std::size_t chunk_values = chunk_pages << PageBits;

  /// Hands out the next free page of the pool to @p page and fills it.
  template <class Fill>
  Value* allocate(index_t page, Fill& fill) {
    const std::size_t slot = touched_.size();
    if (slot / chunk_pages == chunks_.size()) chunks_.emplace_back(new Value[chunk_values]);
    Value* values = chunks_[slot / chunk_pages].get() + ((slot % chunk_pages) << PageBits);
    if (touched_.empty()) low_ = high_ = page;
    low_ = std::min(low_, page);
    high_ = std::max(high_, page);
    touched_.push_back(page);
    const index_t first = page << PageBits;
    fill(first, values, std::min(page_size, voxels_ - first));
    return values;
  }

  std::vector<Value*> table_;                      ///< page -> its values, null if not handed out
  std::vector<std::unique_ptr<Value[]>> chunks_;   ///< the pool: slot s in chunk s / chunk_pages
  std::vector<index_t> touched_;                   ///< pages handed out since clear(); slot = position
  index_t voxels_ = 0;
  index_t low_ = 0, high_ = 0;                     ///< lowest and highest page handed out since clear()
};

}  // namespace geovoronoi::detail::search

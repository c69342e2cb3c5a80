#pragma once
/// @file cut.hpp
/// @brief Cut grid edges: the set of edges between neighbouring voxels that a cut separates, stored
///        in memory proportional to the cut's area, and a hash-table view for lookups in solvers.
///
/// Directions are the positions of the offsets in connectivity<N>::offsets(). That table is
/// symmetric about its middle: the opposite of direction d is N - 1 - d, and the directions
/// d >= N / 2 are the *forward* ones (offsets whose last non-zero coordinate, in z, y, x order, is
/// +1: lexicographically positive). An edge is stored once, at the voxel it leaves in a forward
/// direction, as bit d - N / 2 of that voxel's forward mask (at most 13 bits, for 26-connectivity).

#include <geovoronoi/config.hpp>
#include <geovoronoi/connectivity.hpp>
#include <geovoronoi/grid.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

/// Bits of one voxel's cut edges: forward mask (N / 2 bits) in a cut_set, all N directions in a
/// cut_view.
using cut_mask_t = std::uint32_t;

/// The direction opposite to @p d in a connectivity of @p n neighbours.
GEOVORONOI_HOST_DEVICE constexpr int opposite_direction(int d, int n) noexcept { return n - 1 - d; }

/// True when direction @p d of a connectivity of @p n neighbours is a forward one (lexicographically
/// positive offset).
GEOVORONOI_HOST_DEVICE constexpr bool is_forward_direction(int d, int n) noexcept { return d >= n / 2; }

/**
 * @brief A trivially copyable, read-only view of a cut: an open-addressing hash table from voxel
 *        index to the mask of *all* its cut directions (forward and backward), for solvers.
 *
 * A solver that pops voxel u calls incident(u) once and then tests one bit per neighbour, so a
 * voxel far from any cut costs one probe of a table whose size is proportional to the cut's area.
 * The table is filled from both ends of every cut edge, which makes cut(u, d) == cut(v, opposite d)
 * hold by construction. Keys are linear voxel indices, -1 marks an empty slot; capacity is a power
 * of two at least twice the number of keys (linear probing, multiplicative hashing), so every probe
 * sequence ends at an empty slot. Owned by a cut_table; valid while that table lives.
 */
struct cut_view {
  const index_t* keys = nullptr;      ///< capacity slots, -1 where empty
  const cut_mask_t* masks = nullptr;  ///< capacity masks: bit d set when the edge in direction d is cut
  std::uint64_t capacity = 0;         ///< 0 (no cut) or a power of two
  index_t count = 0;                  ///< number of voxels with at least one cut edge
  int shift = 64;                     ///< 64 - log2(capacity), for the hash

  /// Slot where the probe for voxel @p u starts.
  GEOVORONOI_HOST_DEVICE std::uint64_t home(index_t u) const noexcept {
    return (static_cast<std::uint64_t>(u) * 0x9E3779B97F4A7C15ull) >> shift;
  }

  /// Mask of the cut directions at voxel @p u (0 when none of its edges is cut).
  GEOVORONOI_HOST_DEVICE cut_mask_t incident(index_t u) const noexcept {
    if (count == 0) return 0;
    for (std::uint64_t s = home(u);; s = (s + 1) & (capacity - 1)) {
      const index_t k = keys[s];
      if (k == u) return masks[s];
      if (k < 0) return 0;
    }
  }

  /// True when the edge from voxel @p u in stencil direction @p d (forward or backward) is cut.
  /// @pre the edge lies inside the grid the cut was built for.
  GEOVORONOI_HOST_DEVICE bool cut(index_t u, int d) const noexcept { return (incident(u) >> d) & 1u; }

  /// True when no edge is cut.
  GEOVORONOI_HOST_DEVICE bool empty() const noexcept { return count == 0; }
};

/**
 * @brief A set of cut grid edges of one grid and one connectivity.
 *
 * Stored as a vector of (voxel, forward mask) entries sorted by voxel, only for voxels that leave at
 * least one cut edge in a forward direction: a cut of area A costs O(A) memory whatever the volume.
 * Host lookups binary-search it (O(log n)); solvers use the hash view of a cut_table built from it
 * (O(1)). Bulk construction goes through cut_builder (sort once), single edges through insert().
 *
 * @tparam Dim 2 or 3.
 *
 * @code
 * geovoronoi::grid<3> g({6, 6, 6});
 * geovoronoi::cut_set<3> cuts(g, geovoronoi::connectivity<6>{});
 * cuts.insert(g.index({2, 0, 0}), 3);         // direction 3 of connectivity<6> is (+1, 0, 0)
 * bool c = cuts.cut(g.index({3, 0, 0}), 2);   // the same edge from the other end: true
 * @endcode
 */
template <int Dim>
class cut_set {
  static_assert(Dim == 2 || Dim == 3, "geovoronoi::cut_set: Dim must be 2 or 3");

 public:
  /// One voxel with cut edges: bit f of `forward` is the edge in direction directions() / 2 + f.
  struct entry {
    index_t voxel;
    cut_mask_t forward;
    friend bool operator==(const entry& a, const entry& b) noexcept {
      return a.voxel == b.voxel && a.forward == b.forward;
    }
  };
  using const_iterator = typename std::vector<entry>::const_iterator;

  /// An empty set for no grid (assign to it).
  cut_set() = default;

  /// An empty set of cut edges of grid @p g under connectivity<N>.
  template <int N>
  cut_set(const grid<Dim>& g, connectivity<N>) : grid_(g), n_(N) {
    static_assert(connectivity<N>::dim == Dim, "geovoronoi::cut_set: the connectivity does not match the grid dimension");
    constexpr auto offs = connectivity<N>::offsets();
    for (int d = 0; d < N; ++d)
      for (int a = 0; a < 3; ++a) offset_[d][a] = a < Dim ? offs[d][a] : 0;
  }

  const grid<Dim>& geometry() const noexcept { return grid_; }
  /// N of the connectivity (number of stencil directions).
  int directions() const noexcept { return n_; }
  /// Offset of direction @p d (z = 0 in 2D).
  const std::array<int, 3>& offset(int d) const noexcept { return offset_[d]; }

  /// Number of cut edges.
  std::size_t size() const noexcept { return edges_; }
  bool empty() const noexcept { return edges_ == 0; }
  /// Number of voxels that store a forward mask.
  std::size_t voxel_count() const noexcept { return entries_.size(); }
  /// Bytes held by the set's storage (its capacity), for memory checks.
  std::size_t memory_bytes() const noexcept { return entries_.capacity() * sizeof(entry); }

  /// The entries, sorted by voxel, every mask non-zero.
  const_iterator begin() const noexcept { return entries_.begin(); }
  const_iterator end() const noexcept { return entries_.end(); }
  const std::vector<entry>& entries() const noexcept { return entries_; }

  /// Calls f(u, d) once for every cut edge, with d its forward direction from voxel u.
  template <class F>
  void for_each_edge(F&& f) const {
    for (const entry& e : entries_)
      for (int b = 0; b < n_ / 2; ++b)
        if ((e.forward >> b) & 1u) f(e.voxel, n_ / 2 + b);
  }

  /**
   * @brief The voxel across direction @p d from voxel @p u, or -1 when that edge leaves the grid.
   * @throws std::invalid_argument when u is not a voxel of the grid or d not a direction.
   */
  index_t neighbour(index_t u, int d) const {
    check(u, d);
    const coord<Dim> c = grid_.coords(u);
    coord<Dim> v{};
    for (int a = 0; a < Dim; ++a) v[a] = c[a] + offset_[d][a];
    return grid_.contains(v) ? grid_.index(v) : index_t(-1);
  }

  /**
   * @brief Cuts the edge from voxel @p u in direction @p d (either orientation). O(voxel_count())
   *        worst case; use cut_builder for many edges.
   * @throws std::invalid_argument when u is outside the grid, d is not a direction, or the edge
   *         leaves the grid.
   */
  void insert(index_t u, int d) {
    index_t from;
    int f;
    canonical(u, d, from, f);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), from,
                               [](const entry& e, index_t x) { return e.voxel < x; });
    const cut_mask_t bit = cut_mask_t(1) << f;
    if (it != entries_.end() && it->voxel == from) {
      if (!(it->forward & bit)) ++edges_;
      it->forward |= bit;
    } else {
      entries_.insert(it, entry{from, bit});
      ++edges_;
    }
  }

  /// True when the edge from voxel @p u in direction @p d is cut. O(log voxel_count()).
  /// @throws std::invalid_argument as insert().
  bool cut(index_t u, int d) const {
    index_t from;
    int f;
    canonical(u, d, from, f);
    auto it = std::lower_bound(entries_.begin(), entries_.end(), from,
                               [](const entry& e, index_t x) { return e.voxel < x; });
    return it != entries_.end() && it->voxel == from && ((it->forward >> f) & 1u);
  }

  /**
   * @brief Adds every edge of @p other (union), in O(voxel_count() + other.voxel_count()).
   * @throws std::invalid_argument when the grids or connectivities differ.
   */
  void merge(const cut_set& other) {
    if (!(other.grid_ == grid_) || other.n_ != n_)
      throw std::invalid_argument("geovoronoi::cut_set::merge: the two cut sets belong to different grids or connectivities");
    std::vector<entry> out;
    out.reserve(entries_.size() + other.entries_.size());
    const_iterator a = entries_.cbegin(), b = other.entries_.cbegin();
    const const_iterator ae = entries_.cend(), be = other.entries_.cend();
    while (a != ae || b != be) {
      if (b == be || (a != ae && a->voxel < b->voxel)) out.push_back(*a++);
      else if (a == ae || b->voxel < a->voxel) out.push_back(*b++);
      else out.push_back(entry{a->voxel, (a++)->forward | (b++)->forward});
    }
    out.shrink_to_fit();
    entries_ = std::move(out);
    recount();
  }

  /// Sets equal when grid, connectivity and edges are equal.
  friend bool operator==(const cut_set& a, const cut_set& b) noexcept {
    return a.grid_ == b.grid_ && a.n_ == b.n_ && a.entries_ == b.entries_;
  }
  friend bool operator!=(const cut_set& a, const cut_set& b) noexcept { return !(a == b); }

  /// Throws unless voxel @p u and direction @p d exist; the edge may still leave the grid.
  void check(index_t u, int d) const {
    if (u < 0 || u >= grid_.size())
      throw std::invalid_argument("geovoronoi::cut_set: voxel " + std::to_string(u) + " is outside the grid (" +
                                  std::to_string(grid_.size()) + " voxels)");
    if (d < 0 || d >= n_)
      throw std::invalid_argument("geovoronoi::cut_set: direction " + std::to_string(d) + " is not one of the " +
                                  std::to_string(n_) + " stencil directions");
  }

 private:
  template <int>
  friend class cut_builder;

  /// @p e must be sorted by voxel, unique, masks non-zero and valid for the grid.
  void assign_sorted(std::vector<entry> e) {
    entries_ = std::move(e);
    recount();
  }
  /// The forward end and forward bit of edge (u, d).
  void canonical(index_t u, int d, index_t& from, int& f) const {
    const index_t v = neighbour(u, d);
    if (v < 0)
      throw std::invalid_argument("geovoronoi::cut_set: the edge from voxel " + geovoronoi::to_string<Dim>(grid_.coords(u)) +
                                  " in direction " + std::to_string(d) + " leaves the grid");
    if (is_forward_direction(d, n_)) {
      from = u;
      f = d - n_ / 2;
    } else {
      from = v;
      f = opposite_direction(d, n_) - n_ / 2;
    }
  }
  void recount() noexcept {
    edges_ = 0;
    for (const entry& e : entries_)
      for (cut_mask_t m = e.forward; m; m &= m - 1) ++edges_;
  }

  grid<Dim> grid_{};
  int n_ = 0;
  std::array<std::array<int, 3>, 26> offset_{};
  std::vector<entry> entries_;
  std::size_t edges_ = 0;
};

/**
 * @brief Collects cut edges in any order, with repeats, and builds a cut_set by sorting once:
 *        O(k log k) for k insertions, memory O(k).
 */
template <int Dim>
class cut_builder {
 public:
  using entry = typename cut_set<Dim>::entry;

  template <int N>
  cut_builder(const grid<Dim>& g, connectivity<N> c) : set_(g, c) {}

  /// Records the edge from voxel @p u in direction @p d (either orientation).
  /// @throws std::invalid_argument as cut_set::insert().
  void insert(index_t u, int d) {
    index_t from;
    int f;
    set_.canonical(u, d, from, f);
    pending_.push_back(entry{from, cut_mask_t(1) << f});
  }

  /// Records forward mask @p forward at voxel @p u without checks (internal fast path).
  /// @pre every bit of @p forward is a forward edge of u that stays inside the grid.
  void insert_unchecked(index_t u, cut_mask_t forward) { pending_.push_back(entry{u, forward}); }

  /// Number of insertions so far (with repeats).
  std::size_t pending() const noexcept { return pending_.size(); }

  /// The set of every edge inserted so far (the builder is left empty).
  cut_set<Dim> build() {
    std::sort(pending_.begin(), pending_.end(), [](const entry& a, const entry& b) { return a.voxel < b.voxel; });
    std::vector<entry> out;
    for (const entry& e : pending_) {
      if (!out.empty() && out.back().voxel == e.voxel) out.back().forward |= e.forward;
      else out.push_back(e);
    }
    out.shrink_to_fit();
    pending_.clear();
    pending_.shrink_to_fit();
    cut_set<Dim> s = set_;
    s.assign_sorted(std::move(out));
    return s;
  }

 private:
  cut_set<Dim> set_;
  std::vector<entry> pending_;
};

/**
 * @brief Owner of the hash table behind a cut_view: every voxel incident to a cut edge, with the
 *        mask of all its cut directions. Memory: capacity * 12 bytes, capacity < 4 * incident voxels
 *        (at most 2 per cut edge), so O(cut area).
 */
class cut_table {
 public:
  cut_table() = default;

  template <int Dim>
  explicit cut_table(const cut_set<Dim>& s) {
    const int n = s.directions();
    std::vector<std::pair<index_t, cut_mask_t>> ends;
    ends.reserve(2 * s.size());
    s.for_each_edge([&](index_t u, int d) {
      ends.emplace_back(u, cut_mask_t(1) << d);
      ends.emplace_back(s.neighbour(u, d), cut_mask_t(1) << opposite_direction(d, n));
    });
    std::sort(ends.begin(), ends.end());
    std::size_t count = 0;
    for (std::size_t i = 0; i < ends.size(); ++i) count += (i == 0 || ends[i].first != ends[i - 1].first);
    if (count == 0) return;
    std::uint64_t cap = 2;
    int bits = 1;
    while (cap < 2 * count) cap <<= 1, ++bits;
    keys_.assign(cap, index_t(-1));
    masks_.assign(cap, 0);
    view_.capacity = cap;
    view_.shift = 64 - bits;
    view_.count = static_cast<index_t>(count);
    for (const auto& [u, m] : ends) {
      std::uint64_t slot = view_.home(u);
      while (keys_[slot] >= 0 && keys_[slot] != u) slot = (slot + 1) & (cap - 1);
      keys_[slot] = u;
      masks_[slot] |= m;
    }
    view_.keys = keys_.data();
    view_.masks = masks_.data();
  }

  cut_table(const cut_table& o) : keys_(o.keys_), masks_(o.masks_), view_(o.view_) { rebind(); }
  cut_table(cut_table&& o) noexcept
      : keys_(std::move(o.keys_)), masks_(std::move(o.masks_)), view_(o.view_) {
    rebind();
    o.view_ = cut_view{};
  }
  cut_table& operator=(cut_table o) noexcept {
    keys_.swap(o.keys_);
    masks_.swap(o.masks_);
    view_ = o.view_;
    rebind();
    return *this;
  }

  /// The view (valid while this table lives and is not assigned to).
  const cut_view& view() const noexcept { return view_; }
  /// The key and mask arrays (capacity entries each), e.g. to copy to a device.
  const std::vector<index_t>& keys() const noexcept { return keys_; }
  const std::vector<cut_mask_t>& masks() const noexcept { return masks_; }
  std::size_t memory_bytes() const noexcept {
    return keys_.capacity() * sizeof(index_t) + masks_.capacity() * sizeof(cut_mask_t);
  }

 private:
  void rebind() noexcept {
    view_.keys = keys_.empty() ? nullptr : keys_.data();
    view_.masks = masks_.empty() ? nullptr : masks_.data();
  }
  std::vector<index_t> keys_;
  std::vector<cut_mask_t> masks_;
  cut_view view_{};
};

}  // namespace geovoronoi

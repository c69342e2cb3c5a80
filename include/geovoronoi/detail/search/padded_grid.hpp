#pragma once
// The grid with one voxel of padding on each side of every axis, shared read-only by the count-only
// insert-queries on it (fused_padded.hpp, fused_lanes.hpp): every voxel of the grid has all its
// stencil neighbours in the array, so their neighbour loops need no bounds checks and no coordinate
// decoding. A padding voxel's bound is 0, which rejects every candidate (nd < 0 is false for every
// nd >= 0 and for NaN), exactly as a bounds check would.

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/metric.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi::detail::search {

/// The read-only part of the padded layout, built once per call and shared by every worker.
template <class P>
class padded_grid {
 public:
  using T = typename P::value_type;
  static constexpr int dim = P::dim;
  static constexpr int neighbours = P::neighbours;
  struct info {
    T bound;        // the initial key (fused_query::bound), 0 on the padding
    label_t label;  // the diagram's label inside the domain, no_label outside and on the padding
  };

  /// Whether the fast path applies to @p p: a padded grid indexable in 32 bits.
  static bool applies(const P& p) noexcept {
    std::uint64_t n = 1;
    for (int a = 0; a < dim; ++a) n *= std::uint64_t(p.geometry.extent(a)) + 2;
    return n < std::uint64_t(UINT32_MAX);
  }
  /// Bytes of the shared tables for @p p.
  static std::size_t shared_bytes(const P& p) noexcept {
    return padded_size(p) * (sizeof(info) + (P::has_cuts ? sizeof(cut_mask_t) : 0));
  }
  static std::size_t padded_size(const P& p) noexcept {
    std::size_t n = 1;
    for (int a = 0; a < dim; ++a) n *= std::size_t(p.geometry.extent(a)) + 2;
    return n;
  }

  padded_grid(const P& p, const T* dist, const label_t* lab) : dist_(dist) {
    using M = typename P::metric_type;
    for (int a = 0; a < 3; ++a) ext_[a] = a < dim ? p.geometry.extent(a) : 1;
    px_ = ext_[0] + 2;
    py_ = ext_[1] + 2;
    pz_ = dim == 3 ? ext_[2] + 2 : 1;
    info_.assign(padded_size(p), info{T(0), no_label});
    for_each_row([&](index_t o, index_t w, index_t n) {
      info* row = info_.data() + w;
      for (index_t x = 0; x < n; ++x) {
        const index_t v = o + x;
        const bool in = detail::inside<M>(p.field[v]);
        row[x].bound = dist[v] > T(0) && in ? dist[v] : T(0);
        row[x].label = in ? lab[v] : no_label;
      }
    });
    for (int k = 0; k < neighbours; ++k) {
      delta_[k] = p.edges.offset[k][0] + px_ * (p.edges.offset[k][1] + py_ * p.edges.offset[k][2]);
      length_[k] = p.edges.length[k];
    }
    if constexpr (P::has_cuts) {
      cut_.assign(info_.size(), 0);
      const cut_view& c = p.cuts;
      for (std::uint64_t s = 0; s < c.capacity; ++s)
        if (c.keys[s] >= 0) cut_[std::size_t(pad(c.keys[s]))] = c.masks[s];
    }
  }

  std::size_t bytes() const noexcept { return info_.capacity() * sizeof(info) + cut_.capacity() * sizeof(cut_mask_t); }
  /// Cut directions of the voxel at padded index @p w (problems with cuts only).
  cut_mask_t cut_mask(index_t w) const noexcept { return cut_[std::size_t(w)]; }
  std::size_t size() const noexcept { return info_.size(); }
  const info* data() const noexcept { return info_.data(); }
  index_t extent(int a) const noexcept { return ext_[a]; }
  /// Calls f(o, w, n) for each x-row of the grid: its first voxel o, its first padded index w, its
  /// length n.
  template <class F>
  void for_each_row(F&& f) const {
    for (index_t z = 0; z < ext_[2]; ++z)
      for (index_t y = 0; y < ext_[1]; ++y) f(ext_[0] * (y + ext_[1] * z), pad(0, y, z), ext_[0]);
  }
  /// Padded index of grid voxel (x, y, z).
  index_t pad(index_t x, index_t y, index_t z) const noexcept {
    return (x + 1) + px_ * ((y + 1) + py_ * (z + (dim == 3 ? 1 : 0)));
  }
  index_t pad(index_t v) const noexcept {
    const index_t x = v % ext_[0], r = v / ext_[0];
    return pad(x, r % ext_[1], r / ext_[1]);
  }
  /// Grid index of a padded index that lies in the grid.
  index_t unpad(index_t w) const noexcept {
    const index_t x = w % px_ - 1, r = w / px_;
    const index_t y = r % py_ - 1, z = r / py_ - (dim == 3 ? 1 : 0);
    return x + ext_[0] * (y + ext_[1] * z);
  }
  index_t padded_delta(int a, int dir) const noexcept {
    const index_t s = a == 0 ? 1 : a == 1 ? px_ : px_ * py_;
    return dir * s;
  }
  /// The 2*Dim face neighbours of a voxel on the padded layout: linear offset, stencil edge, axis.
  struct face_table {
    index_t delta[2 * dim];
    int edge[2 * dim];
    int axis[2 * dim];
  };
  template <class Face>
  face_table padded_faces(const std::vector<Face>& faces) const {
    face_table t{};
    for (int i = 0; i < 2 * dim; ++i) {
      const auto& f = faces[std::size_t(i)];
      t.delta[i] = padded_delta(f.axis, f.dir);
      t.edge[i] = f.edge;
      t.axis[i] = f.axis;
    }
    return t;
  }
  /// Calls f(i, w, k, bw) for each face i (of table @p ft) of padded voxel v that is not cut and whose
  /// neighbour w is in the domain with a label: label k, bound bw. A Laplace facet's candidates.
  template <class F>
  void for_each_labelled_face(std::uint32_t v, const face_table& ft, F&& f) const {
    cut_mask_t cut = 0;  // a cut face is no facet
    if constexpr (P::has_cuts) cut = cut_mask(index_t(v));
    for (int i = 0; i < 2 * dim; ++i) {
      if ((cut >> ft.edge[i]) & 1u) continue;
      const index_t w = index_t(v) + ft.delta[i];
      const label_t k = info_[std::size_t(w)].label;  // no_label: padding (off the grid), outside, or unreached
      if (k == no_label) continue;
      f(i, w, k, info_[std::size_t(w)].bound);
    }
  }
  /// The diagram's distance of padded voxel w whose bound is @p bw: the bound where it is > 0 (then
  /// they are equal), else read.
  T diagram_distance(index_t w, T bw) const noexcept { return bw > T(0) ? bw : dist_[unpad(w)]; }
  const index_t* delta() const noexcept { return delta_; }
  const T* length() const noexcept { return length_; }
  const T* dist() const noexcept { return dist_; }

 private:
  const T* dist_;
  index_t ext_[3];
  index_t px_ = 1, py_ = 1, pz_ = 1;
  std::vector<info> info_;
  std::vector<cut_mask_t> cut_;  // problems with cuts: every voxel's cut mask (all directions)
  index_t delta_[neighbours];
  T length_[neighbours];
};

}  // namespace geovoronoi::detail::search

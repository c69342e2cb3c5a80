#pragma once
// Visiting the in-grid neighbours of a voxel on the implicit grid graph, with a fast path for voxels
// away from the border (no per-neighbour bounds checks).

#include <geovoronoi/config.hpp>

#include <cstdint>

namespace geovoronoi::detail {

template <class P>
class stencil_walker {
 public:
  static constexpr int Dim = P::dim;
  static constexpr int N = P::neighbours;

  explicit stencil_walker(const P& p) : p_(p) {
    nx_ = p.geometry.extent(0);
    ny_ = p.geometry.extent(1);
    nz_ = Dim == 3 ? p.geometry.extent(Dim - 1) : 1;
    nxy_ = nx_ * ny_;
    small_ = p.geometry.size() <= index_t(UINT32_MAX);
  }

  /// Calls f(k, u) for each neighbour u = v + offset k that lies inside the grid.
  template <class F>
  void for_each_neighbour(index_t v, F&& f) const {
    index_t x, y, z;
    if (small_) {
      const std::uint32_t vv = std::uint32_t(v), nx = std::uint32_t(nx_), nxy = std::uint32_t(nxy_);
      const std::uint32_t zz = vv / nxy, r = vv - zz * nxy, yy = r / nx;
      z = zz, y = yy, x = r - yy * nx;
    } else {
      z = v / nxy_;
      const index_t r = v - z * nxy_;
      y = r / nx_;
      x = r - y * nx_;
    }
    const bool interior = x > 0 && x < nx_ - 1 && y > 0 && y < ny_ - 1 && (Dim == 2 || (z > 0 && z < nz_ - 1));
    if (interior) {
      for (int k = 0; k < N; ++k) f(k, v + p_.edges.delta[k]);
    } else {
      for (int k = 0; k < N; ++k) {
        const index_t xx = x + p_.edges.offset[k][0], yy = y + p_.edges.offset[k][1], zz = z + p_.edges.offset[k][2];
        if (xx < 0 || xx >= nx_ || yy < 0 || yy >= ny_ || zz < 0 || zz >= nz_) continue;
        f(k, v + p_.edges.delta[k]);
      }
    }
  }

 private:
  const P& p_;
  index_t nx_, ny_, nz_, nxy_;
  bool small_;
};

}  // namespace geovoronoi::detail

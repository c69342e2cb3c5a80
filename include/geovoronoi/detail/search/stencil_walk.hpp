#pragma once
// Visiting the in-grid neighbours of a voxel on the implicit grid graph, with a fast path for voxels
// away from the border (no per-neighbour bounds checks). The one walker of the library: the engines,
// the parent rule, the update, the shape functions' searches on the grid's own layout and the Thrust
// backend's expansion functors (host and device) all use it.

#include <geovoronoi/config.hpp>
#include <geovoronoi/cut.hpp>

#include <cstdint>

namespace geovoronoi::detail::search {

/// The grid's extents, decoded once; trivially copyable, so a device functor carries it by value.
/// The stencil comes from the problem at each call.
template <int Dim>
struct stencil_walker {
  index_t nx = 1, ny = 1, nz = 1, nxy = 1;
  bool small = true;  ///< fewer than 2^32 voxels: coordinates decode with 32-bit divisions

  stencil_walker() = default;
  template <class P>
  explicit stencil_walker(const P& p)
      : nx(p.geometry.extent(0)),
        ny(p.geometry.extent(1)),
        nz(Dim == 3 ? p.geometry.extent(Dim - 1) : 1),
        nxy(nx * ny),
        small(p.geometry.size() <= index_t(UINT32_MAX)) {
    static_assert(P::dim == Dim, "stencil_walker: the problem's dimension differs from the walker's");
  }

  /// Whether voxel @p v lies off the grid's border, so that v + delta[k] is its k-th neighbour for
  /// every k (the test of for_each_neighbour's fast path). That loop keeps its own copy of the decoding,
  /// which is the seq solve's hot path: written once in a helper, GCC schedules it differently there.
  GEOVORONOI_HOST_DEVICE bool interior(index_t v) const {
    index_t x, y, z;
    if (small) {
      const std::uint32_t vv = std::uint32_t(v), nx32 = std::uint32_t(nx), nxy32 = std::uint32_t(nxy);
      const std::uint32_t zz = vv / nxy32, r = vv - zz * nxy32, yy = r / nx32;
      z = index_t(zz), y = index_t(yy), x = index_t(r - yy * nx32);
    } else {
      z = v / nxy;
      const index_t r = v - z * nxy;
      y = r / nx;
      x = r - y * nx;
    }
    return x > 0 && x < nx - 1 && y > 0 && y < ny - 1 && (Dim == 2 || (z > 0 && z < nz - 1));
  }
  /// Calls f(k, u) for each in-grid neighbour u = v + offset k of @p p's stencil whose edge to @p v is
  /// not cut (for a problem with cuts; without, the cut test compiles away), in increasing k; the
  /// connectivity's offsets are in (z, y, x) lexicographic order, so the neighbours come in increasing
  /// linear index (the parent rule, parents.hpp, takes the first realiser it meets as the lowest-index one).
  template <class P, class F>
  GEOVORONOI_HOST_DEVICE void for_each_neighbour(const P& p, index_t v, F&& f) const {
    index_t x, y, z;
    if (small) {
      const std::uint32_t vv = std::uint32_t(v), nx32 = std::uint32_t(nx), nxy32 = std::uint32_t(nxy);
      const std::uint32_t zz = vv / nxy32, r = vv - zz * nxy32, yy = r / nx32;
      z = index_t(zz), y = index_t(yy), x = index_t(r - yy * nx32);
    } else {
      z = v / nxy;
      const index_t r = v - z * nxy;
      y = r / nx;
      x = r - y * nx;
    }
    const bool interior = x > 0 && x < nx - 1 && y > 0 && y < ny - 1 && (Dim == 2 || (z > 0 && z < nz - 1));
    if constexpr (P::has_cuts) {
      // one probe of the cut table; a voxel that touches no cut takes the usual paths below
      if (const cut_mask_t cut = p.cut_mask(v)) {
        for (int k = 0; k < P::neighbours; ++k) {
          if ((cut >> k) & 1u) continue;
          const index_t xx = x + p.edges.offset[k][0], yy = y + p.edges.offset[k][1], zz = z + p.edges.offset[k][2];
          if (!interior && (xx < 0 || xx >= nx || yy < 0 || yy >= ny || zz < 0 || zz >= nz)) continue;
          f(k, v + p.edges.delta[k]);
        }
        return;
      }
    }
    if (interior) {
      for (int k = 0; k < P::neighbours; ++k) f(k, v + p.edges.delta[k]);
    } else {
      for (int k = 0; k < P::neighbours; ++k) {
        const index_t xx = x + p.edges.offset[k][0], yy = y + p.edges.offset[k][1], zz = z + p.edges.offset[k][2];
        if (xx < 0 || xx >= nx || yy < 0 || yy >= ny || zz < 0 || zz >= nz) continue;
        f(k, v + p.edges.delta[k]);
      }
    }
  }
};

}  // namespace geovoronoi::detail::search

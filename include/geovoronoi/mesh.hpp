#pragma once
/// @file mesh.hpp
/// @brief A triangle soup in world coordinates: what the STL and OBJ readers return and what cuts
///        are built from.

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace geovoronoi {

/**
 * @brief Triangles over a vertex list, in world coordinates. No topology is required: a cut is just
 *        the union of its closed triangles, so open, non-manifold or self-intersecting meshes are
 *        all fine.
 */
struct triangle_mesh {
  std::vector<std::array<double, 3>> vertices;         ///< world positions (finite)
  std::vector<std::array<std::uint32_t, 3>> triangles;  ///< indices into vertices
  /// Triangles a reader dropped because their area is zero (repeated vertices, or a cross product
  /// of exactly zero).
  std::size_t degenerate = 0;
};

namespace detail {
/// True when triangle (a, b, c) has zero area in double arithmetic: a cross product of exactly
/// (0, 0, 0). Exactly collinear triangles whose cross product rounds to a tiny non-zero value are
/// kept; the cut builder drops them on its exact lattice.
inline bool zero_area(const std::array<double, 3>& a, const std::array<double, 3>& b,
                      const std::array<double, 3>& c) noexcept {
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  return uy * vz - uz * vy == 0.0 && uz * vx - ux * vz == 0.0 && ux * vy - uy * vx == 0.0;
}
}  // namespace detail

}  // namespace geovoronoi

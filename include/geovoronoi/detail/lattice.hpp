#pragma once
// The lattice every exact mesh construction snaps to (cut_from_mesh, voxelize): world points are
// moved once into the grid's continuous index space and rounded to 2^-lattice_bits voxel; voxel
// centres are lattice points, and detail/exact.hpp's predicates are exact on it.

#include <geovoronoi/config.hpp>
#include <geovoronoi/grid.hpp>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi::detail {

/// log2 of the lattice steps per voxel.
inline constexpr int lattice_bits = 16;
/// Largest |index-space coordinate| a vertex may have, in voxels.
inline constexpr double lattice_range = double(std::int64_t(1) << (40 - lattice_bits));

/// Continuous index-space coordinates of world point @p p on grid @p g.
template <int Dim>
std::array<double, Dim> index_space(const grid<Dim>& g, const std::array<double, Dim>& p) noexcept {
  std::array<double, Dim> u{};
  for (int a = 0; a < Dim; ++a) {
    double s = 0.0;
    for (int r = 0; r < Dim; ++r)
      if (g.direction(r, a) != 0.0) s += g.direction(r, a) * (p[r] - g.origin()[r]);
    u[a] = s / g.spacing(a);
  }
  return u;
}

/// Snaps index-space coordinate @p x to the lattice, or returns false when it is out of range.
inline bool snap(double x, std::int64_t& out) noexcept {
  if (!(std::abs(x) <= lattice_range)) return false;
  out = static_cast<std::int64_t>(std::floor(std::ldexp(x, lattice_bits) + 0.5));
  return true;
}

/// Lattice coordinates of every mesh vertex.
template <int Dim>
std::vector<std::array<std::int64_t, Dim>> snap_all(const grid<Dim>& g, const std::vector<std::array<double, Dim>>& pts,
                                                    const char* who) {
  std::vector<std::array<std::int64_t, Dim>> out(pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) {
    for (int a = 0; a < Dim; ++a)
      if (!std::isfinite(pts[i][a]))
        throw std::invalid_argument(std::string(who) + ": vertex " + std::to_string(i) + " has a coordinate that is not finite");
    const auto u = index_space<Dim>(g, pts[i]);
    for (int a = 0; a < Dim; ++a)
      if (!snap(u[a], out[i][a]))
        throw std::invalid_argument(std::string(who) + ": vertex " + std::to_string(i) +
                                    " lies more than 2^24 voxels from the grid (index-space coordinate " +
                                    std::to_string(u[a]) + " along axis " + std::to_string(a) + ")");
  }
  return out;
}

/// Refuses grids the lattice cannot hold.
template <int Dim>
void check_lattice_grid(const grid<Dim>& g, const char* who) {
  for (int a = 0; a < Dim; ++a)
    if (double(g.extent(a)) > lattice_range)
      throw std::invalid_argument(std::string(who) + ": the grid has " + std::to_string(g.extent(a)) +
                                  " voxels along axis " + std::to_string(a) + "; cuts support at most 2^24");
}

/// floor(x / 2^lattice_bits) and ceil(...) for lattice coordinates.
inline std::int64_t lattice_floor(std::int64_t x) noexcept { return x >> lattice_bits; }
inline std::int64_t lattice_ceil(std::int64_t x) noexcept { return -((-x) >> lattice_bits); }

}  // namespace geovoronoi::detail

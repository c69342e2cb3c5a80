#pragma once
/// @file grid.hpp
/// @brief The voxel grid policy: extents, anisotropic spacing, origin, 64-bit linear indexing.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <string>

namespace geovoronoi {

/// Integer voxel coordinates (i, j[, k]), x first.
template <int Dim>
using coord = std::array<index_t, Dim>;

/// World-space point (x, y[, z]).
template <int Dim>
using point = std::array<double, Dim>;

/**
 * @brief A regular 2D or 3D voxel grid.
 *
 * Voxel (i,j,k) has linear index i + nx*(j + ny*k) (x varies fastest) and its centre lies at
 * origin + (i*sx, j*sy, k*sz). The type is trivially copyable and its accessors are host-device, so
 * it can be passed to kernels by value. Construction validates its arguments.
 *
 * @tparam Dim 2 or 3.
 *
 * @code
 * geovoronoi::grid<3> g({128, 96, 32}, {0.5, 0.5, 1.0});   // anisotropic voxels
 * auto v = g.index({3, 4, 5});                               // 3 + 128*(4 + 96*5)
 * @endcode
 */
template <int Dim>
class grid {
  static_assert(Dim == 2 || Dim == 3, "geovoronoi::grid: Dim must be 2 or 3");

 public:
  static constexpr int dim = Dim;

  /// An empty grid (0 voxels); only useful as a placeholder to assign to.
  grid() = default;

  /**
   * @param extents number of voxels along each axis; each must be >= 1.
   * @param spacing physical voxel size along each axis; each must be finite and > 0.
   * @param origin  world position of voxel 0's centre; each must be finite.
   * @throws std::invalid_argument naming the offending axis, or if the voxel count overflows 64 bits.
   */
  explicit grid(const coord<Dim>& extents, const point<Dim>& spacing = ones(), const point<Dim>& origin = {})
      : extents_(extents), spacing_(spacing), origin_(origin) {
    static const char* axis[] = {"x", "y", "z"};
    index_t total = 1;
    for (int a = 0; a < Dim; ++a) {
      if (extents[a] <= 0)
        throw std::invalid_argument("geovoronoi::grid: extent along " + std::string(axis[a]) + " is " +
                                    std::to_string(extents[a]) + "; every extent must be >= 1");
      if (!(std::isfinite(spacing[a]) && spacing[a] > 0))
        throw std::invalid_argument("geovoronoi::grid: spacing along " + std::string(axis[a]) + " is " +
                                    std::to_string(spacing[a]) + "; spacing must be finite and > 0");
      if (!std::isfinite(origin[a]))
        throw std::invalid_argument("geovoronoi::grid: origin along " + std::string(axis[a]) + " is not finite");
      if (total > std::numeric_limits<index_t>::max() / extents[a])
        throw std::invalid_argument("geovoronoi::grid: the voxel count overflows a 64-bit index");
      total *= extents[a];
    }
  }

  /// Number of voxels along axis @p a.
  GEOVORONOI_HOST_DEVICE index_t extent(int a) const noexcept { return extents_[a]; }
  GEOVORONOI_HOST_DEVICE const coord<Dim>& extents() const noexcept { return extents_; }
  GEOVORONOI_HOST_DEVICE double spacing(int a) const noexcept { return spacing_[a]; }
  GEOVORONOI_HOST_DEVICE const point<Dim>& spacing() const noexcept { return spacing_; }
  GEOVORONOI_HOST_DEVICE const point<Dim>& origin() const noexcept { return origin_; }

  /// Total number of voxels (0 for a default-constructed grid).
  GEOVORONOI_HOST_DEVICE index_t size() const noexcept {
    index_t n = 1;
    for (int a = 0; a < Dim; ++a) n *= extents_[a];
    return n;
  }

  /// Physical volume of one voxel (area in 2D).
  GEOVORONOI_HOST_DEVICE double voxel_volume() const noexcept {
    double v = 1;
    for (int a = 0; a < Dim; ++a) v *= spacing_[a];
    return v;
  }

  /// True when @p c lies inside the grid.
  GEOVORONOI_HOST_DEVICE bool contains(const coord<Dim>& c) const noexcept {
    for (int a = 0; a < Dim; ++a)
      if (c[a] < 0 || c[a] >= extents_[a]) return false;
    return true;
  }

  /// Linear index of voxel @p c. @pre contains(c).
  GEOVORONOI_HOST_DEVICE index_t index(const coord<Dim>& c) const noexcept {
    index_t v = c[Dim - 1];
    for (int a = Dim - 2; a >= 0; --a) v = v * extents_[a] + c[a];
    return v;
  }

  /// Voxel coordinates of linear index @p v. @pre 0 <= v < size().
  GEOVORONOI_HOST_DEVICE coord<Dim> coords(index_t v) const noexcept {
    coord<Dim> c{};
    for (int a = 0; a < Dim; ++a) {
      c[a] = v % extents_[a];
      v /= extents_[a];
    }
    return c;
  }

  /// World position of the centre of voxel @p c.
  GEOVORONOI_HOST_DEVICE point<Dim> world(const coord<Dim>& c) const noexcept {
    point<Dim> p{};
    for (int a = 0; a < Dim; ++a) p[a] = origin_[a] + static_cast<double>(c[a]) * spacing_[a];
    return p;
  }

  /// The voxel whose centre is nearest to world point @p p (halves round up). May lie outside the
  /// grid; check with contains().
  coord<Dim> nearest_voxel(const point<Dim>& p) const noexcept {
    coord<Dim> c{};
    for (int a = 0; a < Dim; ++a) {
      const double f = std::floor((p[a] - origin_[a]) / spacing_[a] + 0.5);
      c[a] = (f >= -9.0e18 && f <= 9.0e18) ? static_cast<index_t>(f) : index_t(-1);
    }
    return c;
  }

  /// Grids are equal when extents, spacing and origin are equal.
  friend bool operator==(const grid& a, const grid& b) noexcept {
    return a.extents_ == b.extents_ && a.spacing_ == b.spacing_ && a.origin_ == b.origin_;
  }
  friend bool operator!=(const grid& a, const grid& b) noexcept { return !(a == b); }

 private:
  static point<Dim> ones() noexcept {
    point<Dim> p{};
    for (auto& x : p) x = 1.0;
    return p;
  }

  coord<Dim> extents_{};
  point<Dim> spacing_{};
  point<Dim> origin_{};
};

/// Human-readable "(i, j, k)".
template <int Dim>
std::string to_string(const coord<Dim>& c) {
  std::string s = "(";
  for (int a = 0; a < Dim; ++a) s += (a ? ", " : "") + std::to_string(c[a]);
  return s + ")";
}

}  // namespace geovoronoi

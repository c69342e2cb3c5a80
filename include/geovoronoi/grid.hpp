#pragma once
/// @file grid.hpp
/// @brief The voxel grid policy: extents, anisotropic spacing, origin, direction (orientation),
///        64-bit linear indexing.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <limits>
#include <string>

namespace geovoronoi {

/// Integer voxel coordinates (i, j[, k]), x first.
template <int Dim>
using coord = std::array<index_t, Dim>;

/// World-space point (x, y[, z]).
template <int Dim>
using point = std::array<double, Dim>;

/// A Dim x Dim direction (orientation) matrix, row-major: entry (r, c) at index r * Dim + c. Column c
/// is the world direction of index axis c (ITK's and VTK's convention).
template <int Dim>
using direction_matrix = std::array<double, Dim * Dim>;

/// How far a direction matrix D may be from orthonormal: every entry of D^T D - I must lie within
/// this bound (which also rules out singular matrices).
inline constexpr double direction_tolerance = 1e-6;

namespace detail {
/// The shortest decimal text that reads back as @p x ("0.1", "1e+30", "nan", "-inf"), for messages.
inline std::string shortest_text(double x) {
  char buf[40];
  for (int prec = 6; prec <= 17; ++prec) {
    std::snprintf(buf, sizeof buf, "%.*g", prec, x);
    if (!(x == x) || std::strtod(buf, nullptr) == x) break;
  }
  return buf;
}

/// The identity direction.
template <int Dim>
GEOVORONOI_HOST_DEVICE constexpr direction_matrix<Dim> identity_direction() noexcept {
  direction_matrix<Dim> d{};
  for (int a = 0; a < Dim; ++a) d[a * Dim + a] = 1.0;
  return d;
}

/// "[a b; c d]" for messages.
inline std::string matrix_text(const double* d, int n) {
  std::string s = "[";
  char buf[32];
  for (int r = 0; r < n; ++r)
    for (int c = 0; c < n; ++c) {
      std::snprintf(buf, sizeof buf, "%.17g", d[r * n + c]);
      s += (c ? " " : (r ? "; " : "")) + std::string(buf);
    }
  return s + "]";
}

/// Why the n x n row-major matrix @p d cannot be a grid direction (empty when it can): an entry that
/// is not finite, a singular matrix, or one that is not orthonormal within direction_tolerance.
inline std::string direction_problem(const double* d, int n) {
  for (int i = 0; i < n * n; ++i)
    if (!std::isfinite(d[i])) return "the direction matrix " + matrix_text(d, n) + " has an entry that is not finite";
  double det = d[0];
  if (n == 2) det = d[0] * d[3] - d[1] * d[2];
  if (n == 3)
    det = d[0] * (d[4] * d[8] - d[5] * d[7]) - d[1] * (d[3] * d[8] - d[5] * d[6]) + d[2] * (d[3] * d[7] - d[4] * d[6]);
  double worst = 0;  // largest |(D^T D - I)_ij|
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      double dot = 0;
      for (int r = 0; r < n; ++r) dot += d[r * n + i] * d[r * n + j];
      worst = std::max(worst, std::abs(dot - (i == j ? 1.0 : 0.0)));
    }
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", worst);
  if (!(std::abs(det) > 1e-12))
    return "the direction matrix " + matrix_text(d, n) + " is singular (determinant " + std::to_string(det) +
           "); it must be orthonormal (a rotation, possibly with a reflection)";
  if (!(worst <= direction_tolerance))
    return "the direction matrix " + matrix_text(d, n) + " is not orthonormal (largest entry of D^T D - I is " +
           buf + ", tolerance 1e-6); its columns must be unit vectors at right angles";
  return {};
}
}  // namespace detail

/**
 * @brief A regular 2D or 3D voxel grid.
 *
 * Voxel (i,j,k) has linear index i + nx*(j + ny*k) (x varies fastest) and its centre lies at
 * origin + D * (i*sx, j*sy, k*sz), D the direction matrix (identity unless given; ITK's and VTK's
 * convention: column c of D is the world direction of index axis c). D must be orthonormal within
 * direction_tolerance, so world-to-index uses its transpose. The solvers never look at origin or
 * direction: they only travel with the grid to the outputs and to world-coordinate conversions.
 * The type is trivially copyable and its accessors are host-device, so it can be passed to kernels
 * by value. Construction validates its arguments.
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
   * @param direction row-major direction matrix; must be orthonormal within direction_tolerance
   *                (a rotation, possibly with a reflection).
   * @throws std::invalid_argument naming the offending axis, or if the voxel count overflows 64 bits,
   *         or naming the direction matrix if it is singular, not finite or not orthonormal.
   */
  explicit grid(const coord<Dim>& extents, const point<Dim>& spacing = ones(), const point<Dim>& origin = {},
                const direction_matrix<Dim>& direction = detail::identity_direction<Dim>())
      : extents_(extents), spacing_(spacing), origin_(origin), direction_(direction) {
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
    const std::string bad = detail::direction_problem(direction.data(), Dim);
    if (!bad.empty()) throw std::invalid_argument("geovoronoi::grid: " + bad);
  }

  /// Number of voxels along axis @p a.
  GEOVORONOI_HOST_DEVICE index_t extent(int a) const noexcept { return extents_[a]; }
  GEOVORONOI_HOST_DEVICE const coord<Dim>& extents() const noexcept { return extents_; }
  GEOVORONOI_HOST_DEVICE double spacing(int a) const noexcept { return spacing_[a]; }
  GEOVORONOI_HOST_DEVICE const point<Dim>& spacing() const noexcept { return spacing_; }
  GEOVORONOI_HOST_DEVICE const point<Dim>& origin() const noexcept { return origin_; }
  /// The direction matrix, row-major (identity unless the grid was given one).
  GEOVORONOI_HOST_DEVICE const direction_matrix<Dim>& direction() const noexcept { return direction_; }
  /// Entry (r, c) of the direction matrix: component r of index axis c's world direction.
  GEOVORONOI_HOST_DEVICE double direction(int r, int c) const noexcept { return direction_[r * Dim + c]; }

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

  /// World position of the centre of voxel @p c: origin + D * (c * spacing). Zero entries of D are
  /// skipped, so an axis-aligned grid (D with 0 and +-1 entries) computes exactly
  /// origin + c * spacing per axis.
  GEOVORONOI_HOST_DEVICE point<Dim> world(const coord<Dim>& c) const noexcept {
    point<Dim> p{};
    for (int r = 0; r < Dim; ++r) {
      double sum = 0.0;
      for (int a = 0; a < Dim; ++a)
        if (direction_[r * Dim + a] != 0.0)
          sum += direction_[r * Dim + a] * (static_cast<double>(c[a]) * spacing_[a]);
      p[r] = origin_[r] + sum;
    }
    return p;
  }

  /// The voxel whose centre is nearest to world point @p p (halves round up): per index axis a,
  /// floor((D^T (p - origin))_a / spacing_a + 0.5). May lie outside the grid; check with contains().
  coord<Dim> nearest_voxel(const point<Dim>& p) const noexcept {
    coord<Dim> c{};
    for (int a = 0; a < Dim; ++a) {
      double u = 0.0;
      for (int r = 0; r < Dim; ++r)
        if (direction_[r * Dim + a] != 0.0) u += direction_[r * Dim + a] * (p[r] - origin_[r]);
      const double f = std::floor(u / spacing_[a] + 0.5);
      c[a] = (f >= -9.0e18 && f <= 9.0e18) ? static_cast<index_t>(f) : index_t(-1);
    }
    return c;
  }

  /**
   * @brief nearest_voxel(p), checked: the voxel must lie in the grid.
   * @throws std::invalid_argument naming the world point as given (not a voxel it rounds to, which
   *         may be meaningless far outside), and the first axis along which it leaves the grid with
   *         its index there and the grid's range; or saying that the point is not finite.
   */
  coord<Dim> checked_nearest_voxel(const point<Dim>& p) const {
    const coord<Dim> c = nearest_voxel(p);
    bool finite = true;
    for (int a = 0; a < Dim; ++a) finite = finite && std::isfinite(p[a]);
    std::string given = "world point (";
    for (int a = 0; a < Dim; ++a) given += (a ? ", " : "") + detail::shortest_text(p[a]);
    given += ")";
    if (!finite) throw std::invalid_argument(given + " is not a finite point");
    if (contains(c)) return c;
    for (int a = 0; a < Dim; ++a) {
      double u = 0.0;
      for (int r = 0; r < Dim; ++r)
        if (direction_[r * Dim + a] != 0.0) u += direction_[r * Dim + a] * (p[r] - origin_[r]);
      const double f = std::floor(u / spacing_[a] + 0.5);
      if (f >= 0.0 && f < static_cast<double>(extents_[a])) continue;
      const char* axis[] = {"x", "y", "z"};
      throw std::invalid_argument(given + " lies outside the grid: its nearest voxel centre has index " +
                                  detail::shortest_text(f) + " along " + axis[a] + ", where the grid's indices run 0 to " +
                                  std::to_string(extents_[a] - 1));
    }
    throw std::invalid_argument(given + " lies outside the grid");
  }

  /// Grids are equal when extents, spacing, origin and direction are equal.
  friend bool operator==(const grid& a, const grid& b) noexcept {
    return a.extents_ == b.extents_ && a.spacing_ == b.spacing_ && a.origin_ == b.origin_ &&
           a.direction_ == b.direction_;
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
  direction_matrix<Dim> direction_ = detail::identity_direction<Dim>();
};

/// Human-readable "(i, j, k)".
template <int Dim>
std::string to_string(const coord<Dim>& c) {
  std::string s = "(";
  for (int a = 0; a < Dim; ++a) s += (a ? ", " : "") + std::to_string(c[a]);
  return s + ")";
}

}  // namespace geovoronoi

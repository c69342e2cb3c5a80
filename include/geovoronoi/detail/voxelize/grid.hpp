#pragma once
// voxelize_grid(): the parts' bounds, optionally in their principal frame, turned into a grid<3>.

#include <geovoronoi/detail/voxelize/common.hpp>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

namespace detail::vox {

/// At most this many voxels in a grid voxelize_grid() builds.
inline constexpr double max_grid_voxels = 2147483648.0;  // 2^31

/// Orthonormal, right-handed frame of the surface's principal axes (columns), by decreasing
/// area-weighted second moment about the area centroid. Signs: the largest-magnitude component of
/// the first two axes is positive (the first of equal ones); the third is their cross product.
inline std::array<std::array<double, 3>, 3> principal_frame(const std::vector<voxelize_part>& parts) {
  double area = 0.0;
  Eigen::Vector3d first = Eigen::Vector3d::Zero();
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const auto& p : parts)
    for (const auto& t : p.mesh.triangles) {
      const Eigen::Vector3d a(p.mesh.vertices[t[0]].data()), b(p.mesh.vertices[t[1]].data()),
          c(p.mesh.vertices[t[2]].data());
      const double ar = 0.5 * (b - a).cross(c - a).norm();
      area += ar;
      first += ar * (a + b + c) / 3.0;
      const Eigen::Vector3d s = a + b + c;
      // integral of x x^T over the triangle
      second += ar / 12.0 * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
    }
  std::array<std::array<double, 3>, 3> e{};
  if (!(area > 0)) {
    for (int i = 0; i < 3; ++i) e[i][i] = 1.0;
    return e;
  }
  const Eigen::Vector3d m = first / area;
  const Eigen::Matrix3d cov = second / area - m * m.transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(cov);
  Eigen::Vector3d ax[3] = {es.eigenvectors().col(2), es.eigenvectors().col(1), Eigen::Vector3d::Zero()};
  for (int i = 0; i < 2; ++i) {
    int big = 0;
    for (int k = 1; k < 3; ++k)
      if (std::abs(ax[i][k]) > std::abs(ax[i][big])) big = k;
    if (ax[i][big] < 0) ax[i] = -ax[i];
    ax[i].normalize();
  }
  ax[2] = ax[0].cross(ax[1]).normalized();
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) e[i][k] = ax[i][k];
  return e;
}

}  // namespace detail::vox

inline grid<3> voxelize_grid(const std::vector<voxelize_part>& parts, const voxelize_options& o) {
  const std::string who = "geovoronoi::voxelize_grid: ";
  static const char* axis[3] = {"x", "y", "z"};
  const bool by_size = o.voxel_size[0] != 0 || o.voxel_size[1] != 0 || o.voxel_size[2] != 0;
  const bool by_count = o.voxels[0] != 0 || o.voxels[1] != 0 || o.voxels[2] != 0;
  if (by_size == by_count)
    throw std::invalid_argument(who + (by_size ? "both voxel_size and voxels are given; give exactly one"
                                               : "neither voxel_size nor voxels is given; give exactly one"));
  for (int a = 0; a < 3; ++a) {
    if (by_size && !(std::isfinite(o.voxel_size[a]) && o.voxel_size[a] > 0))
      throw std::invalid_argument(who + "voxel_size along " + axis[a] + " is " + detail::shortest_text(o.voxel_size[a]) +
                                  "; every voxel size must be finite and > 0");
    if (by_count && o.voxels[a] <= 0)
      throw std::invalid_argument(who + "voxels along " + axis[a] + " is " + std::to_string(o.voxels[a]) +
                                  "; every count must be > 0");
  }
  if (o.pad < 0) throw std::invalid_argument(who + "pad is " + std::to_string(o.pad) + "; it must be >= 0");
  std::size_t tris = 0;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const auto& m = parts[i].mesh;
    for (std::size_t t = 0; t < m.triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const auto v = m.triangles[t][k];
        if (v >= m.vertices.size())
          throw std::invalid_argument(who + detail::vox::part_text(parts[i].name, i) + ": triangle " + std::to_string(t) +
                                      " refers to vertex " + std::to_string(v) + " of " + std::to_string(m.vertices.size()));
        for (int a = 0; a < 3; ++a)
          if (!std::isfinite(m.vertices[v][a]))
            throw std::invalid_argument(who + detail::vox::part_text(parts[i].name, i) + ": vertex " +
                                        std::to_string(v) + " has a coordinate that is not finite");
      }
    tris += m.triangles.size();
  }
  if (tris == 0)
    throw std::invalid_argument(who + (parts.empty() ? "no parts given" : "the parts hold no triangles") +
                                "; the bounds of a grid come from the meshes");
  std::array<std::array<double, 3>, 3> e{};
  for (int i = 0; i < 3; ++i) e[i][i] = 1.0;
  if (o.principal_axes) e = detail::vox::principal_frame(parts);
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto& p : parts)
    for (const auto& t : p.mesh.triangles)
      for (int k = 0; k < 3; ++k) {
        const auto& v = p.mesh.vertices[t[k]];
        for (int a = 0; a < 3; ++a) {
          const double u = o.principal_axes ? e[a][0] * v[0] + e[a][1] * v[1] + e[a][2] * v[2] : v[a];
          lo[a] = std::min(lo[a], u);
          hi[a] = std::max(hi[a], u);
        }
      }
  coord<3> n{};
  point<3> s{}, c0{};
  double total = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double ext = hi[a] - lo[a];
    double first_face = lo[a];  // lower face of the first voxel before padding
    if (by_count) {
      if (!(ext > 0))
        throw std::invalid_argument(who + "the meshes' bounds have zero extent along " + axis[a] +
                                    " (a flat mesh), so voxels cannot set the spacing there; give voxel_size");
      s[a] = ext / double(o.voxels[a]);
      n[a] = o.voxels[a];
    } else {
      s[a] = o.voxel_size[a];
      if (o.snap_origin) first_face = (std::floor(lo[a] / s[a] + 0.5) - 0.5) * s[a];
      const double cells = std::ceil((hi[a] - first_face) / s[a]);
      if (!(cells < 1e12))
        throw std::invalid_argument(who + "the bounds span " + detail::shortest_text(ext) + " along " + axis[a] +
                                    ", more than 10^12 voxels of size " + detail::shortest_text(s[a]));
      n[a] = std::max<index_t>(1, static_cast<index_t>(cells));
      if (double(n[a]) * s[a] + first_face < hi[a]) ++n[a];
    }
    n[a] += 2 * o.pad;
    c0[a] = first_face + 0.5 * s[a] - double(o.pad) * s[a];
    total *= double(n[a]);
  }
  if (total > detail::vox::max_grid_voxels || double(std::max({n[0], n[1], n[2]})) > detail::lattice_range)
    throw std::invalid_argument(who + "the grid would have " + std::to_string(n[0]) + " x " + std::to_string(n[1]) +
                                " x " + std::to_string(n[2]) + " voxels (" + detail::shortest_text(total) +
                                "), more than 2^31 in all or 2^24 along an axis; choose a larger voxel_size or fewer voxels");
  direction_matrix<3> d{};
  point<3> origin{};
  for (int r = 0; r < 3; ++r) {
    for (int a = 0; a < 3; ++a) d[std::size_t(r * 3 + a)] = e[a][r];
    origin[r] = o.principal_axes ? e[0][r] * c0[0] + e[1][r] * c0[1] + e[2][r] * c0[2] : c0[r];
  }
  return grid<3>(n, s, origin, d);
}

}  // namespace geovoronoi

#pragma once
// The generalized winding number of a triangle soup (Jacobson et al. 2013) with the hierarchical
// evaluation of Barill et al. 2018: a bounding-volume tree whose far nodes are replaced by their
// dipole (area-weighted normal at the area centroid), the near ones summed exactly triangle by
// triangle with Van Oosterom and Strackee's solid angle. Index space, double precision.

#include <geovoronoi/detail/voxelize/common.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace geovoronoi::detail::vox {

/// Solid angle of triangle (a, b, c) seen from p, in [-2 pi, 2 pi]; positive when p is behind the
/// triangle (on the side its normal (b - a) x (c - a) points away from).
inline double solid_angle(const double* a, const double* b, const double* c, const double* p) noexcept {
  const double ax = a[0] - p[0], ay = a[1] - p[1], az = a[2] - p[2];
  const double bx = b[0] - p[0], by = b[1] - p[1], bz = b[2] - p[2];
  const double cx = c[0] - p[0], cy = c[1] - p[1], cz = c[2] - p[2];
  const double la = std::sqrt(ax * ax + ay * ay + az * az), lb = std::sqrt(bx * bx + by * by + bz * bz),
               lc = std::sqrt(cx * cx + cy * cy + cz * cz);
  const double det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
  const double den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (ax * cx + ay * cy + az * cz) * lb +
                     (bx * cx + by * cy + bz * cz) * la;
  return 2.0 * std::atan2(det, den);
}

/// Winding numbers of one soup at any point (index-space coordinates in voxels).
class winding_tree {
 public:
  /// Far-field acceptance: a node is replaced by its dipole when the point is farther than beta
  /// times the node's radius from its centre.
  static constexpr double beta = 3.0;

  explicit winding_tree(const std::vector<lattice_triangle>& tris) : tris_(&tris) {
    const std::size_t n = tris.size();
    pos_.resize(n * 9);
    for (std::size_t t = 0; t < n; ++t)
      for (int i = 0; i < 3; ++i)
        for (int k = 0; k < 3; ++k) pos_[t * 9 + i * 3 + k] = double(tris[t].v[i][k]) / double(one);
    order_.resize(n);
    std::iota(order_.begin(), order_.end(), std::uint32_t(0));
    if (n) build(0, n);
  }

  /// The winding number at lattice point @p p. A point lying exactly on a triangle (exact test) is
  /// moved 2^-12 voxel along +x first, to the side the crossing count's tie rule chooses.
  double at(const lattice3& p) const {
    double q[3] = {double(p[0]) / double(one), double(p[1]) / double(one), double(p[2]) / double(one)};
    bool on = false;
    double w = eval(q, &p, on);
    if (on) {
      q[0] += 1.0 / 4096.0;
      w = eval(q, nullptr, on);
    }
    return w;
  }

 private:
  struct node {
    double lo[3], hi[3];
    double centre[3], normal[3];  // area centroid, sum of area vectors
    double radius;
    std::uint32_t begin, end;
    std::int32_t left = -1, right = -1;
  };

  const double* tri(std::uint32_t t) const { return &pos_[std::size_t(t) * 9]; }

  std::int32_t build(std::size_t begin, std::size_t end) {
    const std::int32_t id = static_cast<std::int32_t>(nodes_.size());
    nodes_.emplace_back();
    node nd{};
    for (int k = 0; k < 3; ++k) {
      nd.lo[k] = 1e300;
      nd.hi[k] = -1e300;
      nd.centre[k] = nd.normal[k] = 0.0;
    }
    double area = 0.0;
    for (std::size_t i = begin; i < end; ++i) {
      const double* t = tri(order_[i]);
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) {
          nd.lo[k] = std::min(nd.lo[k], t[v * 3 + k]);
          nd.hi[k] = std::max(nd.hi[k], t[v * 3 + k]);
        }
      const double ux = t[3] - t[0], uy = t[4] - t[1], uz = t[5] - t[2];
      const double vx = t[6] - t[0], vy = t[7] - t[1], vz = t[8] - t[2];
      const double n[3] = {0.5 * (uy * vz - uz * vy), 0.5 * (uz * vx - ux * vz), 0.5 * (ux * vy - uy * vx)};
      const double a = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
      area += a;
      for (int k = 0; k < 3; ++k) {
        nd.normal[k] += n[k];
        nd.centre[k] += a * (t[k] + t[3 + k] + t[6 + k]) / 3.0;
      }
    }
    for (int k = 0; k < 3; ++k) nd.centre[k] = area > 0 ? nd.centre[k] / area : 0.5 * (nd.lo[k] + nd.hi[k]);
    double r2 = 0.0;
    for (int c = 0; c < 8; ++c) {
      double d2 = 0.0;
      for (int k = 0; k < 3; ++k) {
        const double x = ((c >> k) & 1 ? nd.hi[k] : nd.lo[k]) - nd.centre[k];
        d2 += x * x;
      }
      r2 = std::max(r2, d2);
    }
    nd.radius = std::sqrt(r2);
    nd.begin = static_cast<std::uint32_t>(begin);
    nd.end = static_cast<std::uint32_t>(end);
    if (end - begin > leaf_size) {
      int axis = 0;
      for (int k = 1; k < 3; ++k)
        if (nd.hi[k] - nd.lo[k] > nd.hi[axis] - nd.lo[axis]) axis = k;
      const std::size_t mid = (begin + end) / 2;
      auto key = [&](std::uint32_t t) {
        const double* p = tri(t);
        return p[axis] + p[3 + axis] + p[6 + axis];
      };
      std::nth_element(order_.begin() + std::ptrdiff_t(begin), order_.begin() + std::ptrdiff_t(mid),
                       order_.begin() + std::ptrdiff_t(end), [&](std::uint32_t x, std::uint32_t y) {
                         const double kx = key(x), ky = key(y);
                         return kx < ky || (kx == ky && x < y);
                       });
      const std::int32_t l = build(begin, mid);
      const std::int32_t r = build(mid, end);
      nd.left = l;
      nd.right = r;
    }
    nodes_[static_cast<std::size_t>(id)] = nd;
    return id;
  }

  double eval(const double* q, const lattice3* exact, bool& on) const {
    double sum = 0.0;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top) {
      const node& nd = nodes_[static_cast<std::size_t>(stack[--top])];
      const double dx = nd.centre[0] - q[0], dy = nd.centre[1] - q[1], dz = nd.centre[2] - q[2];
      const double d2 = dx * dx + dy * dy + dz * dz;
      if (d2 > beta * beta * nd.radius * nd.radius) {
        sum += (dx * nd.normal[0] + dy * nd.normal[1] + dz * nd.normal[2]) / (d2 * std::sqrt(d2));
        continue;
      }
      if (nd.left < 0) {
        for (std::uint32_t i = nd.begin; i < nd.end; ++i) {
          const std::uint32_t t = order_[i];
          if (exact && on_triangle((*tris_)[t], *exact)) {
            on = true;
            return 0.0;
          }
          const double* p = tri(t);
          sum += solid_angle(p, p + 3, p + 6, q);
        }
        continue;
      }
      stack[top++] = nd.left;
      stack[top++] = nd.right;
    }
    return sum / (4.0 * 3.14159265358979323846);
  }

  /// Lattice point p lies in the closed triangle (exact).
  static bool on_triangle(const lattice_triangle& t, const lattice3& p) {
    for (int k = 0; k < 3; ++k)
      if (p[k] < t.lo[k] || p[k] > t.hi[k]) return false;
    if (orient3d(t.v[0], t.v[1], t.v[2], p) != 0) return false;
    auto mag = [](int128_t x) { return x < 0 ? -x : x; };
    const int drop = (mag(t.n[0]) >= mag(t.n[1]) && mag(t.n[0]) >= mag(t.n[2])) ? 0 : (mag(t.n[1]) >= mag(t.n[2]) ? 1 : 2);
    const int i = drop == 0 ? 1 : 0, j = drop == 2 ? 1 : 2;
    return triangle_contains({t.v[0][i], t.v[0][j]}, {t.v[1][i], t.v[1][j]}, {t.v[2][i], t.v[2][j]}, {p[i], p[j]});
  }

  static constexpr std::size_t leaf_size = 8;
  const std::vector<lattice_triangle>* tris_;
  std::vector<double> pos_;
  std::vector<std::uint32_t> order_;
  std::vector<node> nodes_;
};

}  // namespace geovoronoi::detail::vox

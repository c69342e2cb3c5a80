#pragma once
/// @file phantom.hpp
/// @brief Procedural stiffness volumes used by the benchmarks, the tests and the demo: constant,
///        gradient (1 -> 10 along x), a two-material beam, a T-bone-steak phantom (meat, fat, bone,
///        background) and a noisy MRI-like pelvis (mri_like: tissues over three decades of values,
///        masked background); closed triangle meshes (box, ellipsoid, torus, the "limb" parts)
///        for voxelize(); and a hand with fingers closer than a coarse cell (fingers: the case of
///        branching grids).

#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/mesh.hpp>
#include <geovoronoi/voxelize.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace geovoronoi::phantom {

/// Young's moduli of the steak's tissues, the contrast of SOFA's steak demo (its transfer function
/// maps meat to 2e4, fat to 5e3 and bone to 1.5e10); 0 is background (outside the domain).
struct steak_moduli {
  float meat = 2.0e4f;
  float fat = 5.0e3f;
  float bone = 1.5e10f;
};

/// Every voxel 1.
template <int Dim>
image<float, Dim> constant(const grid<Dim>& g, float value = 1.0f) {
  return image<float, Dim>(g, value);
}

/// Stiffness rising linearly from @p lo at x = 0 to @p hi at the last x.
template <int Dim>
image<float, Dim> gradient(const grid<Dim>& g, float lo = 1.0f, float hi = 10.0f) {
  image<float, Dim> f(g);
  const double nx = double(std::max<index_t>(g.extent(0) - 1, 1));
  for (index_t v = 0; v < g.size(); ++v) f[v] = float(lo + (hi - lo) * double(g.coords(v)[0]) / nx);
  return f;
}

/// A bar of two materials (the setting of SOFA's beam.mhd, 20x20x100 voxels): stiffness @p soft for
/// the first half of the last axis (z < extent / 2), @p stiff for the rest. Every voxel is inside the
/// domain; the field is piecewise constant, so the problem is not translation-invariant.
template <int Dim>
image<float, Dim> two_material_beam(const grid<Dim>& g, float soft = 1.0e4f, float stiff = 1.0e5f) {
  image<float, Dim> f(g);
  const index_t half = g.extent(Dim - 1) / 2;
  for (index_t v = 0; v < g.size(); ++v) f[v] = g.coords(v)[Dim - 1] < half ? soft : stiff;
  return f;
}

/// Tissue of a point of the steak's cross-section, in normalised coordinates u, v in [-1, 1]:
/// 0 background, 1 meat, 2 fat, 3 bone.
inline int steak_tissue(double u, double v, double w = 0.0) {
  // outline: a lopsided ellipse whose radius wobbles, thinning slightly towards the slab's faces
  const double a = std::atan2(v, u);
  const double r = std::sqrt(u * u + v * v);
  const double edge = 0.92 + 0.05 * std::sin(3 * a + 0.7) + 0.03 * std::cos(5 * a) - 0.06 * w * w;
  if (r > edge) return 0;
  // the T-bone: a bar across (the top of the T) and a bar down (its stem), slightly curved
  const double ux = u + 0.05 * std::sin(2.5 * v);
  if (std::abs(v - 0.12 - 0.04 * u * u) < 0.07 && std::abs(u) < 0.62) return 3;
  if (std::abs(ux + 0.05) < 0.06 && v > 0.12 && v < 0.82 * edge) return 3;
  // fat: a rim around the outline and marbling veins inside
  if (r > edge - 0.09 - 0.02 * std::sin(7 * a)) return 2;
  const double vein = std::sin(9 * u + 4 * std::sin(3 * v)) * std::sin(7 * v - 2 * u + 1.3 * w);
  if (vein > 0.93) return 2;
  return 1;
}

/// The T-bone-steak phantom over a 3D grid (cross-section in x-y, slab along z); about 128x96x32
/// voxels suits the demo. Background voxels are 0 (outside the domain).
inline image<float, 3> steak(const grid<3>& g, steak_moduli m = {}) {
  image<float, 3> f(g, 0.0f);
  const index_t nx = g.extent(0), ny = g.extent(1), nz = g.extent(2);
  for (index_t z = 0; z < nz; ++z)
    for (index_t y = 0; y < ny; ++y)
      for (index_t x = 0; x < nx; ++x) {
        const double u = nx > 1 ? 2.0 * double(x) / double(nx - 1) - 1.0 : 0.0;
        const double v = ny > 1 ? 2.0 * double(y) / double(ny - 1) - 1.0 : 0.0;
        const double w = nz > 1 ? 2.0 * double(z) / double(nz - 1) - 1.0 : 0.0;
        const int t = steak_tissue(u, v, w);
        f({x, y, z}) = t == 0 ? 0.0f : t == 1 ? m.meat : t == 2 ? m.fat : m.bone;
      }
  return f;
}

/// Extents and spacing of the MRI-like phantom: SOFA's pelvis MRI is 221 x 271 x 69 voxels of about
/// 0.9 x 0.9 x 2.5 mm; @p nx scales the grid (y and z follow the pelvis's proportions).
inline grid<3> mri_like_grid(index_t nx = 221) {
  const index_t n = std::max<index_t>(nx, 1);
  const index_t ny = std::max<index_t>(1, (n * 271 + 110) / 221), nz = std::max<index_t>(1, (n * 69 + 110) / 221);
  return grid<3>({n, ny, nz}, {0.9, 0.9, 2.5});
}

/// Mean intensities of the MRI-like phantom's tissues (arbitrary units, used as stiffness).
struct mri_intensities {
  float fat = 900.0f;     ///< subcutaneous rim and intermuscular streaks
  float muscle = 250.0f;  ///< the bulk of the body
  float fluid = 1500.0f;  ///< the bladder
  float marrow = 600.0f;  ///< inside the hip bones and the sacrum
  float cortex = 12.0f;   ///< cortical bone shells (dark in MRI)
  float gas = 2.0f;       ///< bowel gas pockets
  float skin = 6.0f;      ///< the body's ragged partial-volume edge
};

namespace detail {
/// Deterministic per-voxel hash in [0, 1) (splitmix64), independent of the platform's <random>.
inline double unit_hash(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  x ^= x >> 31;
  return double(x >> 11) * (1.0 / 9007199254740992.0);
}
/// The width of a finger of phantom::fingers() (the rule is there), checking its arguments.
inline index_t finger_width(const grid<3>& g, int count, index_t gap) {
  if (count < 1) throw std::invalid_argument("phantom::fingers: count must be >= 1");
  if (gap < 1) throw std::invalid_argument("phantom::fingers: gap must be >= 1 voxel");
  const index_t nx = g.extent(0);
  const index_t w = (nx - (count - 1) * gap) / count;
  if (w < 1)
    throw std::invalid_argument("phantom::fingers: " + std::to_string(count) + " fingers with gaps of " +
                                std::to_string(gap) + " voxels do not fit in " + std::to_string(nx) + " columns");
  return w;
}

}  // namespace detail

/// Tissue of a point of the MRI-like pelvis, in normalised coordinates u (left-right), v
/// (front-back), w (feet-head), each in [-1, 1]: 0 outside, 1 skin edge, 2 fat, 3 muscle,
/// 4 fluid, 5 marrow, 6 cortical bone, 7 gas.
inline int mri_tissue(double u, double v, double w) {
  const double a = std::atan2(v, u);
  const double r = std::sqrt(u * u + (v / 0.82) * (v / 0.82));
  const double edge = 0.88 + 0.05 * std::sin(2 * a + 1.1 * w) + 0.03 * std::cos(5 * a - 0.5) - 0.05 * w * w +
                      0.015 * std::sin(13 * a + 3 * w);
  if (r > edge) return 0;
  if (r > edge - 0.025) return 1;
  if (r > edge - 0.13 - 0.03 * std::sin(6 * a + w)) return 2;
  // two hip bones (marrow inside a cortical shell) and the sacrum behind
  for (int side = -1; side <= 1; side += 2) {
    const double cu = u - side * (0.48 + 0.04 * w), cv = v - 0.02 - 0.05 * w;
    const double rho = std::sqrt(cu * cu + 1.3 * cv * cv);
    const double shell = 0.17 + 0.03 * std::sin(3 * std::atan2(cv, cu) + w);
    if (rho < shell + 0.028) return rho > shell - 0.01 ? 6 : 5;
  }
  {
    const double su = u / 0.22, sv = (v - 0.5 + 0.08 * w) / 0.12;
    const double s = su * su + sv * sv;
    if (s < 1.0) return s > 0.6 ? 6 : 5;
  }
  // bladder in front, gas pockets in the bowel above it
  if (u * u / 0.04 + (v + 0.4) * (v + 0.4) / 0.02 + w * w / 0.5 < 1.0) return 4;
  for (int k = 0; k < 4; ++k) {
    const double gu = u - (-0.2 + 0.14 * k), gv = v + 0.05 - 0.07 * (k % 2), gw = w - 0.35 + 0.15 * k;
    if (gu * gu + gv * gv + 0.2 * gw * gw < 0.0025 + 0.001 * k) return 7;
  }
  // muscle, streaked with fat
  const double streak = std::sin(11 * u + 3 * std::sin(4 * v)) * std::sin(8 * v - 3 * u + 1.7 * w);
  return streak > 0.9 ? 2 : 3;
}

/**
 * A real-data-like stiffness volume: a noisy MRI of a pelvis-shaped body. Tissue regions (fat,
 * muscle, bladder fluid, bone marrow, dark cortical bone shells, bowel gas, a dim ragged skin
 * edge) span about three decades of values (1-2000), a smooth bias field (+-20 %) and per-voxel
 * noise (+-@p noise, roughly Gaussian) make every region heterogeneous, and everything outside the
 * body is 0 (masked). Deterministic in @p salt. Use with mri_like_grid()'s anisotropic spacing.
 * @throws std::invalid_argument if @p noise is outside [0, 0.5).
 */
inline image<float, 3> mri_like(const grid<3>& g, std::uint64_t salt = 17, double noise = 0.15,
                                mri_intensities m = {}) {
  if (!(noise >= 0.0 && noise < 0.5)) throw std::invalid_argument("phantom::mri_like: noise must be in [0, 0.5)");
  image<float, 3> f(g, 0.0f);
  const index_t nx = g.extent(0), ny = g.extent(1), nz = g.extent(2);
  const float level[8] = {0.0f, m.skin, m.fat, m.muscle, m.fluid, m.marrow, m.cortex, m.gas};
  const std::uint64_t base = salt * 0xD1B54A32D192ED03ull;
  for (index_t z = 0; z < nz; ++z)
    for (index_t y = 0; y < ny; ++y)
      for (index_t x = 0; x < nx; ++x) {
        const double u = nx > 1 ? 2.0 * double(x) / double(nx - 1) - 1.0 : 0.0;
        const double v = ny > 1 ? 2.0 * double(y) / double(ny - 1) - 1.0 : 0.0;
        const double w = nz > 1 ? 2.0 * double(z) / double(nz - 1) - 1.0 : 0.0;
        const int t = mri_tissue(u, v, w);
        if (t == 0) continue;
        const index_t idx = g.index({x, y, z});
        const std::uint64_t h = base + 4 * std::uint64_t(idx);
        // sum of four uniforms: mean 2, sd about 0.58; scaled to unit sd
        const double gauss = (detail::unit_hash(h) + detail::unit_hash(h + 1) + detail::unit_hash(h + 2) +
                              detail::unit_hash(h + 3) - 2.0) * 1.7320508;
        const double bias = 1.0 + 0.2 * std::sin(1.7 * u + 0.9) * std::cos(1.3 * v - 0.4 * w);
        const double value = double(level[t]) * bias * std::max(0.2, 1.0 + noise * gauss);
        f[idx] = float(std::max(value, 0.5));
      }
  return f;
}

/**
 * @brief A hand: a palm with @p count parallel fingers separated by gaps of @p gap voxels, a 3D slab
 *        of uniform stiffness @p stiffness on empty background (0).
 *
 * The palm fills the rows y < max(1, ny / 4) over the whole x range and every z. Finger i fills
 * x in [i (w + gap), i (w + gap) + w) for y >= the palm's rows and every z, with
 * w = (nx - (count - 1) gap) / count (rounded down); columns right of the last finger are empty. The
 * gaps are empty from the palm to the top row, so the only path between two fingertips runs down
 * through the palm. With gaps thinner than a coarse cell (1 voxel against a factor of 4), a regular
 * coarse grid glues neighbouring fingers; a branching grid keeps them apart.
 * @throws std::invalid_argument if count < 1, gap < 1 or the fingers would be narrower than 1 voxel.
 *
 * @code
 * auto hand = geovoronoi::phantom::fingers(geovoronoi::grid<3>({55, 48, 8}));  // 4 fingers of 13 voxels
 * @endcode
 */
inline image<float, 3> fingers(const grid<3>& g, int count = 4, index_t gap = 1, float stiffness = 1.0f) {
  const index_t nx = g.extent(0), ny = g.extent(1), nz = g.extent(2);
  const index_t w = detail::finger_width(g, count, gap), palm = std::max<index_t>(1, ny / 4);
  image<float, 3> f(g, 0.0f);
  for (index_t z = 0; z < nz; ++z)
    for (index_t y = 0; y < ny; ++y)
      for (index_t x = 0; x < nx; ++x) {
        bool in = y < palm;
        if (!in) {
          const index_t i = x / (w + gap), r = x % (w + gap);
          in = i < count && r < w;
        }
        if (in) f({x, y, z}) = stiffness;
      }
  return f;
}

/// @p count well-spread seed voxels inside the domain of @p field (value > 0), deterministic:
/// greedy farthest-point sampling in index space from the domain voxel nearest the centre.
template <int Dim>
std::vector<coord<Dim>> spread_seeds(const image<float, Dim>& field, int count) {
  const auto& g = field.geometry();
  std::vector<index_t> in;
  for (index_t v = 0; v < g.size(); ++v)
    if (field[v] > 0) in.push_back(v);
  std::vector<coord<Dim>> out;
  if (in.empty() || count <= 0) return out;
  // a strided subsample keeps this O(count * samples) on big volumes
  const std::size_t stride = std::max<std::size_t>(1, in.size() / 20000);
  std::vector<index_t> cand;
  for (std::size_t i = 0; i < in.size(); i += stride) cand.push_back(in[i]);
  auto dist2 = [&](index_t a, index_t b) {
    const auto ca = g.coords(a), cb = g.coords(b);
    double s = 0;
    for (int k = 0; k < Dim; ++k) s += double(ca[k] - cb[k]) * double(ca[k] - cb[k]);
    return s;
  };
  coord<Dim> mid{};
  for (int k = 0; k < Dim; ++k) mid[k] = g.extent(k) / 2;
  index_t first = cand[0];
  for (index_t c : cand)
    if (dist2(c, g.index(mid)) < dist2(first, g.index(mid))) first = c;
  std::vector<double> best(cand.size(), 1e300);
  index_t next = first;
  for (int s = 0; s < count && s < int(cand.size()); ++s) {
    const index_t chosen = next;
    out.push_back(g.coords(chosen));
    double far = -1;
    for (std::size_t i = 0; i < cand.size(); ++i) {
      best[i] = std::min(best[i], dist2(cand[i], chosen));
      if (best[i] > far) far = best[i], next = cand[i];
    }
    if (far <= 0) break;
  }
  return out;
}

/// @p count pseudo-random distinct seed voxels inside the domain (value > 0), deterministic in @p salt.
template <int Dim>
std::vector<coord<Dim>> random_seeds(const image<float, Dim>& field, int count, std::uint64_t salt = 1) {
  const auto& g = field.geometry();
  std::vector<coord<Dim>> out;
  std::vector<char> used(static_cast<std::size_t>(g.size()), 0);
  std::uint64_t s = salt * 0x9E3779B97F4A7C15ull + 1;
  for (index_t tries = 0; int(out.size()) < count && tries < 100 * g.size() + 1000; ++tries) {
    s ^= s << 13, s ^= s >> 7, s ^= s << 17;
    const index_t v = index_t(s % std::uint64_t(g.size()));
    if (field[v] > 0 && !used[v]) used[v] = 1, out.push_back(g.coords(v));
  }
  return out;
}

/// The box [lo, hi] as 12 triangles facing outward (counter-clockwise seen from outside).
/// @throws std::invalid_argument unless lo < hi along every axis.
inline triangle_mesh box_mesh(const point<3>& lo, const point<3>& hi) {
  for (int a = 0; a < 3; ++a)
    if (!(lo[a] < hi[a])) throw std::invalid_argument("geovoronoi::phantom::box_mesh: lo must be below hi along every axis");
  triangle_mesh m;
  for (int c = 0; c < 8; ++c) m.vertices.push_back({c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]});
  // corner c has bit a set when it is at hi along axis a
  m.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},   // z = lo, z = hi
                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},   // y = lo, y = hi
                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};  // x = lo, x = hi
  return m;
}

/// An icosphere subdivided @p subdivisions times (20 * 4^s triangles), its vertices on the unit
/// sphere, scaled by @p radii and moved to @p centre; closed, facing outward.
/// @throws std::invalid_argument for radii that are not > 0 or subdivisions outside [0, 9].
inline triangle_mesh ellipsoid_mesh(const point<3>& centre, const point<3>& radii, int subdivisions) {
  if (!(radii[0] > 0 && radii[1] > 0 && radii[2] > 0) || subdivisions < 0 || subdivisions > 9)
    throw std::invalid_argument("geovoronoi::phantom::ellipsoid_mesh: radii must be > 0 and subdivisions in [0, 9]");
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<std::array<double, 3>> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<std::uint32_t, 3>> f = {{0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11},
                                                 {1, 5, 9}, {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                                 {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8}, {3, 8, 9},
                                                 {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  auto unit = [](std::array<double, 3> p) {
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    return std::array<double, 3>{p[0] / r, p[1] / r, p[2] / r};
  };
  for (auto& p : v) p = unit(p);
  for (auto& tri : f) {  // face outward: the normal along the centroid
    const auto &a = v[tri[0]], &b = v[tri[1]], &c = v[tri[2]];
    const double n0 = (b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]);
    const double n1 = (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]);
    const double n2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (n0 * (a[0] + b[0] + c[0]) + n1 * (a[1] + b[1] + c[1]) + n2 * (a[2] + b[2] + c[2]) < 0) std::swap(tri[1], tri[2]);
  }
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::uint32_t> mid;
    auto middle = [&](std::uint32_t a, std::uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      const auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      v.push_back(unit({v[a][0] + v[b][0], v[a][1] + v[b][1], v[a][2] + v[b][2]}));
      const auto id = static_cast<std::uint32_t>(v.size() - 1);
      mid.emplace(key, id);
      return id;
    };
    std::vector<std::array<std::uint32_t, 3>> g;
    g.reserve(f.size() * 4);
    for (const auto& tri : f) {
      const std::uint32_t ab = middle(tri[0], tri[1]), bc = middle(tri[1], tri[2]), ca = middle(tri[2], tri[0]);
      g.push_back({tri[0], ab, ca});
      g.push_back({tri[1], bc, ab});
      g.push_back({tri[2], ca, bc});
      g.push_back({ab, bc, ca});
    }
    f.swap(g);
  }
  triangle_mesh m;
  m.vertices.reserve(v.size());
  for (const auto& p : v)
    m.vertices.push_back({centre[0] + radii[0] * p[0], centre[1] + radii[1] * p[1], centre[2] + radii[2] * p[2]});
  m.triangles = std::move(f);
  return m;
}

/// A torus about the z axis through @p centre: tube radius @p minor around a circle of radius
/// @p major, @p segments_major x @p segments_minor quads split in two triangles; closed, facing outward.
/// @throws std::invalid_argument unless 0 < minor < major and both segment counts are >= 3.
inline triangle_mesh torus_mesh(const point<3>& centre, double major, double minor, int segments_major,
                                int segments_minor) {
  if (!(minor > 0 && major > minor) || segments_major < 3 || segments_minor < 3)
    throw std::invalid_argument("geovoronoi::phantom::torus_mesh: needs 0 < minor < major and at least 3 segments each way");
  const double pi = 3.14159265358979323846;
  triangle_mesh m;
  const auto nu = static_cast<std::uint32_t>(segments_major), nv = static_cast<std::uint32_t>(segments_minor);
  for (std::uint32_t i = 0; i < nu; ++i)
    for (std::uint32_t j = 0; j < nv; ++j) {
      const double th = 2 * pi * i / nu, ph = 2 * pi * j / nv;
      const double r = major + minor * std::cos(ph);
      m.vertices.push_back({centre[0] + r * std::cos(th), centre[1] + r * std::sin(th), centre[2] + minor * std::sin(ph)});
    }
  auto at = [&](std::uint32_t i, std::uint32_t j) { return (i % nu) * nv + (j % nv); };
  for (std::uint32_t i = 0; i < nu; ++i)
    for (std::uint32_t j = 0; j < nv; ++j) {
      // d/dtheta x d/dphi points outward
      m.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      m.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
    }
  return m;
}

/// The demo's mesh phantom, in millimetres, centred at 0: a soft-tissue ellipsoid of 120 x 60 x 40
/// ("flesh", value 2e4, label 1) and inside it a thin stiff ellipsoid of 90 x 12 x 12 along x
/// ("bone", value 1.5e10, label 2), listed flesh then bone so overlap_rule::last_wins puts the bone on top.
inline std::vector<voxelize_part> limb() {
  std::vector<voxelize_part> parts(2);
  parts[0].mesh = ellipsoid_mesh({0, 0, 0}, {60, 30, 20}, 4);
  parts[0].value = 2.0e4;
  parts[0].label = 1;
  parts[0].name = "flesh";
  parts[1].mesh = ellipsoid_mesh({0, 0, 0}, {45, 6, 6}, 3);
  parts[1].value = 1.5e10;
  parts[1].label = 2;
  parts[1].name = "bone";
  return parts;
}

/**
 * @brief phantom::fingers(g, count, gap, stiffness) as closed meshes: the palm and each finger a box
 *        (voxelize_part with @p stiffness and label 1) whose faces lie half a voxel outside its
 *        voxels' centres, in world coordinates through g (origin, spacing and direction).
 *
 * No voxel centre lies on a face, so voxelize(fingers_meshes(g, ...), g) reproduces
 * fingers(g, ...) exactly: the hand as a user would bring it, a surface mesh, for voxelizing at the
 * fine resolution of a branching grid. Fingers and palm touch along a face (they are separate parts
 * of one material).
 * @throws std::invalid_argument as fingers() does.
 */
inline std::vector<voxelize_part> fingers_meshes(const grid<3>& g, int count = 4, index_t gap = 1, float stiffness = 1.0f) {
  const index_t nx = g.extent(0), ny = g.extent(1), nz = g.extent(2);
  const index_t w = detail::finger_width(g, count, gap), palm = std::max<index_t>(1, ny / 4);
  // a box over the voxels [lo, hi) in index space, its corners moved to world coordinates
  auto box = [&](coord<3> lo, coord<3> hi, std::string name) {
    voxelize_part part;
    part.mesh = box_mesh({double(lo[0]) - 0.5, double(lo[1]) - 0.5, double(lo[2]) - 0.5},
                         {double(hi[0]) - 0.5, double(hi[1]) - 0.5, double(hi[2]) - 0.5});
    for (auto& v : part.mesh.vertices) {
      std::array<double, 3> x{};
      for (int r = 0; r < 3; ++r) {
        x[std::size_t(r)] = g.origin()[r];
        for (int a = 0; a < 3; ++a) x[std::size_t(r)] += g.direction(r, a) * (v[std::size_t(a)] * g.spacing(a));
      }
      v = x;
    }
    part.value = stiffness;
    part.label = 1;
    part.name = std::move(name);
    return part;
  };
  std::vector<voxelize_part> parts;
  parts.push_back(box({0, 0, 0}, {nx, palm, nz}, "palm"));
  if (palm < ny)
    for (int i = 0; i < count; ++i) {
      const index_t x0 = index_t(i) * (w + gap);
      parts.push_back(box({x0, palm, 0}, {x0 + w, ny, nz}, "finger " + std::to_string(i)));
    }
  return parts;
}

}  // namespace geovoronoi::phantom

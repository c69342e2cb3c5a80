#pragma once
/// @file phantom.hpp
/// @brief Procedural stiffness volumes used by the benchmarks, the tests and the demo: constant,
///        gradient (1 -> 10 along x), a two-material beam and a T-bone-steak phantom (meat, fat, bone,
///        background).

#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
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

}  // namespace geovoronoi::phantom

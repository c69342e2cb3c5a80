#pragma once
// Shared pieces of the voxelizer: a part snapped to the lattice, the perturbed row/triangle test,
// the exact crossing position, the row sweep, and a deterministic host parallel loop.

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/exact.hpp>
#include <geovoronoi/detail/lattice.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/mesh.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace geovoronoi::detail::vox {

/// Lattice steps per voxel, and half of it.
inline constexpr std::int64_t one = std::int64_t(1) << lattice_bits;
inline constexpr std::int64_t half = one / 2;

/// "part 2" or "part 2 (\"bone\")" (0-based position in the list).
inline std::string part_text(const std::string& name, std::size_t i) {
  std::string s = "part " + std::to_string(i);
  if (!name.empty()) s += " (\"" + geovoronoi::printable(name) + "\")";
  return s;
}

inline std::string point_text(const std::array<double, 3>& p) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "(%.9g, %.9g, %.9g)", p[0], p[1], p[2]);
  return buf;
}

/// A non-degenerate triangle on the lattice, with its (unnormalised) normal.
struct lattice_triangle {
  lattice3 v[3];
  std::uint32_t id[3];   ///< canonical vertex ids (vertices on the same lattice point share one)
  int128_t n[3];         ///< (b - a) x (c - a)
  std::int64_t lo[3], hi[3];
  std::uint32_t index;   ///< position in the part's mesh
};

/// A part after snapping: its usable triangles and what the checks found.
struct snapped_part {
  std::vector<lattice3> pts;
  std::vector<std::uint32_t> canon;  ///< vertex -> smallest vertex index on the same lattice point
  std::vector<lattice_triangle> tris;
  std::size_t degenerate = 0;
  bool paired = false;    ///< every edge shared by exactly two triangles in opposite directions
  double volume = 0.0;    ///< signed enclosed volume, world units^3
};

/// Sign of orient2d((au, av), (bu, bv), (pu + eps, pv + eps^2)) for infinitesimal eps > 0: never 0
/// for distinct a, b.
inline int perturbed_orient(std::int64_t au, std::int64_t av, std::int64_t bu, std::int64_t bv, std::int64_t pu,
                            std::int64_t pv) noexcept {
  const int128_t o = int128_t(bu - au) * (pv - av) - int128_t(bv - av) * (pu - au);
  if (o != 0) return o > 0 ? 1 : -1;
  if (bv != av) return av > bv ? 1 : -1;
  return bu > au ? 1 : -1;
}

/// A crossing of a row with a triangle: at x = r / d (lattice units, d > 0), sign s = sign(n_x).
struct crossing {
  int128_t r, d;
  int s;
};

/// The row through lattice point (., y, z), perturbed to (., y + eps, z + eps^2), crosses @p t:
/// fills @p out and returns true.
inline bool row_crossing(const lattice_triangle& t, std::int64_t y, std::int64_t z, crossing& out) noexcept {
  if (t.n[0] == 0) return false;
  const lattice3 &a = t.v[0], &b = t.v[1], &c = t.v[2];
  const int o1 = perturbed_orient(a[1], a[2], b[1], b[2], y, z);
  if (perturbed_orient(b[1], b[2], c[1], c[2], y, z) != o1) return false;
  if (perturbed_orient(c[1], c[2], a[1], a[2], y, z) != o1) return false;
  // n . ((x, y, z) - a) = 0  =>  x = (a_x n_x - n_y (y - a_y) - n_z (z - a_z)) / n_x
  int128_t r = int128_t(a[0]) * t.n[0] - t.n[1] * (y - a[1]) - t.n[2] * (z - a[2]);
  int128_t d = t.n[0];
  if (d < 0) {
    r = -r;
    d = -d;
  }
  out = {r, d, o1};
  return true;
}

/// ceil(p / q) for q > 0.
inline int128_t ceil_div(int128_t p, int128_t q) noexcept {
  int128_t x = p / q;
  if (p % q != 0 && p > 0) ++x;
  return x;
}

/**
 * cnt[i] = sum of the signs of the crossings strictly beyond sample i (x_cross > i * one + ox), for
 * i in [0, nx): a difference array, O(nx + crossings), no sort.
 */
inline void sweep(const std::vector<crossing>& cs, index_t nx, std::int64_t ox, std::vector<int>& diff, int* cnt) {
  diff.assign(static_cast<std::size_t>(nx) + 1, 0);
  for (const crossing& c : cs) {
    const int128_t m = ceil_div(c.r - int128_t(ox) * c.d, c.d * one);  // samples i < m see it
    const index_t at = m <= 0 ? 0 : (m >= nx ? nx : static_cast<index_t>(m));
    diff[static_cast<std::size_t>(at)] += c.s;
  }
  int acc = 0;
  for (index_t i = nx - 1; i >= 0; --i) {
    acc += diff[static_cast<std::size_t>(i) + 1];
    cnt[i] = acc;
  }
}

/// The closed cube [c - half, c + half]^3 (lattice) meets the closed triangle @p t (separating axes,
/// exact: every projection fits 128 bits for coordinates below 2^41 apart).
inline bool triangle_meets_cube(const lattice_triangle& t, const lattice3& c) noexcept {
  for (int k = 0; k < 3; ++k)
    if (t.hi[k] < c[k] - half || t.lo[k] > c[k] + half) return false;
  int128_t v[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) v[i][k] = int128_t(t.v[i][k] - c[k]);
  auto mag = [](int128_t x) { return x < 0 ? -x : x; };
  auto separated = [&](const int128_t* axis) {
    int128_t p[3];
    for (int i = 0; i < 3; ++i) p[i] = axis[0] * v[i][0] + axis[1] * v[i][1] + axis[2] * v[i][2];
    const int128_t mn = std::min({p[0], p[1], p[2]}), mx = std::max({p[0], p[1], p[2]});
    const int128_t rad = int128_t(half) * (mag(axis[0]) + mag(axis[1]) + mag(axis[2]));
    return mn > rad || mx < -rad;
  };
  if (separated(t.n)) return false;
  for (int e = 0; e < 3; ++e) {
    const int128_t ed[3] = {v[(e + 1) % 3][0] - v[e][0], v[(e + 1) % 3][1] - v[e][1], v[(e + 1) % 3][2] - v[e][2]};
    for (int k = 0; k < 3; ++k) {
      // ed x unit_k
      int128_t ax[3] = {0, 0, 0};
      ax[(k + 1) % 3] = ed[(k + 2) % 3];
      ax[(k + 2) % 3] = -ed[(k + 1) % 3];
      if (ax[0] == 0 && ax[1] == 0 && ax[2] == 0) continue;
      if (separated(ax)) return false;
    }
  }
  return true;
}

/// Runs f(worker, i) for i in [0, n) on @p threads host threads (0: the hardware's), each i once.
/// Which worker runs which i varies; callers write results by i only, so nothing depends on it.
/// The first exception is rethrown on the calling thread.
template <class F>
void parallel_for(index_t n, unsigned threads, F&& f) {
  if (n <= 0) return;
  unsigned t = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  t = static_cast<unsigned>(std::min<index_t>(t, n));
  if (t <= 1) {
    for (index_t i = 0; i < n; ++i) f(0u, i);
    return;
  }
  std::atomic<index_t> next{0};
  std::exception_ptr error;
  std::mutex m;
  auto body = [&](unsigned w) {
    try {
      for (index_t i; (i = next.fetch_add(1)) < n;) f(w, i);
    } catch (...) {
      std::lock_guard<std::mutex> lock(m);
      if (!error) error = std::current_exception();
      next.store(n);
    }
  };
  std::vector<std::thread> pool;
  pool.reserve(t - 1);
  for (unsigned w = 1; w < t; ++w) pool.emplace_back(body, w);
  body(0);
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

/// The worker count parallel_for(n, threads, ...) uses at most.
inline unsigned worker_count(index_t n, unsigned threads) {
  unsigned t = threads ? threads : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::max<index_t>(1, std::min<index_t>(t, n)));
}

}  // namespace geovoronoi::detail::vox

#pragma once
// Host-device arithmetic of the CUDA backend that needs no CUDA compiler: the tile decomposition,
// halo indexing, packed keys of each relaxation rule, the two-list worklist bookkeeping and the
// placement of the insert-query boxes. It is a plain .hpp on purpose: tests/cuda_tiling.test.cpp
// checks it with g++ on machines without a GPU.

#include <geovoronoi/config.hpp>

#include <cstdint>
#include <cstring>
#include <type_traits>

namespace geovoronoi::cuda::detail {

using std::uint32_t;
using std::uint64_t;

/// Tile edge lengths: 8x8x8 in 3D, 32x16 in 2D (both 512 voxels = one 512-thread block).
template <int Dim>
struct tile_shape {
  static constexpr int tx = Dim == 3 ? 8 : 32;
  static constexpr int ty = Dim == 3 ? 8 : 16;
  static constexpr int tz = Dim == 3 ? 8 : 1;
  static constexpr int hz = Dim == 3 ? 1 : 0;  ///< halo depth along z (none in 2D)
  static constexpr int sx = tx + 2, sy = ty + 2, sz = tz + 2 * hz;  ///< haloed box
  static constexpr int voxels = tx * ty * tz;
  static constexpr int halo_voxels = sx * sy * sz;
};

/// The grid cut into tiles; trivially copyable, passed to kernels by value.
struct tiling {
  index_t nx = 1, ny = 1, nz = 1;      ///< grid extents (nz = 1 in 2D)
  index_t tnx = 1, tny = 1, tnz = 1;   ///< tiles per axis
  int tx = 1, ty = 1, tz = 1;          ///< tile extents

  GEOVORONOI_HOST_DEVICE index_t tiles() const noexcept { return tnx * tny * tnz; }
  GEOVORONOI_HOST_DEVICE index_t voxels() const noexcept { return nx * ny * nz; }

  /// Tile id of tile coordinates (x fastest, like voxels).
  GEOVORONOI_HOST_DEVICE index_t tile_id(index_t a, index_t b, index_t c) const noexcept { return a + tnx * (b + tny * c); }
  GEOVORONOI_HOST_DEVICE void tile_coords(index_t t, index_t& a, index_t& b, index_t& c) const noexcept {
    a = t % tnx;
    t /= tnx;
    b = t % tny;
    c = t / tny;
  }
  /// Tile holding voxel (x, y, z).
  GEOVORONOI_HOST_DEVICE index_t tile_of(index_t x, index_t y, index_t z) const noexcept {
    return tile_id(x / tx, y / ty, z / tz);
  }
  GEOVORONOI_HOST_DEVICE index_t tile_of(index_t v) const noexcept {
    const index_t x = v % nx, r = v / nx;
    return tile_of(x, r % ny, r / ny);
  }
  GEOVORONOI_HOST_DEVICE bool in_grid(index_t x, index_t y, index_t z) const noexcept {
    return x >= 0 && x < nx && y >= 0 && y < ny && z >= 0 && z < nz;
  }
  GEOVORONOI_HOST_DEVICE index_t voxel(index_t x, index_t y, index_t z) const noexcept { return x + nx * (y + ny * z); }
};

/// A tiling of an (nx, ny, nz) grid with the tile shape of dimension Dim.
template <int Dim>
inline tiling make_tiling(index_t nx, index_t ny, index_t nz) noexcept {
  using s = tile_shape<Dim>;
  tiling t;
  t.nx = nx, t.ny = ny, t.nz = nz;
  t.tx = s::tx, t.ty = s::ty, t.tz = s::tz;
  t.tnx = (nx + s::tx - 1) / s::tx;
  t.tny = (ny + s::ty - 1) / s::ty;
  t.tnz = (nz + s::tz - 1) / s::tz;
  return t;
}

/// Position in the haloed shared-memory box of local coordinates (lx, ly, lz), each from -1 (halo)
/// to t? (halo on the far side); z halo only in 3D.
template <int Dim>
GEOVORONOI_HOST_DEVICE constexpr int halo_slot(int lx, int ly, int lz) noexcept {
  using s = tile_shape<Dim>;
  return (lx + 1) + s::sx * ((ly + 1) + s::sy * (lz + s::hz));
}
/// Inverse of halo_slot.
template <int Dim>
GEOVORONOI_HOST_DEVICE constexpr void halo_coords(int slot, int& lx, int& ly, int& lz) noexcept {
  using s = tile_shape<Dim>;
  lx = slot % s::sx - 1;
  slot /= s::sx;
  ly = slot % s::sy - 1;
  lz = slot / s::sy - s::hz;
}
/// Whether a haloed slot lies on the halo ring rather than in the tile itself.
template <int Dim>
GEOVORONOI_HOST_DEVICE constexpr bool is_halo(int lx, int ly, int lz) noexcept {
  using s = tile_shape<Dim>;
  return lx < 0 || lx >= s::tx || ly < 0 || ly >= s::ty || lz < 0 || lz >= s::tz;
}

// ---- packed keys ---------------------------------------------------------------------------------

/// Every rule keeps one 64-bit word per voxel, smaller is better, all ones = not reached.
inline constexpr uint64_t unreached = ~uint64_t(0);

GEOVORONOI_HOST_DEVICE inline uint32_t float_bits(float d) noexcept {
  uint32_t b;
  std::memcpy(&b, &d, sizeof b);
  return b;
}
GEOVORONOI_HOST_DEVICE inline float bits_float(uint32_t b) noexcept {
  float d;
  std::memcpy(&d, &b, sizeof d);
  return d;
}
GEOVORONOI_HOST_DEVICE inline uint64_t double_bits(double d) noexcept {
  uint64_t b;
  std::memcpy(&b, &d, sizeof b);
  return b;
}
GEOVORONOI_HOST_DEVICE inline double bits_double(uint64_t b) noexcept {
  double d;
  std::memcpy(&d, &b, sizeof d);
  return d;
}

/// float solve: (distance bits << 32 | label); same layout as the core's key_traits<float>.
GEOVORONOI_HOST_DEVICE inline uint64_t pack(float d, label_t l) noexcept {
  return (uint64_t(float_bits(d)) << 32) | uint32_t(l);
}
GEOVORONOI_HOST_DEVICE inline float key_distance(uint64_t k) noexcept { return bits_float(uint32_t(k >> 32)); }
GEOVORONOI_HOST_DEVICE inline label_t key_label(uint64_t k) noexcept { return label_t(uint32_t(k)); }

/// Distance-only words (double solve, insert queries): the distance's bit pattern, which orders like
/// the value for non-negative numbers; float bits are zero-extended.
template <class T>
GEOVORONOI_HOST_DEVICE inline uint64_t distance_word(T d) noexcept {
  if constexpr (std::is_same_v<T, float>)
    return uint64_t(float_bits(d));
  else
    return double_bits(d);
}
template <class T>
GEOVORONOI_HOST_DEVICE inline T word_distance(uint64_t w) noexcept {
  if constexpr (std::is_same_v<T, float>)
    return bits_float(uint32_t(w));
  else
    return bits_double(w);
}

/// A source of the engine: voxel and initial state word.
struct seed_word {
  index_t voxel;
  uint64_t word;
};

/// A source of the double label pass: voxel, initial distance bits, label.
struct label_seed {
  index_t voxel;
  uint64_t word;
  std::uint32_t label;
};

// ---- worklist ------------------------------------------------------------------------------------

/// Two tile lists alternate: iteration i consumes list i % 2 and fills list (i + 1) % 2.
GEOVORONOI_HOST_DEVICE constexpr int current_list(long long iteration) noexcept { return int(iteration & 1); }
GEOVORONOI_HOST_DEVICE constexpr int next_list(long long iteration) noexcept { return int((iteration + 1) & 1); }

/// Blocks of the relaxation kernel: enough to fill the device, never more than there are tiles
/// (the kernel strides over the active list, whose length only the device knows).
inline constexpr int blocks_for(index_t tiles, int sm_count, int blocks_per_sm) noexcept {
  const index_t cap = index_t(sm_count > 0 ? sm_count : 1) * (blocks_per_sm > 0 ? blocks_per_sm : 1);
  return int(tiles < cap ? (tiles > 0 ? tiles : 1) : cap);
}

/// Peak device bytes of a dense solve: field + state words + labels (double only) + two tile lists
/// and one flag per tile + a few counters.
template <class T>
inline constexpr uint64_t solve_device_bytes(index_t voxels, index_t tiles) noexcept {
  const uint64_t per_voxel = sizeof(T) + sizeof(uint64_t) + (std::is_same_v<T, double> ? sizeof(label_t) : 0);
  return per_voxel * uint64_t(voxels) + 3 * sizeof(uint32_t) * uint64_t(tiles) + 64;
}

// ---- insert-query boxes --------------------------------------------------------------------------

/// Box (in voxels) searched in shared memory for one query before falling back to the whole grid.
template <int Dim>
struct query_box_shape {
  static constexpr int bx = Dim == 3 ? 16 : 64;
  static constexpr int by = Dim == 3 ? 16 : 64;
  static constexpr int bz = Dim == 3 ? 16 : 1;
  static constexpr int voxels = bx * by * bz;
};

/// Start and extent of the box along one axis of length n, centred on q, shifted to fit the grid.
struct box_axis {
  index_t lo;
  index_t len;
};
GEOVORONOI_HOST_DEVICE inline box_axis place_box(index_t q, index_t n, index_t want) noexcept {
  const index_t len = want < n ? want : n;
  index_t lo = q - len / 2;
  if (lo < 0) lo = 0;
  if (lo + len > n) lo = n - len;
  return {lo, len};
}
/// Whether local coordinate i of an axis placed by place_box is on a face that has grid beyond it
/// (where a cell touching the box may continue outside it).
GEOVORONOI_HOST_DEVICE inline bool open_face(const box_axis& a, index_t i, index_t n) noexcept {
  return (i == 0 && a.lo > 0) || (i == a.len - 1 && a.lo + a.len < n);
}

}  // namespace geovoronoi::cuda::detail

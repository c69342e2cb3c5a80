#pragma once
/// @file config.hpp
/// @brief Version, basic index types and the host/device annotation shared by every header.

#include <cstdint>

#define GEOVORONOI_VERSION_MAJOR 0
#define GEOVORONOI_VERSION_MINOR 1
#define GEOVORONOI_VERSION_PATCH 0

/// Expands to `__host__ __device__` when compiled by a CUDA compiler, to nothing otherwise, so that
/// policy code (grids, connectivities, metrics) is shared verbatim by the host and device backends.
#if defined(__CUDACC__) || defined(__HIPCC__)
#define GEOVORONOI_HOST_DEVICE __host__ __device__
#else
#define GEOVORONOI_HOST_DEVICE
#endif

/// Keeps a rarely taken helper out of line, so that the hot loop calling it keeps its registers.
#if defined(__GNUC__) || defined(__clang__)
#define GEOVORONOI_NOINLINE __attribute__((noinline))
#elif defined(_MSC_VER)
#define GEOVORONOI_NOINLINE __declspec(noinline)
#else
#define GEOVORONOI_NOINLINE
#endif

namespace geovoronoi {

/// Linear voxel index. Always 64-bit: a 2048^3 volume has 8.6e9 voxels.
using index_t = std::int64_t;

/// Seed (node) label: the 0-based position of the seed in the caller's list, -1 for "none".
using label_t = std::int32_t;

/// Label of voxels that are masked or that no seed reaches.
inline constexpr label_t no_label = -1;

/// Index stored in parent images for seeds and for voxels without a parent.
inline constexpr index_t no_index = -1;

}  // namespace geovoronoi

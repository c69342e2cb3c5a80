#pragma once
/// @file voxelize.hpp
/// @brief Turns closed triangle meshes into a stiffness image and a material-label image on a
///        grid<3>, deciding exactly which voxel centres lie inside.
///
/// **The rule.** A voxel belongs to a mesh when its centre is inside the mesh. Every vertex is
/// moved once into the grid's index space and snapped to the lattice of 2^-16 voxel (the rounding
/// cut_from_mesh() uses; the only rounding), so every later test is exact integer arithmetic and
/// the image never depends on the compiler, the thread count or the triangle order.
/// (Body and full statement of the tie rule: detail/voxelize/.)

#include <geovoronoi/config.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>
#include <geovoronoi/mesh.hpp>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace geovoronoi {

/// One surface and what its inside becomes.
struct voxelize_part {
  triangle_mesh mesh;      ///< the surface, in world coordinates
  double value = 1.0;      ///< written to the stiffness image at voxels inside this part
  label_t label = 0;       ///< written to the label image; 0 means "its 1-based position in the list"
  std::string name;        ///< names the part in error messages (a file name); may be empty
};

/// How "inside" is decided.
enum class inside_rule {
  /// The mesh must be closed (every edge shared by exactly two triangles), consistently oriented
  /// and free of self-intersections; otherwise voxelize() throws naming the first offending edge or
  /// triangle. Inside = the exact signed crossing count along the row is non-zero.
  closed,
  /// Any triangle soup: inside = the generalized winding number at the centre is >= 1/2.
  winding
};

/// What a voxel inside several parts receives.
enum class overlap_rule {
  last_wins,   ///< the part listed last
  first_wins,  ///< the part listed first
  max_value,   ///< the part with the largest value (ties: the later part)
  min_value,   ///< the part with the smallest value (ties: the later part)
  error        ///< throw, naming the two parts and a voxel they share
};

/// Options of voxelize(). The grid is given by exactly one of @ref voxel_size or @ref voxels
/// (the overload taking a grid ignores both, and @ref pad, @ref principal_axes, @ref snap_origin).
struct voxelize_options {
  point<3> voxel_size{0.0, 0.0, 0.0};  ///< world size of a voxel per axis (all > 0), or all 0
  coord<3> voxels{0, 0, 0};            ///< voxel counts across the meshes' bounds (all > 0), or all 0
  index_t pad = 0;                     ///< voxels added outside the bounds on every side
  bool principal_axes = false;         ///< grid axes along the meshes' principal axes (a rotated grid)
  bool snap_origin = true;             ///< origin on a multiple of the voxel size along each grid axis
  inside_rule rule = inside_rule::closed;
  overlap_rule overlap = overlap_rule::last_wins;
  bool surface_inside = false;         ///< voxels the surface passes through count as inside too
  int fraction_samples = 0;            ///< k > 0: also the occupied fraction from k^3 samples per voxel
  double outside_value = 0.0;          ///< stiffness of voxels inside no part
};

/// What voxelize() looked at.
struct voxelize_stats {
  std::size_t triangles = 0;      ///< triangles used, over all parts
  std::size_t degenerate = 0;     ///< triangles that collapse on the lattice (skipped; zero area)
  std::size_t crossings = 0;      ///< row/triangle crossings found
  std::size_t inside_voxels = 0;  ///< voxels given to some part
  double mesh_volume = 0.0;       ///< sum of the parts' enclosed volumes (world units^3)
};

/**
 * @brief The images voxelize() builds, all on the same grid.
 * @tparam T value type of the stiffness image (float or double)
 */
template <class T>
struct voxelization {
  image<T, 3> stiffness;          ///< the inside part's value, options.outside_value elsewhere
  image<label_t, 3> label;        ///< the inside part's label, 0 elsewhere
  image<float, 3> fraction;       ///< occupied fraction in [0, 1]; empty unless fraction_samples > 0
  voxelize_stats stats;
};

/**
 * @brief The grid voxelize(parts, options) uses: the parts' bounds (in the principal frame when
 *        asked) grown by options.pad voxels, with the voxel size or counts the options give.
 * @throws std::invalid_argument when neither or both of voxel_size / voxels are given, a size or
 *         count is not positive, there are no triangles, or the grid would be too large.
 */
grid<3> voxelize_grid(const std::vector<voxelize_part>& parts, const voxelize_options& options = {});

/**
 * @brief Voxelizes @p parts onto voxelize_grid(parts, options).
 * @throws std::invalid_argument naming the part and the first open edge, inconsistently oriented
 *         edge or intersecting triangle pair (inside_rule::closed), an overlap (overlap_rule::error),
 *         or a bad option.
 *
 * @code
 * geovoronoi::voxelize_options o;
 * o.voxel_size = {1.0, 1.0, 1.0};
 * o.pad = 2;
 * auto v = geovoronoi::voxelize<float>({{geovoronoi::io::read_mesh("liver.stl"), 3000.0}}, o);
 * auto diagram = geovoronoi::voronoi(seq::par, v.stiffness, seeds);
 * @endcode
 */
template <class T = float>
voxelization<T> voxelize(const std::vector<voxelize_part>& parts, const voxelize_options& options = {});

/// @brief Voxelizes @p parts onto the given grid @p g (any origin, spacing and direction).
template <class T = float>
voxelization<T> voxelize(const std::vector<voxelize_part>& parts, const grid<3>& g,
                         const voxelize_options& options = {});

}  // namespace geovoronoi

#include <geovoronoi/detail/voxelize/voxelize.hpp>

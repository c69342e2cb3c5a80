#pragma once
/// @file voxelize.hpp
/// @brief Turns closed triangle meshes into a stiffness image and a material-label image on a
///        grid<3>, deciding exactly which voxel centres lie inside.
///
/// **Lattice.** Every vertex is moved once into the grid's continuous index space and snapped to
/// the lattice of 2^-16 voxel, exactly as cut_from_mesh() does (detail/lattice.hpp); that rounding
/// is the only one. Voxel centres (i, j, k) are the lattice points (i, j, k) * 2^16, and every test
/// below is exact 128-bit integer arithmetic on snapped vertices, so the images never depend on the
/// compiler, the thread count, the triangle order or the vertex rotation within a triangle (except
/// inside_rule::winding on a soup with unpaired edges, which is floating point: see below).
/// Vertices must lie within 2^24 voxels of voxel 0 along each index axis. Triangles that collapse
/// to a line or a point on the lattice are skipped (voxelize_stats::degenerate).
///
/// **Inside (inside_rule::closed).** A voxel belongs to a part when its centre is inside the part's
/// surface. The centre c = (x, y, z) is tested as the point c + (delta, eps, eps^2) with
/// infinitesimals delta >> eps > 0, which lies on no plane of any triangle (symbolic
/// perturbation). Its winding number is the signed count of the crossings of the ray from it along
/// +x (the row through the voxel, fixed j and k) with the triangles:
///  - the perturbed row (., y + eps, z + eps^2) crosses triangle abc when it lies inside the
///    triangle's projection onto the index (y, z) plane: each edge test is the exact orient2d, and
///    a zero is decided by the eps terms (for edge a -> b: sign(a_z - b_z), else sign(b_y - a_y)).
///    The projection of every edge is on one definite side of the row, so a row through a vertex
///    or an edge shared by triangles of a closed surface is counted exactly once (or, at a
///    silhouette, zero or two times with opposite signs), never twice with the same sign;
///  - a triangle parallel to x (n_x = 0, a degenerate projection) is never crossed;
///  - a crossing has the sign of n_x, the x component of (b - a) x (c - a) (+1 where an
///    outward-facing surface is left along +x), and the exact rational position
///    x_c = a_x - (n_y (y - a_y) + n_z (z - a_z)) / n_x;
///  - it counts for centre x when x_c > x strictly (the half-open rule: delta dominates, so a
///    centre lying exactly on a face counts as lying on its +x side). Two surfaces sharing a face
///    with opposite orientations therefore never both, and never neither, claim a centre on it.
/// The centre is inside when the count is non-zero (nested shells add up; a reversed inner shell,
/// a cavity, cancels its outer shell). Rows are swept with a difference array: the cost is
/// O(voxels + crossings) plus, per triangle, the rows of its projected bounding box.
///
/// **Checks (inside_rule::closed).** Vertices that snap to the same lattice point are merged (their
/// smallest index names them); then every undirected edge must be shared by exactly two triangles
/// running along it in opposite directions, the enclosed signed volume must be positive (a
/// negative one means the mesh is inside out: an error, not a silent flip), and no two triangles
/// may meet except along their shared edge or at their shared vertex (exact orient3d tests over a
/// uniform grid of buckets; touching counts as meeting). Errors are std::invalid_argument naming
/// the part ("part 0", or "part 0 (\"bone\")", positions 0-based), the first offending edge (its
/// two vertex indices and world coordinates) and the triangle indices.
///
/// **Inside (inside_rule::winding).** Any soup: inside when the generalized winding number at the
/// centre is >= 1/2. If the part's edges are paired as above (closed, consistently oriented, even
/// self-intersecting), the winding number off the surface is exactly the signed crossing count, so
/// the rule is exact: count >= 1. Otherwise it is evaluated in double precision with Barill et
/// al.'s tree (exact solid angles near, dipoles beyond 3 node radii; the error is of order 1e-2
/// near the 1/2 level, nothing elsewhere); a centre lying exactly on a triangle (exact test) is
/// evaluated 2^-12 voxel along +x instead, the side the half-open rule picks.
///
/// **Surface voxels (surface_inside).** A voxel also belongs to a part when one of its non-degenerate
/// triangles meets the voxel's closed cube [i - 1/2, i + 1/2] x [j - 1/2, j + 1/2] x [k - 1/2, k + 1/2]
/// in index space (exact separating-axis test on the lattice).
///
/// **Fraction (fraction_samples = k).** The share of k^3 sample points per voxel, at the centres of
/// a k x k x k subdivision rounded to the lattice, that lie inside some part by the same rule
/// (surface_inside does not apply). For k = 1 it is exactly 0 or 1, equal to inside-ness.
///
/// **Several parts.** Each part's inside is decided on its own; overlap_rule settles voxels inside
/// several. Parts are processed z slice by z slice on options.threads host threads; a slice's
/// result depends only on the slice, so the images are bitwise the same for any thread count.

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
/// With @ref voxels the cells span the bounds exactly (spacing = extent / count per axis, the origin
/// is not snapped); with @ref voxel_size the first cell's lower face is at the bounds' minimum, or,
/// with @ref snap_origin, the first centre is the multiple of the voxel size whose cell holds it.
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
  unsigned threads = 0;                ///< host threads (0: the hardware's); never changes the result
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
 *
 * The principal frame: the eigenvectors of the surface's area-weighted second-moment matrix about
 * its area centroid, by decreasing eigenvalue, each of the first two with its largest-magnitude
 * component positive, the third their cross product (right-handed); it becomes the grid's direction
 * matrix (SOFA MeshToImageEngine's rotateImage).
 * @throws std::invalid_argument when neither or both of voxel_size / voxels are given, a size or
 *         count is not positive, there are no triangles, a triangle refers to a missing vertex or a
 *         vertex is not finite, or the grid would hold more than 2^31 voxels (2^24 along an axis).
 */
inline grid<3> voxelize_grid(const std::vector<voxelize_part>& parts, const voxelize_options& options = {});

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

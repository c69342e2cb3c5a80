#pragma once
// Meshes in: what `voxelize`, the `--mesh` option of `voronoi`, `shape-functions` and `cut`, and the
// demo share. The mesh specs (MESH[:VALUE[:LABEL]]), the grid and inside options of the command line,
// reading the meshes, and the one call of the library's voxelize() (docs/cli.md, "Meshes in").

#include "arguments.hpp"
#include "kinds.hpp"

#include <geovoronoi/io/rgb_image.hpp>
#include <geovoronoi/voxelize.hpp>

#include <set>
#include <string>
#include <vector>

namespace gvcli {

/// The help lines of --mesh and its grid options, the same in `voronoi`, `shape-functions` and `cut`.
#define GEOVORONOI_CLI_MESH_HELP                                                                          \
  "  --mesh MESH[:VALUE[:LABEL]]\n"                                                                       \
  "                      instead of --stiffness: the field voxelized from closed meshes (.stl/.obj,\n"   \
  "                      world coordinates; VALUE inside, default 1; 0 outside); repeatable, a later\n"  \
  "                      mesh wins where they overlap (`geovoronoi help voxelize`)\n"                    \
  "  --voxel-size S      with --mesh: the voxel size, S or SX,SY,SZ; or --voxels NX,NY,NZ (one of them)\n" \
  "  --pad N, --rotate, --winding\n"                                                                      \
  "                      with --mesh: as for `geovoronoi voxelize` (default: 0, off, off)\n"

/// One `MESH[:VALUE[:LABEL]]` of the command line.
struct mesh_spec {
  std::string path;      ///< the .stl or .obj file
  double value = 1.0;    ///< the stiffness inside it (default 1)
  gv::label_t label = 0; ///< its label; 0: its 1-based position among the meshes
};

/// Parses @p text as MESH[:VALUE[:LABEL]]. The text is split at its last colon only when what follows
/// is a number (a mesh file ends in .stl or .obj, never in a number), then once more for VALUE:LABEL,
/// so `C:\m\liver.stl:3000:2` is the file C:\m\liver.stl. VALUE: a finite number; LABEL: an integer
/// from 1 to 2147483647. A usage_error naming the text when a part is bad.
mesh_spec parse_mesh_spec(const std::string& text);

/// The grid and inside options shared by `voxelize` and `--mesh`: --voxel-size, --voxels, --pad
/// (with a value) and --rotate, --winding (flags).
std::set<std::string> mesh_grid_options();
std::set<std::string> mesh_grid_flags();
/// The options of `voxelize` alone: --overlap, --fraction, --outside-value, --format, --precision;
/// and its flag --surface-inside.
std::set<std::string> voxelize_only_options();
std::set<std::string> voxelize_only_flags();

/// The library's options from @p a: exactly one of --voxel-size S | SX,SY,SZ and --voxels NX,NY,NZ,
/// --pad N, --rotate, --winding, and (when given: `voxelize` only) --overlap, --surface-inside,
/// --fraction, --outside-value. A usage_error for anything bad or missing.
gv::voxelize_options parse_voxelize_options(const arguments& a);

/// Reads the meshes of @p specs (each recorded by the run's read_log) into the library's parts, named
/// by their files. A usage_error for a file that is not .stl/.obj, missing or malformed.
std::vector<gv::voxelize_part> read_mesh_parts(const std::vector<mesh_spec>& specs);

/// The one call of the library's voxelize() of the front end (the command, --mesh, the demo): the
/// library's refusals (an open mesh, an overlap under --overlap error, a grid too large) come back as
/// a usage_error with the library's message.
template <class T>
gv::voxelization<T> voxelize_parts(const std::vector<gv::voxelize_part>& parts, const gv::voxelize_options& o);

/// Voxels with each label 1..max (index = label; entry 0 counts the voxels inside no part).
std::vector<std::size_t> label_counts(const gv::image<gv::label_t, 3>& label);

/// "flesh.stl (label 1): 1234 voxels, bone.stl (label 2): 56 voxels; mesh volume 12.3, voxel volume
/// 12.5 (+1.6%)": what the summaries print.
std::string voxelize_summary(const std::vector<gv::voxelize_part>& parts, const gv::image<gv::label_t, 3>& label,
                             const gv::voxelize_stats& stats);

/// The three mid-slices of a label image of voxelize() (label 0, outside every mesh, drawn as
/// outside), titled @p title; with @p stiffness, its stiffest material hatched.
template <class S>
geovoronoi::io::rgb_image mesh_label_picture(const gv::image<gv::label_t, 3>& label, const gv::image<S, 3>* stiffness,
                                             const std::string& title);

}  // namespace gvcli

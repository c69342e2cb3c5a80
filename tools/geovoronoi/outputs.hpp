#pragma once
// What the geovoronoi tool writes: the Voronoi outputs and the shape-function outputs (docs/cli.md).

#include "branching.hpp"
#include "kinds.hpp"
#include "output_dir.hpp"

#include <geovoronoi.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/shape_functions.hpp>

#include <string>

namespace gvcli {

/// How the pictures of a run are titled: the metric and neighbourhood, the distance's unit.
struct picture_context {
  std::string metric = "min_stiffness", length = "LENGTH";
  int connectivity = 26;
  std::string setting() const { return "METRIC " + metric + ", " + std::to_string(connectivity) + " NEIGHBOURS"; }
  std::string distance_unit() const {
    if (metric == "uniform") return length;
    if (metric == "mean_cost") return length + " X COST";
    return length + "/STIFFNESS";
  }
  /// Options whose title is "@p what - METRIC m, c NEIGHBOURS".
  geovoronoi::io::picture_options options(const std::string& what) const {
    geovoronoi::io::picture_options o;
    o.title = {what + " - " + setting()};
    return o;
  }
};

/// distance.mhd, label.mhd, labels.png, distance.png, voronoi.vti. The distance (and the stiffness in
/// voronoi.vti) in T: MET_FLOAT / Float32, or MET_DOUBLE / Float64 with `--precision double`.
template <class T>
void write_voronoi(const std::string& dir, const gv::diagram<T, 3>& d, const gv::image<T, 3>& field,
                   const picture_context& pc);
/// The same in the output folder itself.
template <class T>
void write_voronoi(const output_dir& out, const gv::diagram<T, 3>& d, const gv::image<T, 3>& field,
                   const picture_context& pc) {
  write_voronoi(out.subdir("."), d, field, pc);
}

/// In the folder @p dir: indices.mhd, weights.mhd (K interleaved channels: ITK, ParaView, Slicer),
/// indices_sofa_planar.mhd, weights_sofa_planar.mhd (K planar channels, SOFA's layout), weights.vti
/// (K-component weights and nodes arrays), weights_*.npy (CSR), weight_node<png_node>.png (titled
/// "@p method SHAPE FUNCTION"; voxels without any weight drawn as outside). Weights in T (float, or
/// double with `--precision double`).
template <class T>
void write_shape(const std::string& dir, const gv::shape_weights<T, 3>& w, const gv::diagram<T, 3>& d, int png_node,
                 const picture_context& pc, const std::string& method);

/// Writes the weights at chosen points (shape-functions --at) into @p dir: weights_at_indptr/indices/
/// data.npy (points x nodes CSR; data in T) and weights_at.csv (point,node,weight).
template <class T>
void write_shape_at(const std::string& dir, const gv::point_weights<T>& w);

/// copies.npz at @p path: the branching grid and its diagram per copy (`--coarsen`; docs/cli.md).
template <class T>
void write_copies(const std::string& path, const branching_solution<T>& s);

/// copy_weights.npz at @p path: the weights per copy (`shape-functions --coarsen`, the per-copy
/// layout beside the fine images of write_shape(); docs/cli.md): node and weight (copies, K), each
/// copy's cell, lowest fine voxel and voxel count, fine_copy, the seeds' copies, K, the nodes, the
/// factor and the coarse grid.
template <class T>
void write_copy_weights(const std::string& path, const branching_solution<T>& s);

/// The one summary line a command prints at the end.
void summary(const char* what, const gv::grid<3>& g, std::size_t seeds, const std::string& backend, double seconds,
             const std::string& out);

/// The summary line of `voronoi --coarsen N`: the fine voxels, the factor and the copies.
void branching_summary(const char* what, const gv::grid<3>& fine, int factor, std::size_t copies, std::size_t seeds,
                       const std::string& backend, double seconds, const std::string& out);

}  // namespace gvcli

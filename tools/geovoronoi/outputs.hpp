#pragma once
// What the geovoronoi tool writes: the Voronoi outputs and the shape-function outputs (docs/cli.md).

#include "output_dir.hpp"

#include <geovoronoi.hpp>
#include <geovoronoi/shape_functions.hpp>

#include <string>

namespace gvcli {

namespace gv = geovoronoi;

/// The method's name on the command line and as the demo's folder name.
inline const char* method_name(gv::shape_method m) {
  return m == gv::shape_method::distance_ratio ? "distance-ratio" : m == gv::shape_method::sibson ? "sibson" : "laplace";
}

/// distance.mhd, label.mhd, labels.png, distance.png, voronoi.vti
void write_voronoi(const output_dir& out, const gv::diagram<float, 3>& d, const gv::image<float, 3>& field);

/// indices.mhd, weights.mhd (K planar channels, SOFA layout), weights_*.npy (CSR), weight_node<i>.png,
/// in the folder @p dir.
void write_shape(const std::string& dir, const gv::shape_weights<float, 3>& w, const gv::diagram<float, 3>& d,
                 int png_node);

/// The one summary line a command prints at the end.
void summary(const char* what, const gv::grid<3>& g, std::size_t seeds, const std::string& backend, double seconds,
             const std::string& out);

}  // namespace gvcli

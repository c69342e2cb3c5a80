#pragma once
// Branching (non-manifold) grids in the front end (docs/branching.md): `voronoi --coarsen N` of the
// tool and gv.branching_grid() / gv.voronoi(..., coarsen=N) of the Python extension. The library's
// branching grids and their solves are instantiated in one unit (branching.cpp: 3D, float and double,
// every metric and connectivity of kinds.hpp, the host backends), shared by the tool and the
// extension; everything else sees these plain arrays.

#include "kinds.hpp"

#include <geovoronoi/branching_grid.hpp>

#include <cstdint>
#include <string>
#include <vector>

namespace gvcli {

/// The reduction named @p name: mean, min, max, harmonic (or harmonic_mean); else a usage_error.
gv::stiffness_reduction parse_reduction(const std::string& name);
/// "mean", "min", "max" or "harmonic".
const char* reduction_name(gv::stiffness_reduction r) noexcept;

/// A branching grid's arrays (branching_grid's accessors, copied out of the library's object).
template <class T>
struct branching_arrays {
  gv::grid<3> coarse;
  int factor = 1;
  std::vector<gv::index_t> cell_begin, copy_cell, copy_voxel, voxel_count, link_begin, link_copy;
  std::vector<std::uint8_t> link_dir;
  std::vector<T> stiffness;
  gv::image<gv::index_t, 3> fine_copy;
  gv::index_t copies() const noexcept { return gv::index_t(copy_cell.size()); }
};

/// What selects a branching solve.
struct branching_key {
  backend_id backend = backend_id::seq;
  metric_id metric = metric_id::min_stiffness;
  int connectivity = 26;
  int factor = 1;
  gv::stiffness_reduction reduction = gv::stiffness_reduction::mean;
};

/// A branching solve: the grid's arrays, the diagram per copy (parents included) and painted on the
/// fine grid (paint_fine(); its seeds are the seeds' fine voxel indices, as a regular diagram's).
template <class T>
struct branching_solution {
  branching_arrays<T> grid;
  gv::branching_diagram<T> copies;
  gv::diagram<T, 3> fine;
};

/// make_branching_grid(fine, factor, connectivity<N>, {reduction}): std::invalid_argument from the
/// library (factor < 1, no material, ...).
template <class T>
branching_arrays<T> build_branching(gv::image_view<const T, 3> fine, int factor, int connectivity,
                                    gv::stiffness_reduction reduction);

/// The branching grid of @p fine (key.factor, key.connectivity, key.reduction) and the Voronoi diagram
/// of @p seeds (fine voxels) on it with key.metric on key.backend (seq or thrust; cuda: a usage_error,
/// the CUDA backend has no solve on branching grids). The library's std::invalid_argument for a bad
/// grid or seed, and gv::overflow_error, pass through.
template <class T>
branching_solution<T> solve_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                      const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt);

}  // namespace gvcli

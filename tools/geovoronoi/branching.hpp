#pragma once
// Branching (non-manifold) grids in the front end (docs/branching.md): `--coarsen N` of the tool's
// voronoi, shape-functions and cut, and gv.branching_grid() / gv.voronoi(..., coarsen=N) /
// gv.shape_functions(..., coarsen=N) of the Python extension. The library's branching grids are
// instantiated in two units shared by the tool and the extension (3D, float and double, every metric
// and connectivity of kinds.hpp, the host backends): branching.cpp (the grid and its diagram) and
// branching_shape.cpp (the shape functions and the cut's update); everything else sees these plain
// arrays and the library's result types.

#include "kinds.hpp"

#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/branching_shape.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/shape_functions.hpp>

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

/// What a branching run computes beyond the grid and its diagram.
struct branching_extras {
  /// Cut edges of the fine grid (cut_from_mesh on the field's grid, the run's connectivity): they split
  /// the copies of the cells they cross before anything is solved (null: no cut).
  const gv::cut_set<3>* cut = nullptr;
  /// The shape functions (method, K, threads, progress; null: none): at every copy, painted on the
  /// fine grid, or only at the fine voxels @p at when it is not null.
  const gv::shape_options* shape = nullptr;
  const std::vector<gv::coord<3>>* at = nullptr;
};

/// A branching solve: the grid's arrays, the diagram per copy (parents included) and painted on the
/// fine grid (paint_fine(); its seeds are the seeds' fine voxel indices, as a regular diagram's); with
/// branching_extras::shape, the weights per copy and painted on the fine grid (paint_fine()), or, with
/// branching_extras::at, at those fine voxels only.
template <class T>
struct branching_solution {
  branching_arrays<T> grid;
  gv::branching_diagram<T> copies;
  gv::diagram<T, 3> fine;
  bool has_weights = false, has_at = false;
  gv::copy_weights<T> weights;
  gv::shape_weights<T, 3> fine_weights;
  gv::point_weights<T> at_weights;
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
                                      const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                      const gv::cut_set<3>* cut = nullptr);

/// solve_branching() and what @p x asks for beyond it (branching_shape.cpp): the shape functions,
/// per copy and painted, or at chosen fine voxels. The library's std::invalid_argument (a bad grid,
/// seed or point) and gv::overflow_error pass through.
template <class T>
branching_solution<T> solve_branching_shapes(const branching_key& key, gv::image_view<const T, 3> fine,
                                             const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                             const branching_extras& x);

/// `cut --coarsen N`: the run without the cut (@p before), the library's incremental update of its
/// diagram (update()) and, with shape options, of its weights (update_shape_functions()) after the fine
/// cut edges (@p updated), and a full recompute on the cut grid (@p full): the times of each, the
/// copies before and after the cut, the update's statistics.
template <class T>
struct branching_cut_run {
  branching_solution<T> before, updated, full;
  double grid_seconds = 0, update_seconds = 0, recompute_seconds = 0, shape_update_seconds = 0,
         shape_recompute_seconds = 0;
  std::size_t copies_before = 0, copies_after = 0;
  gv::update_stats stats;  ///< update()'s: changed copies (cut_tree_edges), invalidated, settled
};
/// The library's update() of the diagram @p before (per copy, with parents) of @p seeds on the grid of
/// @p fine cut by @p before_cut (null: none) onto the grid cut by @p after_cut (every cut edge: those
/// before and the new ones): the diagram after, per copy and painted, bit for bit a solve on the cut
/// grid, and the update's statistics (Python's update() of a branching diagram).
template <class T>
branching_solution<T> update_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                       const std::vector<gv::coord<3>>& seeds, const gv::cut_set<3>* before_cut,
                                       const gv::cut_set<3>& after_cut, const gv::branching_diagram<T>& before,
                                       gv::update_stats& stats);

template <class T>
branching_cut_run<T> cut_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                   const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                   const gv::cut_set<3>& cut, const gv::shape_options* shape);

}  // namespace gvcli

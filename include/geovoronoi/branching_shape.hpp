#pragma once
/// @file branching_shape.hpp
/// @brief Shape functions (Distance Ratio, Sibson, Laplace) on branching grids: one row per copy,
///        rows at fine voxels and world points, the rows painted on the fine grid; branching grids
///        built with a cut of the fine image, and the incremental update of the diagram and of the
///        weights after such a cut.
///
/// The methods are the regular grids' (detail/shape/): the copies are the nodes of the searches
/// (the shared engine walks the copy graph, detail/search/topology.hpp), and what the methods read
/// of the grid becomes, on copies:
/// - a voxel's volume (Sibson): a copy's volume is its fine voxel count times the fine voxel volume,
///   the volume of the material it stands for (a sliver of a cell weighs as little as it is);
/// - a face between two voxels (Laplace's facets, Distance Ratio's frontier): a link between copies
///   of two cells that share a coarse face (a link of a face direction of the coarse stencil), with
///   the coarse face's area and the link's edge weight.
/// With factor 1 every copy is one material voxel and every link a stencil edge: the rows are the
/// regular grid's rows at those voxels, bit for bit. See docs/branching.md.
///
/// @code
/// auto bg = geovoronoi::make_branching_grid(fine, 4, geovoronoi::connectivity<26>{});
/// auto p = geovoronoi::make_problem(bg, geovoronoi::min_stiffness{});
/// auto d = geovoronoi::voronoi(geovoronoi::seq, p, seeds);
/// geovoronoi::shape_options opt;
/// opt.method = geovoronoi::shape_method::sibson;
/// auto w = geovoronoi::shape_functions(geovoronoi::seq, p, d, opt);   // one row per copy
/// auto images = geovoronoi::paint_fine(bg, w);                        // rows at the fine voxels
/// @endcode

#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/change.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/shape_functions.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <memory>
#include <vector>

namespace geovoronoi {

namespace detail::branching {
template <class T>
struct shape_state;
}  // namespace detail::branching

/**
 * @brief Shape-function weights on a branching grid: K fixed-stride slots per copy, in copy order
 *        (the copy index of branching_grid, not the searches' slots).
 *
 * Slot s of copy c lives at index c * k + s of node and weight, in shape_weights' order (filled slots
 * first, by decreasing weight, ties to the lower node; empty slots -1 and 0). A copy that no node
 * reaches has only empty slots.
 */
template <class T>
struct copy_weights {
  /// Number of copies (rows).
  index_t copies = 0;
  /// Slots per copy (K).
  int k = 0;
  /// Number of nodes (columns of to_sparse_matrix()).
  std::size_t nodes = 0;
  /// copies * k node indices (0-based), -1 for an empty slot.
  std::vector<label_t> node;
  /// copies * k weights, 0 for an empty slot.
  std::vector<T> weight;
  /// Distance Ratio with shape_options::keep_update_state: the nodes' searches, which
  /// update_shape_functions() reuses where a cut left them unchanged (opaque; null otherwise).
  std::shared_ptr<const detail::branching::shape_state<T>> update_state;

  /// @brief The weights as a copies x nodes row-major sparse matrix (rows sum to 1 where reached).
  Eigen::SparseMatrix<T, Eigen::RowMajor> to_sparse_matrix() const;
};

/**
 * @brief Shape functions of the diagram's nodes at every copy of a branching grid.
 *
 * Distance Ratio, Sibson and Laplace as on regular grids (shape_functions.hpp), on the copy graph:
 * a query copy's new cell is the copies strictly closer to it than to their node; Sibson weighs each
 * stolen copy by its material volume (voxel_count() x the fine voxel volume); Laplace's facets are
 * the links across coarse faces between the new cell and the rest, each of the coarse face's area.
 * Every backend (geovoronoi::seq, the Thrust backend on host systems) gives the same bits: the
 * searches run the shared engine on the policy's host threads, each row on its own.
 *
 * @param p   the problem @p d was solved on.
 * @param d   voronoi(policy, p, nodes): node i is d.seeds[i] (a copy), label i.
 * @param opt method, K, threads, keep_update_state (Distance Ratio); the memory and search tunings
 *            of the regular grids' query loop do not apply.
 * @throws std::invalid_argument for K out of range, a diagram of another grid, no seeds, or labels
 *         that are not node indices.
 */
template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> shape_functions(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                const node_diagram<T>& d, const shape_options& opt = {});

/**
 * @brief Shape functions at points given as fine voxels: row i is the row of the copy holding
 *        @p fine_voxels[i] (point_weights::voxel holds the fine voxel's linear index); a point in empty
 *        material gets an empty row. Bit for bit the rows of shape_functions().
 * @throws std::invalid_argument for a point outside the fine grid (naming it), and as shape_functions().
 */
template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                    const node_diagram<T>& d, const std::vector<coord<branching_problem<T, Dim, Metric, N>::dim>>& fine_voxels,
                                    const shape_options& opt = {});

/**
 * @brief shape_functions_at() at world points, each taken to its nearest fine voxel centre.
 * @throws std::invalid_argument for a point that is not finite or whose nearest fine voxel centre lies
 *         outside the fine grid, naming the point (grid::checked_nearest_voxel).
 */
template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy& policy, const branching_problem<T, Dim, Metric, N>& p,
                                    const node_diagram<T>& d, const std::vector<point<branching_problem<T, Dim, Metric, N>::dim>>& world,
                                    const shape_options& opt = {});

/**
 * @brief Values at every copy interpolated from values at the nodes.
 * @param nodal_values w.nodes x C.
 * @return w.copies x C; rows of copies without weights are 0.
 * @throws std::invalid_argument if nodal_values does not have w.nodes rows or a slot is invalid.
 */
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const copy_weights<T>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values);

/**
 * @brief The weights at the fine resolution: every material fine voxel takes its copy's row, the
 *        others empty rows (the fine images a SOFA scene reads: docs/branching.md, "SOFA layout").
 * @throws std::invalid_argument if @p w does not have one row per copy of @p bg.
 */
template <int Dim, class T, int N>
shape_weights<T, Dim> paint_fine(const branching_grid<Dim, T, N>& bg, const copy_weights<T>& w);

/**
 * @brief The branching grid of @p fine with the fine edges of @p cut removed: a cut edge joins
 *        neither two voxels of one copy nor two linked copies, so the cut splits the copies of the
 *        cells it crosses and removes the links across it. Otherwise make_branching_grid().
 * @param cut edges of the fine grid under the same connectivity (cut_set of fine's grid and
 *            connectivity<N>: cut_from_mesh, a blade sweep).
 * @throws std::invalid_argument when the cut belongs to another grid or connectivity, and as
 *         make_branching_grid().
 */
template <class T, int Dim, int N>
branching_grid<Dim, T, N> make_branching_grid(const image<T, Dim>& fine, int factor, connectivity<N> conn,
                                              const cut_set<Dim>& cut, const branching_options& opt = {});

/**
 * @brief The diagram on the grid after a cut, from the diagram before it: bit for bit
 *        voronoi(policy, after, seeds, {with_parent = true}) (copies numbered as in the grid after).
 *
 * Copies of cells the cut did not change keep their keys where their shortest-path tree is intact;
 * the subtrees hanging from the changed cells' copies are solved again by the shared engine, and keys
 * may be lowered anywhere (update.hpp's argument on the copy graph). Work: the changed cells, the
 * invalidated subtrees and the copies whose key changes, with their neighbours, plus passes over the
 * copies that compare the two grids and renumber the result.
 *
 * @param after       the problem on the grid built with the cut (make_branching_grid(..., cut)), from
 *                    the same fine image, factor and connectivity as @p before_grid.
 * @param before_grid the grid @p before was solved on.
 * @param before      voronoi() on before_grid, with parents.
 * @param seeds       the seeds given to that voronoi() (fine voxels or world points): a seed whose
 *                    copy the cut splits goes with the part holding its fine voxel.
 * @throws std::invalid_argument when @p before has no parents or belongs to another grid, the grids
 *         differ in their fine grid or factor, the seeds are not the diagram's, or a seed is invalid
 *         after the cut (the cut left its copy outside the metric's domain).
 */
template <class Policy, class T, int Dim, class Metric, int N, class Seeds>
branching_diagram<T> update(const Policy& policy, const branching_problem<T, Dim, Metric, N>& after,
                            const branching_grid<Dim, T, N>& before_grid, const branching_diagram<T>& before,
                            const Seeds& seeds, update_stats* stats = nullptr);

/**
 * @brief The weights on the grid after a cut, from the weights before it: bit for bit
 *        shape_functions(policy, after, after_diagram, opt).
 *
 * Distance Ratio with shape_options::keep_update_state (the state in @p before_weights) runs the
 * searches again only for the nodes a changed cell or a changed key can reach (docs/branching.md, "Cuts
 * and the update"), merges again the rows their supports cover and copies the others; the result keeps
 * the state for the next update when opt.keep_update_state is set. Sibson and Laplace, and Distance
 * Ratio without the state, are computed on the new diagram (shape_functions()).
 *
 * @param after_diagram update(policy, after, before_grid, before_diagram, seeds).
 * @param opt           the options @p before_weights were computed with.
 * @throws std::invalid_argument when the weights or diagrams do not belong to the grids.
 */
template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> update_shape_functions(const Policy& policy, const branching_problem<T, Dim, Metric, N>& after,
                                       const branching_grid<Dim, T, N>& before_grid,
                                       const branching_diagram<T>& before_diagram,
                                       const branching_diagram<T>& after_diagram,
                                       const copy_weights<T>& before_weights, const shape_options& opt = {});

}  // namespace geovoronoi

#include <geovoronoi/detail/branching/shape.hpp>

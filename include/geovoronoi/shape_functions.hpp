#pragma once
/// @file shape_functions.hpp
/// @brief Voronoi shape functions (Distance Ratio, Sibson, Laplace) computed on a geodesic Voronoi
///        diagram, written once for every backend: they call only the solver entry points of
///        voronoi.hpp (bounded_solve, insert_queries), so the backend policy chooses where the
///        shortest-path work runs.
///
/// Nodes are the diagram's seeds. Every voxel the diagram reaches gets at most K (node, weight)
/// pairs, weights >= 0 summing to 1; masked or unreachable voxels get none. See
/// docs/shape-functions.md for the definitions and how they differ from SOFA's.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/result.hpp>
#include <geovoronoi/voronoi.hpp>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace geovoronoi {

/// Which shape functions to compute.
enum class shape_method {
  /// SOFA's default (method 0, Faure et al. 2011): from the distance to the node and to its cell's
  /// frontier; support bounded by twice the cell's largest distance.
  distance_ratio,
  /// Discrete natural-neighbour coordinates: volume the query's new cell steals from each node.
  sibson,
  /// Non-Sibsonian coordinates: facet area between the new cell and each node's cell over the
  /// geodesic length of a path from the query through that facet to the node.
  laplace
};

/// The largest shape_options::max_nodes_per_voxel (K) accepted. Every voxel gets K slots, so K sets
/// the output's size (voxels x K x 8 bytes or more); SOFA uses 4 to 8.
inline constexpr int max_nodes_per_voxel_limit = 1024;

/// What a shape_functions() call did, filled when shape_options::stats points to one.
struct shape_stats {
  /// Worker scratches the Sibson/Laplace query loop created (at most the backend's threads, fewer
  /// when the memory budget allows fewer).
  std::size_t workers = 0;
  /// Largest total bytes held at once by the query loop's scratch: on host backends the workers'
  /// key arrays, cell lists and queues; on others the batch of materialised cells.
  std::size_t peak_scratch_bytes = 0;
  /// Voxels the queries' searches settled (the sum of the new cells' sizes).
  std::size_t voxels_visited = 0;
  /// Queries searched (voxels with d > 0 whose weights come from a new cell).
  std::size_t queries = 0;
  /// Sibson: rows written as 1 for their own node without a search (shape_options::skip_single_owner_rows).
  std::size_t single_owner_rows = 0;
  /// Sibson: of those, the rows decided by a search on restricted bounds (the short search of
  /// search_tuning::single_owner_pops did not decide them).
  std::size_t single_owner_restricted = 0;
};

/**
 * @brief How the Sibson and Laplace searches run on host backends. Every choice gives the same weights
 *        bit for bit; the defaults are the fast ones, the others exist for comparisons and tests.
 */
struct search_tuning {
  /// Queries per lane search (float problems with a built-in metric on x86-64 hosts): 16 or 32; 0
  /// lets the query loop choose (32 where the memory budget holds as many such workers as it would run
  /// with 16).
  int lanes = 0;
  /// Whether the lane search may use AVX-512 where the CPU has it (else SSE2).
  bool avx512 = true;
  /// Sibson's single-owner rows: the most voxels the short search of one query pops before the query
  /// is decided by a search on restricted bounds (0 sends every query there).
  std::size_t single_owner_pops = 256;
};

/// Options of shape_functions().
struct shape_options {
  /// The method.
  shape_method method = shape_method::sibson;
  /// K (SOFA's nbRef): the most nodes one voxel keeps; the smallest weights are dropped, then the
  /// kept ones are renormalised. Must be between 1 and max_nodes_per_voxel_limit (1024).
  int max_nodes_per_voxel = 4;
  /// Queries per progress report and cancellation check (Sibson, Laplace), and per backend call on
  /// backends without fused host queries (there memory grows with it). Must be >= 1.
  std::size_t batch_size = 4096;
  /// Bytes the Sibson/Laplace query loop may hold in scratch at once. On host backends (seq, Thrust
  /// on host systems) each worker is budgeted about 24 bytes per voxel of the grid (float); fewer
  /// workers run when the budget does not allow one per thread, and a budget below one worker throws
  /// std::invalid_argument. On other backends it caps the queries per batch from the cell sizes
  /// seen so far.
  std::size_t memory_budget = std::size_t(1) << 30;
  /// Sibson/Laplace on host backends: fill the part of a query's new cell that lies in an exact ball of
  /// its constant-field region from a distance table instead of searching it (piecewise.hpp). The
  /// weights are bitwise the same either way; false is for comparisons.
  bool reuse_constant_regions = true;
  /// Sibson: write the row of a query whose new cell provably steals from its own node only (1 for that
  /// node) without searching it. One budget search inward from the cells' frontiers finds them
  /// (detail/shape/single_owner.hpp); it runs when the queries are at least 1/64 of the grid. The
  /// weights are bitwise the same either way; false is for comparisons.
  bool skip_single_owner_rows = true;
  /// How the searches run (comparisons and tests; the weights do not depend on it).
  search_tuning tuning;
  /// Optional: filled with statistics of the call (see shape_stats).
  shape_stats* stats = nullptr;
  /// Optional progress callback, called on the calling thread with the fraction done in [0, 1]: between
  /// backend calls, or (Sibson and Laplace on host backends) after one of that thread's tasks once
  /// batch_size queries have completed since the previous report. Returning false cancels the
  /// computation, which then throws geovoronoi::cancelled.
  std::function<bool(double)> progress;
  /// Host threads of the host-parallel backends (Thrust on OpenMP or TBB; their per-query and
  /// per-node loops and solves); 0: the system's default. The weights do not depend on it.
  unsigned threads = 0;
  /// Distance Ratio on the whole grid: keep every node's searches (its own distance over its support
  /// and its frontier distance) in the weights (shape_weights::update_state), so that
  /// update_shape_functions() repairs them around a change instead of running every affected node's
  /// searches again. Costs 12 bytes per voxel of a node's support (the ball d_i < 2 d_max) and of its
  /// frontier region (d_B < d_max), per node (docs/shape-functions.md gives the steak phantom's
  /// figure). Sibson and Laplace ignore it.
  bool keep_update_state = false;
};

namespace detail::shape {
template <class T>
struct distance_ratio_state;
}  // namespace detail::shape

/**
 * @brief Shape-function weights on a grid, K fixed-stride slots per voxel.
 *
 * Slot s of voxel v lives at index v * k + s of node and weight. Filled slots come first, sorted by
 * decreasing weight (ties: lower node first); empty slots have node -1 and weight 0. A voxel outside
 * the domain, or that no node reaches, has only empty slots.
 *
 * @tparam T   weight type (the problem's distance type).
 * @tparam Dim 2 or 3.
 */
template <class T, int Dim>
struct shape_weights {
  /// The grid the weights live on.
  grid<Dim> geometry;
  /// Slots per voxel (K).
  int k = 0;
  /// Number of nodes (columns of to_sparse_matrix()).
  std::size_t nodes = 0;
  /// geometry.size() * k node indices (0-based), -1 for an empty slot.
  std::vector<label_t> node;
  /// geometry.size() * k weights, 0 for an empty slot.
  std::vector<T> weight;
  /// Distance Ratio computed with shape_options::keep_update_state: the nodes' searches, which
  /// update_shape_functions() repairs and renews (opaque; null otherwise, and after an update that
  /// could not use it). Copies of the weights share it; it is never modified, only replaced.
  std::shared_ptr<const detail::shape::distance_ratio_state<T>> update_state;

  /// @brief The weights as a voxels x nodes row-major sparse matrix in the weight type T (one row per
  ///        voxel, empty rows outside the domain); rows sum to 1 inside the domain.
  Eigen::SparseMatrix<T, Eigen::RowMajor> to_sparse_matrix() const;
};

/**
 * @brief Shape-function weights at chosen points (shape_functions_at()), K fixed-stride slots per
 *        point, in the same layout as shape_weights: slot s of point i at index i * k + s.
 */
template <class T>
struct point_weights {
  /// Number of points (rows of to_sparse_matrix()).
  std::size_t points = 0;
  /// Slots per point (K).
  int k = 0;
  /// Number of nodes (columns of to_sparse_matrix()).
  std::size_t nodes = 0;
  /// The voxel (linear index) each point was evaluated at.
  std::vector<index_t> voxel;
  /// points * k node indices (0-based), -1 for an empty slot.
  std::vector<label_t> node;
  /// points * k weights, 0 for an empty slot.
  std::vector<T> weight;

  /// @brief The weights as a points x nodes row-major sparse matrix in T (an empty row for a point on a
  ///        masked or unreachable voxel).
  Eigen::SparseMatrix<T, Eigen::RowMajor> to_sparse_matrix() const;
};

/**
 * @brief Shape functions of the diagram's seeds (the nodes) at every voxel.
 *
 * @param policy  backend, e.g. geovoronoi::seq or geovoronoi::thrust::par.
 * @param problem the problem @p d was computed on.
 * @param d       a diagram of the nodes (geovoronoi::voronoi()); node i is d.seeds[i], label i.
 * @param opt     method, K, batch size, progress callback.
 * @return the weights; bitwise identical for every backend (they return identical diagrams and
 *         query cells, and the accumulation is written once).
 * @throws std::invalid_argument if K < 1 or K > max_nodes_per_voxel_limit, batch_size is 0, d has no seeds, d was computed on another
 *         grid, or d holds a label that is not a node index.
 * @throws geovoronoi::cancelled when the progress callback returns false.
 *
 * @code
 * auto p = geovoronoi::make_problem(g, stiffness, geovoronoi::min_stiffness{}, geovoronoi::connectivity<26>{});
 * auto d = geovoronoi::voronoi(geovoronoi::seq, p, nodes);
 * geovoronoi::shape_options opt;
 * opt.method = geovoronoi::shape_method::laplace;
 * auto w = geovoronoi::shape_functions(geovoronoi::seq, p, d, opt);
 * Eigen::MatrixXf u = geovoronoi::interpolate(w, nodal_displacements);  // voxels x 3
 * @endcode
 */
template <class Policy, class P>
shape_weights<typename P::value_type, P::dim> shape_functions(const Policy& policy, const P& problem,
                                                              const diagram<typename P::value_type, P::dim>& d,
                                                              const shape_options& opt = {});

/**
 * @brief Shape functions of the diagram's nodes at chosen voxels only.
 *
 * Row i holds exactly (bit for bit) the slots that shape_functions() computes at voxel @p points[i]:
 * Sibson and Laplace run only those points' queries; Distance Ratio runs its per-node solves (they
 * are needed for any point in a node's support) and keeps the points' rows. A point on a masked or
 * unreachable voxel gets an empty row; a point may appear several times.
 *
 * @param points voxel coordinates.
 * @throws std::invalid_argument for a point outside the grid, and as shape_functions().
 */
template <class Policy, class P>
point_weights<typename P::value_type> shape_functions_at(const Policy& policy, const P& problem,
                                                         const diagram<typename P::value_type, P::dim>& d,
                                                         const std::vector<coord<P::dim>>& points,
                                                         const shape_options& opt = {});

/**
 * @brief shape_functions_at() at world points, each rounded to the nearest voxel centre (as
 *        seeds_from_world: grid::nearest_voxel, floor(x + 0.5) per axis, so halves round up).
 * @throws std::invalid_argument for a point that is not finite or whose nearest voxel centre lies
 *         outside the grid, naming the point as given (grid::checked_nearest_voxel).
 */
template <class Policy, class P>
point_weights<typename P::value_type> shape_functions_at(const Policy& policy, const P& problem,
                                                         const diagram<typename P::value_type, P::dim>& d,
                                                         const std::vector<point<P::dim>>& world_points,
                                                         const shape_options& opt = {});

/**
 * @brief Values at every voxel interpolated from values at the nodes: row v = sum over the slots of
 *        voxel v of weight * nodal_values.row(node).
 *
 * @param w            shape functions.
 * @param nodal_values w.nodes x C matrix (e.g. an Eigen::MatrixX3f of nodal displacements).
 * @return geometry.size() x C matrix; rows of voxels without weights are 0.
 * @throws std::invalid_argument if nodal_values does not have w.nodes rows, or a slot names a node
 *         outside [0, w.nodes) (or the same node twice in one row); to_sparse_matrix() checks the same.
 */
template <class T, int Dim, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const shape_weights<T, Dim>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values);

}  // namespace geovoronoi

#include <geovoronoi/detail/shape/shape_functions.hpp>

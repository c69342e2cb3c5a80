#pragma once
/// @file result.hpp
/// @brief What the solvers return: the dense diagram, sparse (bounded) solutions and query cells.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>

#include <algorithm>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace geovoronoi {

/**
 * @brief A point source for the general solver: a voxel, its initial distance and the label it spreads.
 *
 * geovoronoi::voronoi() makes one per seed with distance 0 and label = the seed's position.
 */
template <class T>
struct source {
  index_t voxel;
  T distance;
  label_t label;
};

/// Options of the dense solvers.
struct solve_options {
  /// Also compute the parent (predecessor) image.
  bool with_parent = false;
  /// Radius bound: voxels whose distance is not < max_distance (compared in the distance type T)
  /// are reported as unreached (+inf, label -1) and the search stops there.
  double max_distance = std::numeric_limits<double>::infinity();
  /// Optional progress callback: called with the fraction done in [0, 1], non-decreasing, at the
  /// start, every few thousand settled voxels (seq) or expansion rounds (Thrust), and with 1 at the
  /// end; returning false stops the solve, which then throws geovoronoi::cancelled (nothing of it
  /// is kept; the problem, the field and the policy's workspace stay valid for the next call). The
  /// CUDA backend reports only 0 and 1 (it cannot stop a running solve). Called on the calling thread.
  std::function<bool(double)> progress = nullptr;
  /// Host threads of the host-parallel backends (Thrust on OpenMP or TBB); 0: the system's default
  /// (OMP_NUM_THREADS, TBB's default). Results do not depend on it. Ignored by seq and CUDA.
  unsigned threads = 0;
};

namespace detail {
/// What a backend needs of solve_options besides the radius: the progress callback and the thread
/// count (dispatch.hpp passes it to the backends that take it).
struct solve_control {
  const std::function<bool(double)>* progress = nullptr;
  unsigned threads = 0;

  static solve_control of(const solve_options& o) noexcept { return {o.progress ? &o.progress : nullptr, o.threads}; }
  bool reporting() const noexcept { return progress != nullptr && bool(*progress); }
  /// Reports @p fraction (clamped to [0, 1]); throws geovoronoi::cancelled when asked to stop.
  void report(double fraction) const {
    if (reporting() && !(*progress)(std::min(1.0, std::max(0.0, fraction)))) throw cancelled();
  }
};
}  // namespace detail

namespace detail {
/// solve_options::max_distance converted to T without overflowing: beyond T's range it is +inf.
template <class T>
T radius_in(double r) noexcept {
  if (!(r < double(std::numeric_limits<T>::max()))) return r > 0 ? std::numeric_limits<T>::infinity() : T(r);
  if (r < -double(std::numeric_limits<T>::max())) return -std::numeric_limits<T>::infinity();
  return static_cast<T>(r);
}
}  // namespace detail

/**
 * @brief A geodesic Voronoi diagram: per-voxel distance to the nearest seed and that seed's label.
 *
 * distance is +inf and label is -1 where the voxel is masked or unreachable. When requested, parent
 * holds, for every reached voxel that is not a source, the lowest linear index among the neighbours
 * u that realise its key (fl(d(u) + w(u,v)) == d(v) and label(u) == label(v)); -1 elsewhere. It is
 * empty when not requested.
 */
template <class T, int Dim>
struct diagram {
  image<T, Dim> distance;
  image<label_t, Dim> label;
  image<index_t, Dim> parent;
  /// Linear voxel index of each seed, in the caller's order.
  std::vector<index_t> seeds;

  const grid<Dim>& geometry() const noexcept { return distance.geometry(); }
};

/**
 * @brief A geodesic Voronoi diagram over the nodes of an explicit graph (a branching grid's copies,
 *        branching_grid.hpp): one entry per node, the same rules as diagram.
 *
 * distance is +inf and label -1 where a node is unreachable; parent (when requested, else empty)
 * holds the lowest-index neighbour node that realises the node's key, -1 for sources and unreached
 * nodes; seeds holds each seed's node, in the caller's order.
 */
template <class T>
struct node_diagram {
  std::vector<T> distance;
  std::vector<label_t> label;
  std::vector<index_t> parent;
  std::vector<index_t> seeds;

  /// Number of nodes.
  std::size_t size() const noexcept { return distance.size(); }
};

/**
 * @brief The result of a bounded (sparse) solve: the voxels whose distance is below the radius, with
 *        their distance and label, sorted by increasing voxel index.
 */
template <class T>
struct sparse_solution {
  std::vector<index_t> voxel;
  std::vector<T> distance;
  std::vector<label_t> label;
  std::size_t size() const noexcept { return voxel.size(); }
};

/**
 * @brief New cells of query seeds inserted, one at a time, into a finished diagram (which is not
 *        modified), in compressed-row form.
 *
 * Cell i spans entries [offsets[i], offsets[i+1]): each is a voxel v with d_q(v) < d(v) (strict), the
 * geodesic distance d_q(v) from the query, and owner = the label v had in the diagram. Entries of a
 * cell are sorted by increasing voxel index. A query placed on a seed has an empty cell.
 */
template <class T>
struct query_cells {
  std::vector<index_t> query;            ///< the query voxels, in the caller's order
  std::vector<std::size_t> offsets{0};   ///< size() + 1 entries
  std::vector<index_t> voxel;
  std::vector<T> distance;
  std::vector<label_t> owner;

  /// Number of queries.
  std::size_t size() const noexcept { return query.size(); }
  /// Number of voxels in cell @p i.
  std::size_t cell_size(std::size_t i) const noexcept { return offsets[i + 1] - offsets[i]; }

  /// Append the entries of another batch (used by backends that work in chunks).
  void append(const query_cells& other) {
    const std::size_t base = voxel.size();
    query.insert(query.end(), other.query.begin(), other.query.end());
    for (std::size_t i = 1; i < other.offsets.size(); ++i) offsets.push_back(base + other.offsets[i]);
    voxel.insert(voxel.end(), other.voxel.begin(), other.voxel.end());
    distance.insert(distance.end(), other.distance.begin(), other.distance.end());
    owner.insert(owner.end(), other.owner.begin(), other.owner.end());
  }
};

/// The new cell of one query (the single-query form of query_cells).
template <class T>
struct query_cell {
  index_t query = no_index;
  std::vector<index_t> voxel;
  std::vector<T> distance;
  std::vector<label_t> owner;
  std::size_t size() const noexcept { return voxel.size(); }
};

}  // namespace geovoronoi

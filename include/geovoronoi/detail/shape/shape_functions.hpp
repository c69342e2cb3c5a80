#pragma once
// Bodies of geovoronoi/shape_functions.hpp.

#include <geovoronoi/detail/parallel.hpp>
#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/distance_ratio.hpp>
#include <geovoronoi/detail/shape/natural_neighbours.hpp>
#include <geovoronoi/policy.hpp>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

namespace detail::shape {
/// Every filled slot must name a node in [0, nodes), at most once per row: anything else would index
/// past the nodal values (interpolate) or build an invalid sparse matrix (to_sparse_matrix).
inline void check_slots(const std::vector<label_t>& node, int k, std::size_t nodes, const char* who) {
  if (k <= 0) return;
  const std::size_t ks = std::size_t(k);
  for (std::size_t at = 0; at < node.size(); ++at) {
    const label_t n = node[at];
    if (n == no_label) continue;
    if (n < 0 || std::size_t(n) >= nodes)
      throw std::invalid_argument(std::string(who) + ": row " + std::to_string(at / ks) + ", slot " +
                                  std::to_string(at % ks) + " names node " + std::to_string(n) + ", but there are " +
                                  std::to_string(nodes) + " nodes (valid: 0 to " + std::to_string(nodes) +
                                  " - 1, or -1 for an empty slot)");
    for (std::size_t b = at - at % ks; b < at; ++b)
      if (node[b] == n)
        throw std::invalid_argument(std::string(who) + ": row " + std::to_string(at / ks) + " names node " +
                                    std::to_string(n) + " in slots " + std::to_string(b % ks) + " and " +
                                    std::to_string(at % ks));
  }
}

/// Each world point (@p world: a std::vector<point<Dim>>) to its nearest voxel of @p geometry
/// (grid::checked_nearest_voxel); a point outside is an std::invalid_argument naming it
/// (shape_functions_at's message).
template <int Dim, class Points>
std::vector<coord<Dim>> nearest_voxels(const grid<Dim>& geometry, const Points& world) {
  std::vector<coord<Dim>> c;
  c.reserve(world.size());
  for (std::size_t i = 0; i < world.size(); ++i) {
    try {
      c.push_back(geometry.checked_nearest_voxel(world[i]));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("geovoronoi::shape_functions_at: point " + std::to_string(i) + ": " + e.what());
    }
  }
  return c;
}

/// The rows (K slots each) times the nodes' values: interpolate() of every weights type. @p rows_name
/// names the row count in the message of a size mismatch.
template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate_rows(const std::vector<label_t>& node,
                                                                  const std::vector<T>& weight, int k,
                                                                  std::size_t nodes, index_t rows,
                                                                  const char* rows_name,
                                                                  const Eigen::MatrixBase<Derived>& nodal_values) {
  if (nodal_values.rows() < 0 || std::size_t(nodal_values.rows()) != nodes)
    throw std::invalid_argument("geovoronoi::interpolate: nodal_values has " + std::to_string(nodal_values.rows()) +
                                " rows but there are " + std::to_string(nodes) + " nodes");
  if (node.size() != std::size_t(rows) * std::size_t(k) || weight.size() != node.size())
    throw std::invalid_argument(std::string("geovoronoi::interpolate: node/weight arrays do not hold ") + rows_name +
                                " * k entries");
  check_slots(node, k, nodes, "geovoronoi::interpolate");
  const Eigen::Index cols = nodal_values.cols();
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out =
      Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Zero(Eigen::Index(rows), cols);
  for (index_t v = 0; v < rows; ++v)
    for (int s = 0; s < k; ++s) {
      const std::size_t at = std::size_t(v) * std::size_t(k) + std::size_t(s);
      const label_t n = node[at];
      if (n == no_label) continue;
      for (Eigen::Index c = 0; c < cols; ++c)
        out(Eigen::Index(v), c) += weight[at] * static_cast<T>(nodal_values(Eigen::Index(n), c));
    }
  return out;
}

/// Slots (rows x k, -1 empty) as a rows x nodes row-major sparse matrix in T.
template <class T>
Eigen::SparseMatrix<T, Eigen::RowMajor> slots_to_sparse(std::size_t rows, int k, std::size_t nodes,
                                                        const std::vector<label_t>& node, const std::vector<T>& weight,
                                                        const char* who) {
  using index = typename Eigen::SparseMatrix<T, Eigen::RowMajor>::StorageIndex;
  if (rows > std::size_t(std::numeric_limits<index>::max()) || nodes > std::size_t(std::numeric_limits<index>::max()))
    throw std::invalid_argument(std::string(who) + ": too many rows for Eigen's 32-bit sparse indices");
  if (k < 0 || node.size() != rows * std::size_t(k) || weight.size() != node.size())
    throw std::invalid_argument(std::string(who) + ": node/weight arrays do not hold rows * k entries");
  check_slots(node, k, nodes, who);
  Eigen::SparseMatrix<T, Eigen::RowMajor> m(static_cast<index>(rows), static_cast<index>(nodes));
  // no rows (an empty list of points): already compressed; Eigen's reserve/makeCompressed read
  // outer index 1, which a 0-row matrix does not have
  if (rows == 0) return m;
  Eigen::Matrix<index, Eigen::Dynamic, 1> per_row(static_cast<index>(rows));
  for (std::size_t v = 0; v < rows; ++v) {
    index c = 0;
    for (int s = 0; s < k; ++s) c += node[v * std::size_t(k) + std::size_t(s)] != no_label;
    per_row[static_cast<index>(v)] = c;
  }
  m.reserve(per_row);
  for (std::size_t v = 0; v < rows; ++v)
    for (int s = 0; s < k; ++s) {
      const std::size_t at = v * std::size_t(k) + std::size_t(s);
      if (node[at] != no_label) m.insert(static_cast<index>(v), static_cast<index>(node[at])) = weight[at];
    }
  m.makeCompressed();
  return m;
}
}  // namespace detail::shape

template <class T, int Dim>
Eigen::SparseMatrix<T, Eigen::RowMajor> shape_weights<T, Dim>::to_sparse_matrix() const {
  return detail::shape::slots_to_sparse(std::size_t(geometry.size()), k, nodes, node, weight,
                                        "geovoronoi::shape_weights::to_sparse_matrix");
}

template <class T>
Eigen::SparseMatrix<T, Eigen::RowMajor> point_weights<T>::to_sparse_matrix() const {
  return detail::shape::slots_to_sparse(points, k, nodes, node, weight, "geovoronoi::point_weights::to_sparse_matrix");
}

template <class Policy, class P>
shape_weights<typename P::value_type, P::dim> shape_functions(const Policy& policy, const P& problem,
                                                              const diagram<typename P::value_type, P::dim>& d,
                                                              const shape_options& opt) {
  using T = typename P::value_type;
  detail::require_policy<Policy>();
  detail::shape::validate(problem, d, opt);
  shape_weights<T, P::dim> w;
  w.geometry = problem.geometry;
  w.k = opt.max_nodes_per_voxel;
  w.nodes = d.seeds.size();
  const std::size_t slots = std::size_t(problem.geometry.size()) * std::size_t(w.k);
  w.node.assign(slots, no_label);
  w.weight.assign(slots, T(0));
  detail::with_threads(policy, opt.threads, [&] {
    switch (opt.method) {
      case shape_method::distance_ratio:
        detail::shape::distance_ratio(policy, problem, d, opt, w);
        break;
      case shape_method::sibson:
        detail::shape::natural_neighbours(policy, problem, d, opt, false, w);
        break;
      case shape_method::laplace:
        detail::shape::natural_neighbours(policy, problem, d, opt, true, w);
        break;
      default:
        throw std::invalid_argument("geovoronoi::shape_functions: unknown shape_method " +
                                    std::to_string(static_cast<int>(opt.method)));
    }
    return 0;
  });
  return w;
}

template <class Policy, class P>
point_weights<typename P::value_type> shape_functions_at(const Policy& policy, const P& problem,
                                                         const diagram<typename P::value_type, P::dim>& d,
                                                         const std::vector<coord<P::dim>>& points,
                                                         const shape_options& opt) {
  using T = typename P::value_type;
  detail::require_policy<Policy>();
  detail::shape::validate(problem, d, opt);
  point_weights<T> w;
  w.points = points.size();
  w.k = opt.max_nodes_per_voxel;
  w.nodes = d.seeds.size();
  w.voxel.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (!problem.geometry.contains(points[i])) {
      std::string c;
      for (int a = 0; a < P::dim; ++a) c += (a ? ", " : "") + std::to_string(points[i][std::size_t(a)]);
      throw std::invalid_argument("geovoronoi::shape_functions_at: point " + std::to_string(i) + " (" + c +
                                  ") lies outside the grid");
    }
    w.voxel.push_back(problem.geometry.index(points[i]));
  }
  const std::size_t slots = points.size() * std::size_t(w.k);
  w.node.assign(slots, no_label);
  w.weight.assign(slots, T(0));
  switch (opt.method) {
    case shape_method::distance_ratio:
      if (points.empty()) break;  // (an empty vector's data() may be null, which means the whole grid)
      // the per-node solves as for the whole grid (each point's row equals its full row), raw weights
      // kept at the points only, nodes whose support holds no point skipped
      detail::with_threads(policy, opt.threads, [&] {
        detail::shape::distance_ratio_rows(policy, problem, d, opt, w.k, w.nodes, w.voxel.data(), points.size(),
                                           w.node.data(), w.weight.data());
        return 0;
      });
      break;
    case shape_method::sibson:
    case shape_method::laplace:
      detail::with_threads(policy, opt.threads, [&] {
        detail::shape::natural_neighbour_rows(policy, problem, d, opt, opt.method == shape_method::laplace,
                                              w.voxel.data(), points.size(), w.k, w.nodes, w.node.data(),
                                              w.weight.data());
        return 0;
      });
      break;
    default:
      throw std::invalid_argument("geovoronoi::shape_functions_at: unknown shape_method " +
                                  std::to_string(static_cast<int>(opt.method)));
  }
  return w;
}

template <class Policy, class P>
point_weights<typename P::value_type> shape_functions_at(const Policy& policy, const P& problem,
                                                         const diagram<typename P::value_type, P::dim>& d,
                                                         const std::vector<point<P::dim>>& world_points,
                                                         const shape_options& opt) {
  detail::require_policy<Policy>();
  return shape_functions_at(policy, problem, d, detail::shape::nearest_voxels(problem.geometry, world_points), opt);
}

template <class T, int Dim, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const shape_weights<T, Dim>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values) {
  return detail::shape::interpolate_rows(w.node, w.weight, w.k, w.nodes, w.geometry.size(), "geometry.size()",
                                         nodal_values);
}

}  // namespace geovoronoi

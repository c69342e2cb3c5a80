#pragma once
// Bodies of geovoronoi/shape_functions.hpp.

#include <geovoronoi/detail/shape/common.hpp>
#include <geovoronoi/detail/shape/distance_ratio.hpp>
#include <geovoronoi/detail/shape/natural_neighbours.hpp>

#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

template <class T, int Dim>
Eigen::SparseMatrix<float, Eigen::RowMajor> shape_weights<T, Dim>::to_sparse_matrix() const {
  using index = typename Eigen::SparseMatrix<float, Eigen::RowMajor>::StorageIndex;
  const index_t rows = geometry.size();
  if (rows > index_t(std::numeric_limits<index>::max()) || nodes > std::size_t(std::numeric_limits<index>::max()))
    throw std::invalid_argument("geovoronoi::shape_weights::to_sparse_matrix: the grid has too many voxels for "
                                "Eigen's 32-bit sparse indices");
  if (node.size() != std::size_t(rows) * std::size_t(k) || weight.size() != node.size())
    throw std::invalid_argument("geovoronoi::shape_weights::to_sparse_matrix: node/weight arrays do not hold "
                                "geometry.size() * k entries");
  Eigen::SparseMatrix<float, Eigen::RowMajor> m(static_cast<index>(rows), static_cast<index>(nodes));
  Eigen::Matrix<index, Eigen::Dynamic, 1> per_row(static_cast<index>(rows));
  for (index_t v = 0; v < rows; ++v) {
    index c = 0;
    for (int s = 0; s < k; ++s) c += node[std::size_t(v) * std::size_t(k) + std::size_t(s)] != no_label;
    per_row[static_cast<index>(v)] = c;
  }
  m.reserve(per_row);
  for (index_t v = 0; v < rows; ++v)
    for (int s = 0; s < k; ++s) {
      const std::size_t at = std::size_t(v) * std::size_t(k) + std::size_t(s);
      if (node[at] != no_label) m.insert(static_cast<index>(v), static_cast<index>(node[at])) = float(weight[at]);
    }
  m.makeCompressed();
  return m;
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
  return w;
}

template <class T, int Dim, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const shape_weights<T, Dim>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values) {
  if (nodal_values.rows() < 0 || std::size_t(nodal_values.rows()) != w.nodes)
    throw std::invalid_argument("geovoronoi::interpolate: nodal_values has " + std::to_string(nodal_values.rows()) +
                                " rows but there are " + std::to_string(w.nodes) + " nodes");
  const index_t rows = w.geometry.size();
  if (w.node.size() != std::size_t(rows) * std::size_t(w.k) || w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::interpolate: node/weight arrays do not hold geometry.size() * k entries");
  const Eigen::Index cols = nodal_values.cols();
  Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> out =
      Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>::Zero(Eigen::Index(rows), cols);
  for (index_t v = 0; v < rows; ++v)
    for (int s = 0; s < w.k; ++s) {
      const std::size_t at = std::size_t(v) * std::size_t(w.k) + std::size_t(s);
      const label_t n = w.node[at];
      if (n == no_label) continue;
      for (Eigen::Index c = 0; c < cols; ++c)
        out(Eigen::Index(v), c) += w.weight[at] * static_cast<T>(nodal_values(Eigen::Index(n), c));
    }
  return out;
}

}  // namespace geovoronoi

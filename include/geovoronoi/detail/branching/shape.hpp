#pragma once
// Bodies of geovoronoi/branching_shape.hpp.

#include <geovoronoi/branching_grid.hpp>
#include <geovoronoi/detail/shape/shape_functions.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi {

namespace detail::branching {
template <class T>
struct shape_state {};
}  // namespace detail::branching

template <class T>
Eigen::SparseMatrix<T, Eigen::RowMajor> copy_weights<T>::to_sparse_matrix() const {
  return detail::shape::slots_to_sparse(std::size_t(copies), k, nodes, node, weight,
                                        "geovoronoi::copy_weights::to_sparse_matrix");
}

template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> shape_functions(const Policy&, const branching_problem<T, Dim, Metric, N>&, const node_diagram<T>&,
                                const shape_options&) {
  throw std::logic_error("geovoronoi::shape_functions on branching grids: not yet");
}

template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy&, const branching_problem<T, Dim, Metric, N>&, const node_diagram<T>&,
                                    const std::vector<coord<branching_problem<T, Dim, Metric, N>::dim>>&, const shape_options&) {
  throw std::logic_error("geovoronoi::shape_functions_at on branching grids: not yet");
}

template <class Policy, class T, int Dim, class Metric, int N>
point_weights<T> shape_functions_at(const Policy&, const branching_problem<T, Dim, Metric, N>&, const node_diagram<T>&,
                                    const std::vector<point<branching_problem<T, Dim, Metric, N>::dim>>&, const shape_options&) {
  throw std::logic_error("geovoronoi::shape_functions_at on branching grids: not yet");
}

template <class T, class Derived>
Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic> interpolate(const copy_weights<T>& w,
                                                             const Eigen::MatrixBase<Derived>& nodal_values) {
  if (nodal_values.rows() < 0 || std::size_t(nodal_values.rows()) != w.nodes)
    throw std::invalid_argument("geovoronoi::interpolate: nodal_values has " + std::to_string(nodal_values.rows()) +
                                " rows but there are " + std::to_string(w.nodes) + " nodes");
  const index_t rows = w.copies;
  if (w.node.size() != std::size_t(rows) * std::size_t(w.k) || w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::interpolate: node/weight arrays do not hold copies * k entries");
  detail::shape::check_slots(w.node, w.k, w.nodes, "geovoronoi::interpolate");
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

template <int Dim, class T, int N>
shape_weights<T, Dim> paint_fine(const branching_grid<Dim, T, N>& bg, const copy_weights<T>& w) {
  if (w.copies != bg.copies() || w.k < 0 || w.node.size() != std::size_t(w.copies) * std::size_t(w.k) ||
      w.weight.size() != w.node.size())
    throw std::invalid_argument("geovoronoi::paint_fine: the weights have " + std::to_string(w.copies) +
                                " rows but the branching grid has " + std::to_string(bg.copies()) + " copies");
  shape_weights<T, Dim> out;
  out.geometry = bg.fine();
  out.k = w.k;
  out.nodes = w.nodes;
  const std::size_t k = std::size_t(w.k);
  out.node.assign(std::size_t(bg.fine().size()) * k, no_label);
  out.weight.assign(out.node.size(), T(0));
  const index_t* fc = bg.fine_copy().data();
  for (index_t v = 0; v < bg.fine().size(); ++v)
    if (fc[v] >= 0)
      for (std::size_t s = 0; s < k; ++s) {
        out.node[std::size_t(v) * k + s] = w.node[std::size_t(fc[v]) * k + s];
        out.weight[std::size_t(v) * k + s] = w.weight[std::size_t(fc[v]) * k + s];
      }
  return out;
}

template <class T, int Dim, int N>
branching_grid<Dim, T, N> make_branching_grid(const image<T, Dim>&, int, connectivity<N>, const cut_set<Dim>&,
                                              const branching_options&) {
  throw std::logic_error("geovoronoi::make_branching_grid with a cut: not yet");
}

template <class Policy, class T, int Dim, class Metric, int N, class Seeds>
branching_diagram<T> update(const Policy&, const branching_problem<T, Dim, Metric, N>&, const branching_grid<Dim, T, N>&,
                            const branching_diagram<T>&, const Seeds&, update_stats*) {
  throw std::logic_error("geovoronoi::update on branching grids: not yet");
}

template <class Policy, class T, int Dim, class Metric, int N>
copy_weights<T> update_shape_functions(const Policy&, const branching_problem<T, Dim, Metric, N>&,
                                       const branching_grid<Dim, T, N>&, const branching_diagram<T>&,
                                       const branching_diagram<T>&, const copy_weights<T>&, const shape_options&) {
  throw std::logic_error("geovoronoi::update_shape_functions on branching grids: not yet");
}

}  // namespace geovoronoi

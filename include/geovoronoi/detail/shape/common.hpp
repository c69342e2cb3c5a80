#pragma once
// Pieces shared by the three shape-function methods: argument checks, the per-voxel top-K selection
// and normalisation, the face (6-neighbour) table, progress reporting.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi::detail::shape {

/// A node and its raw (unnormalised, > 0) weight at one voxel.
struct candidate {
  label_t node;
  double raw;
};

/// Slot order: larger weight first, ties to the lower node.
inline bool heavier(const candidate& a, const candidate& b) noexcept {
  return a.raw > b.raw || (a.raw == b.raw && a.node < b.node);
}

/**
 * Keeps the K heaviest candidates (dropping the smallest weights, not the highest node indices as
 * SOFA does), renormalises them to sum 1 and writes them to the voxel's K slots. The sum is taken in
 * slot order in double; each weight is raw / sum rounded once to T. The slots are finally re-ordered
 * on the rounded weights so the published order holds for the stored values too.
 */
template <class T>
void store(std::vector<candidate>& c, int k, label_t* node, T* weight) {
  std::sort(c.begin(), c.end(), heavier);
  const std::size_t m = std::min(c.size(), std::size_t(k));
  double sum = 0;
  for (std::size_t s = 0; s < m; ++s) sum += c[s].raw;
  if (!(sum > 0)) return;
  for (std::size_t s = 0; s < m; ++s) {
    node[s] = c[s].node;
    weight[s] = static_cast<T>(c[s].raw / sum);
  }
  // rounding to T can only create ties, never invert the order; restore "ties: lower node first"
  for (std::size_t s = 1; s < m; ++s)
    for (std::size_t t = s; t > 0 && weight[t] == weight[t - 1] && node[t] < node[t - 1]; --t) {
      std::swap(weight[t], weight[t - 1]);
      std::swap(node[t], node[t - 1]);
    }
}

/// Per-node accumulators of one query, cleared in O(touched).
struct accumulators {
  std::vector<std::int64_t> volume;                  // stolen voxels per node
  std::vector<std::array<std::int64_t, 3>> faces;    // facet faces per node and axis
  std::vector<double> h;                             // min path length through the facet (as double of T)
  std::vector<char> seen;
  std::vector<label_t> touched;
  explicit accumulators(std::size_t nodes)
      : volume(nodes, 0), faces(nodes, {0, 0, 0}), h(nodes, 0), seen(nodes, 0) {}
  void touch(label_t k) {
    if (!seen[k]) seen[k] = 1, touched.push_back(k), h[k] = std::numeric_limits<double>::infinity();
  }
  void clear() {
    for (label_t k : touched) volume[k] = 0, faces[k] = {0, 0, 0}, seen[k] = 0;
    touched.clear();
  }
};

/// Calls the progress callback (if any) and throws geovoronoi::cancelled when it asks to stop.
inline void report(const std::function<bool(double)>& progress, double fraction) {
  if (progress && !progress(std::min(1.0, std::max(0.0, fraction)))) throw cancelled();
}

/// The 2*Dim face neighbours of a grid: axis, direction, linear delta, the stencil entry with the same
/// offset (its length is the edge length every backend uses) and the face area.
template <int Dim>
struct face {
  int axis;
  int dir;
  index_t delta;
  int edge;
  double area;
};

template <class P>
std::vector<face<P::dim>> faces_of(const P& p) {
  constexpr int Dim = P::dim;
  std::vector<face<Dim>> out;
  index_t stride = 1;
  for (int a = 0; a < Dim; ++a) {
    double area = 1;
    for (int b = 0; b < Dim; ++b)
      if (b != a) area *= p.geometry.spacing(b);
    for (int dir = -1; dir <= 1; dir += 2) {
      int edge = -1;
      for (int n = 0; n < P::neighbours; ++n) {
        bool match = true;
        for (int b = 0; b < 3; ++b) match = match && p.edges.offset[n][b] == (b == a ? dir : 0);
        if (match) edge = n;
      }
      if (edge < 0) throw std::logic_error("geovoronoi::shape_functions: the connectivity lacks a face neighbour");
      out.push_back({a, dir, dir * stride, edge, area});
    }
    stride *= p.geometry.extent(a);
  }
  return out;
}

/// Whether the neighbour of voxel @p v (coordinates @p c) across face @p f lies inside the grid and
/// the edge to it is not cut: a cut face joins no two cells (no path crosses it), so it is neither a
/// Laplace facet nor a Distance Ratio frontier.
template <class P, class C>
bool face_in_grid(const P& p, index_t v, const C& c, const face<P::dim>& f) noexcept {
  const index_t x = c[f.axis] + f.dir;
  if (!(x >= 0 && x < p.geometry.extent(f.axis))) return false;
  if constexpr (P::has_cuts) return !((p.cut_mask(v) >> f.edge) & 1u);
  return true;
}

template <class P, class D, class Options>
void validate(const P& p, const D& d, const Options& opt) {
  const std::string who = "geovoronoi::shape_functions: ";
  if (opt.max_nodes_per_voxel < 1 || opt.max_nodes_per_voxel > max_nodes_per_voxel_limit)
    throw std::invalid_argument(who + "max_nodes_per_voxel (K) is " + std::to_string(opt.max_nodes_per_voxel) +
                                "; it must be between 1 and " + std::to_string(max_nodes_per_voxel_limit));
  if (opt.batch_size == 0) throw std::invalid_argument(who + "batch_size is 0; it must be >= 1");
  if (d.seeds.empty()) throw std::invalid_argument(who + "the diagram has no seeds, so there are no nodes");
  if (!(d.geometry() == p.geometry) || d.distance.size() != p.geometry.size() ||
      d.label.size() != p.geometry.size())
    throw std::invalid_argument(who + "the diagram was computed on another grid than the problem's");
  const index_t n = p.geometry.size();
  const label_t nodes = static_cast<label_t>(d.seeds.size());
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const index_t s = d.seeds[i];
    if (s < 0 || s >= n)
      throw std::invalid_argument(who + "node " + std::to_string(i) + " has voxel index " + std::to_string(s) +
                                  ", outside the grid");
    if (d.label[s] != static_cast<label_t>(i))
      throw std::invalid_argument(who + "node " + std::to_string(i) + " (voxel " + std::to_string(s) +
                                  ") carries label " + std::to_string(d.label[s]) +
                                  " in the diagram; node i must carry label i (use geovoronoi::voronoi)");
  }
  for (index_t v = 0; v < n; ++v)
    if (d.label[v] < no_label || d.label[v] >= nodes)
      throw std::invalid_argument(who + "voxel " + std::to_string(v) + " carries label " + std::to_string(d.label[v]) +
                                  ", which is not a node index (the diagram has " + std::to_string(nodes) +
                                  " seeds)");
}

}  // namespace geovoronoi::detail::shape

#pragma once
// Pieces shared by the three shape-function methods: argument checks, the per-voxel top-K selection
// and normalisation, progress reporting. What a new cell counts (volumes per owner, facet faces) and
// the face table are the searches' (search/cell_counts.hpp).

#include <geovoronoi/config.hpp>
#include <geovoronoi/detail/search/cell_counts.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/voxel_bits.hpp>
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

// the search core's vocabulary, which every method uses
using search::accumulators;
using search::edge_weight;
using search::extend;
using search::face;
using search::face_in_grid;
using search::faces_of;
using search::relax;
using search::stencil_walker;
using search::voxel_bits;

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

/// Calls the progress callback (if any) and throws geovoronoi::cancelled when it asks to stop.
inline void report(const std::function<bool(double)>& progress, double fraction) {
  if (progress && !progress(std::min(1.0, std::max(0.0, fraction)))) throw cancelled();
}

template <class P, class D, class Options>
void validate(const P& p, const D& d, const Options& opt) {
  const std::string who = "geovoronoi::shape_functions: ";
  if (opt.max_nodes_per_voxel < 1 || opt.max_nodes_per_voxel > max_nodes_per_voxel_limit)
    throw std::invalid_argument(who + "max_nodes_per_voxel (K) is " + std::to_string(opt.max_nodes_per_voxel) +
                                "; it must be between 1 and " + std::to_string(max_nodes_per_voxel_limit));
  if (opt.batch_size == 0) throw std::invalid_argument(who + "batch_size is 0; it must be >= 1");
  if (opt.tuning.lanes != 0 && opt.tuning.lanes != 16 && opt.tuning.lanes != 32)
    throw std::invalid_argument(who + "tuning.lanes is " + std::to_string(opt.tuning.lanes) +
                                "; it must be 0 (the library's choice), 16 or 32");
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
    if (d.label[s] != static_cast<label_t>(i) && d.label[s] >= 0 && d.label[s] < nodes && d.distance[s] == 0)
      throw std::invalid_argument(who + "node " + std::to_string(i) + " (voxel " + std::to_string(s) +
                                  ") is at geodesic distance 0 from node " + std::to_string(d.label[s]) +
                                  " (a path of zero-weight edges joins them, e.g. cost 0 under mean_cost), so it "
                                  "has no cell of its own; give the voxels between them a positive value or use "
                                  "another metric");
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

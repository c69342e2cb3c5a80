#pragma once
// The node list after node edits (change::nodes), with the positions and voxels checked: what the
// update applies and what the shape functions' update replays.

#include <geovoronoi/change.hpp>
#include <geovoronoi/grid.hpp>

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace geovoronoi::detail::update {

/// The node list after @p edits, applied in order to @p seeds; positions are checked.
template <int Dim>
std::vector<index_t> edit_node_list(const grid<Dim>& g, std::vector<index_t> nodes,
                                  const std::vector<node_edit<Dim>>& edits) {
  const std::string who = "geovoronoi::update: ";
  for (std::size_t e = 0; e < edits.size(); ++e) {
    const auto& x = edits[e];
    const std::string name = "node edit " + std::to_string(e);
    const bool adds = x.what == node_edit<Dim>::kind::add;
    const std::size_t pos = adds && x.position == node_edit<Dim>::append ? nodes.size() : x.position;
    if (adds ? pos > nodes.size() : pos >= nodes.size())
      throw std::invalid_argument(who + name + " names node position " + std::to_string(x.position) +
                                  ", but the node list has " + std::to_string(nodes.size()) + " nodes at that point");
    if (x.what == node_edit<Dim>::kind::remove) {
      nodes.erase(nodes.begin() + std::ptrdiff_t(pos));
      continue;
    }
    if (!g.contains(x.voxel))
      throw std::invalid_argument(who + name + " puts a node at " + to_string<Dim>(x.voxel) + ", outside the grid");
    if (adds)
      nodes.insert(nodes.begin() + std::ptrdiff_t(pos), g.index(x.voxel));
    else
      nodes[pos] = g.index(x.voxel);
  }
  return nodes;
}

}  // namespace geovoronoi::detail::update

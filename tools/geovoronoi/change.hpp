#pragma once
// What `cut` and `demo` share about a change to a solved problem (cut surfaces, carved voxels): the
// bit-for-bit checks of the incremental updates (typed_problem::update_in_place(),
// update_shape_functions_in_place()) against a full recompute, and the change's outputs
// (changed.mhd, cut.png, changed_weights.mhd; change.cpp).

#include "output_dir.hpp"
#include "outputs.hpp"

#include <geovoronoi.hpp>
#include <geovoronoi/shape_functions.hpp>

#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace gvcli {

/// The update's promise: @p upd equals the full recompute @p full bit for bit (distance, label,
/// parent). A difference is a bug in the library, not the user's input: runtime_failure (exit 1).
template <class T>
void require_equal(const gv::diagram<T, 3>& upd, const gv::diagram<T, 3>& full) {
  const auto& g = full.geometry();
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const char* what = nullptr;
    if (std::memcmp(&upd.distance[v], &full.distance[v], sizeof(T)) != 0) what = "distance";
    else if (upd.label[v] != full.label[v]) what = "label";
    else if (upd.parent[v] != full.parent[v]) what = "parent";
    if (!what) continue;
    const auto c = g.coords(v);
    char buf[200];
    std::snprintf(buf, sizeof buf, "at voxel (%lld,%lld,%lld) (distance %.9g vs %.9g, label %lld vs %lld)",
                  (long long)c[0], (long long)c[1], (long long)c[2], double(upd.distance[v]), double(full.distance[v]),
                  (long long)upd.label[v], (long long)full.label[v]);
    throw runtime_failure(std::string("internal error: the incremental update differs from the full recompute in its ") +
                          what + " " + buf + "; please report this with the inputs");
  }
}

/// The shape-function update's promise: @p upd equals the full recompute @p full bit for bit (node and
/// weight of every slot); else runtime_failure (exit 1), a bug in the library.
template <class T>
void require_equal(const gv::shape_weights<T, 3>& upd, const gv::shape_weights<T, 3>& full) {
  if (upd.k != full.k || upd.nodes != full.nodes || upd.node.size() != full.node.size() ||
      upd.weight.size() != full.weight.size())
    throw runtime_failure("internal error: the updated shape functions differ in shape from the full recompute; "
                          "please report this with the inputs");
  const std::size_t k = std::size_t(full.k);
  for (std::size_t i = 0; i < full.node.size(); ++i) {
    if (upd.node[i] == full.node[i] && std::memcmp(&upd.weight[i], &full.weight[i], sizeof(T)) == 0) continue;
    const auto c = full.geometry.coords(gv::index_t(i / k));
    char buf[200];
    std::snprintf(buf, sizeof buf, "at voxel (%lld,%lld,%lld) slot %zu (node %lld vs %lld, weight %.9g vs %.9g)",
                  (long long)c[0], (long long)c[1], (long long)c[2], i % k, (long long)upd.node[i],
                  (long long)full.node[i], double(upd.weight[i]), double(full.weight[i]));
    throw runtime_failure(std::string("internal error: the updated shape functions differ from the full recompute ") +
                          buf + "; please report this with the inputs");
  }
}

/// changed_weights.mhd in @p dir: MET_UCHAR, 1 where any slot of the voxel's row (node index or weight
/// bits) differs between @p before and @p after, else 0. Returns the number of such voxels.
template <class T>
std::size_t write_changed_weights(const std::string& dir, const gv::shape_weights<T, 3>& before,
                                  const gv::shape_weights<T, 3>& after);

/// A change's pictures and mask, written into @p dir: changed.mhd (MET_UCHAR, 1 where the distance or
/// the label differs between @p before and @p after) and cut.png (the cells before | after on the
/// slices through the middle of the change: the cut edges of @p cuts (may be null) and the box
/// @p box_lo..@p box_hi (inclusive voxel indices; ignored when box_hi[0] < 0); the cut drawn, changed
/// voxels outlined). Returns the number of changed voxels.
template <class T>
std::size_t write_change(const std::string& dir, const gv::diagram<T, 3>& before, const gv::diagram<T, 3>& after,
                         const gv::image<T, 3>& field_before, const gv::image<T, 3>& field_after,
                         const gv::cut_set<3>* cuts, const gv::coord<3>& box_lo, const gv::coord<3>& box_hi,
                         const picture_context& pc);

}  // namespace gvcli

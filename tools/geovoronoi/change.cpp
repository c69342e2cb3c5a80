// See change.hpp.
#include "change.hpp"

#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <unordered_set>

namespace gvcli {

namespace gio = geovoronoi::io;
using geovoronoi::index_t;

template <class T>
std::size_t write_change(const std::string& dir, const gv::diagram<T, 3>& before, const gv::diagram<T, 3>& after,
                         const gv::image<T, 3>& field_before, const gv::image<T, 3>& field_after,
                         const gv::cut_set<3>* cuts, const gv::coord<3>& box_lo, const gv::coord<3>& box_hi,
                         const picture_context& pc) {
  const auto& g = before.geometry();
  gv::image<std::uint8_t, 3> changed(g, std::uint8_t(0));
  std::size_t n_changed = 0;
  for (index_t v = 0; v < g.size(); ++v)
    if (std::memcmp(&before.distance[v], &after.distance[v], sizeof(T)) != 0 || before.label[v] != after.label[v])
      changed[v] = 1, ++n_changed;
  gio::write_metaimage(dir + "/changed.mhd", changed);

  // The cut's grid edges between face neighbours (the ones a panel can draw), keyed by the lower
  // voxel and the axis; the slices through the middle of the change (cut edges and box).
  std::unordered_set<index_t> faces;
  gv::coord<3> lo{g.extent(0), g.extent(1), g.extent(2)}, hi{-1, -1, -1};
  auto grow = [&](const gv::coord<3>& c) {
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  };
  if (cuts)
    cuts->for_each_edge([&](index_t u, int d) {
      const auto& o = cuts->offset(d);
      const auto cu = g.coords(u);
      const gv::coord<3> cv{cu[0] + o[0], cu[1] + o[1], cu[2] + o[2]};
      grow(cu), grow(cv);
      if (std::abs(o[0]) + std::abs(o[1]) + std::abs(o[2]) != 1) return;
      const int axis = o[0] ? 0 : o[1] ? 1 : 2;
      faces.insert(std::min(u, g.index(cv)) * 3 + axis);
    });
  if (box_hi[0] >= 0) grow(box_lo), grow(box_hi);
  if (hi[0] < 0) lo = {0, 0, 0}, hi = {g.extent(0) - 1, g.extent(1) - 1, g.extent(2) - 1};  // no change at all
  auto left = pc.options("BEFORE THE CHANGE");
  auto right = pc.options("AFTER: " + std::to_string(n_changed) + " VOXELS CHANGED");
  left.title = {left.title[0].substr(0, left.title[0].find(" - "))};
  for (auto* o : {&left, &right}) {
    for (int a = 0; a < 3; ++a) o->slice[std::size_t(a)] = (lo[a] + hi[a]) / 2;
    if (!faces.empty())
      o->cut_between = [&faces, &g](index_t u, index_t v) {
        const auto cu = g.coords(u), cv = g.coords(v);
        const int axis = cu[0] != cv[0] ? 0 : cu[1] != cv[1] ? 1 : 2;
        return faces.count(std::min(u, v) * 3 + axis) != 0;
      };
    o->marked = [&changed](index_t v) { return changed[v] != 0; };
  }
  left.legend = false;
  gio::write_png(dir + "/cut.png", gio::hstack(gio::label_picture(before.label, before.seeds, &field_before, left),
                                               gio::label_picture(after.label, after.seeds, &field_after, right),
                                               gio::picture_background));
  return n_changed;
}

template <class T>
std::size_t write_changed_weights(const std::string& dir, const gv::shape_weights<T, 3>& before,
                                  const gv::shape_weights<T, 3>& after) {
  const auto& g = after.geometry;
  const std::size_t k = std::size_t(after.k);
  if (before.k != after.k || before.node.size() != after.node.size())
    throw std::logic_error("geovoronoi: write_changed_weights: the weights before and after differ in K or size");
  gv::image<std::uint8_t, 3> changed(g, std::uint8_t(0));
  std::size_t n_changed = 0;
  for (index_t v = 0; v < g.size(); ++v)
    for (std::size_t s = std::size_t(v) * k; s < std::size_t(v + 1) * k; ++s)
      if (before.node[s] != after.node[s] || std::memcmp(&before.weight[s], &after.weight[s], sizeof(T)) != 0) {
        changed[v] = 1, ++n_changed;
        break;
      }
  gio::write_metaimage(dir + "/changed_weights.mhd", changed);
  return n_changed;
}

template std::size_t write_changed_weights(const std::string&, const gv::shape_weights<float, 3>&,
                                           const gv::shape_weights<float, 3>&);
template std::size_t write_changed_weights(const std::string&, const gv::shape_weights<double, 3>&,
                                           const gv::shape_weights<double, 3>&);
template std::size_t write_change(const std::string&, const gv::diagram<float, 3>&, const gv::diagram<float, 3>&,
                                  const gv::image<float, 3>&, const gv::image<float, 3>&, const gv::cut_set<3>*,
                                  const gv::coord<3>&, const gv::coord<3>&, const picture_context&);
template std::size_t write_change(const std::string&, const gv::diagram<double, 3>&, const gv::diagram<double, 3>&,
                                  const gv::image<double, 3>&, const gv::image<double, 3>&, const gv::cut_set<3>*,
                                  const gv::coord<3>&, const gv::coord<3>&, const picture_context&);

}  // namespace gvcli

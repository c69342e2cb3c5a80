#pragma once
// Argument checks of the solvers' front end (voronoi.hpp): done once, before dispatch
// (dispatch.hpp), so every backend rejects the same inputs with the same messages.

#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/result.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace geovoronoi::detail {

template <class P>
std::string describe_voxel(const P& p, index_t v) {
  return to_string<P::dim>(p.geometry.coords(v)) + " (voxel " + std::to_string(v) + ")";
}

/// The name of the @p index-th item of a list of @p kind ("seed 3"), or @p kind alone without an
/// index. Built only when a check fails, so checking a list formats nothing.
inline std::string item_name(const char* kind, std::size_t index) {
  return index == std::size_t(-1) ? std::string(kind) : std::string(kind) + " " + std::to_string(index);
}

/// Linear index of @p c, or an exception naming the item (@p kind, @p index) and the coordinates.
template <class P>
index_t checked_voxel(const P& p, const coord<P::dim>& c, const char* kind, std::size_t index = std::size_t(-1)) {
  if (!p.geometry.contains(c))
    throw std::invalid_argument("geovoronoi: " + item_name(kind, index) + " at " + to_string<P::dim>(c) +
                                " lies outside the grid");
  const index_t v = p.geometry.index(c);
  if (!p.inside(v))
    throw std::invalid_argument("geovoronoi: " + item_name(kind, index) + " at " + to_string<P::dim>(c) +
                                " lies on a masked voxel (field value " + std::to_string(double(p.field[v])) + ")");
  return v;
}

template <class P>
index_t checked_voxel(const P& p, index_t v, const char* kind, std::size_t index = std::size_t(-1)) {
  if (v < 0 || v >= p.geometry.size())
    throw std::invalid_argument("geovoronoi: " + item_name(kind, index) + " has voxel index " + std::to_string(v) +
                                ", outside the grid of " + std::to_string(p.geometry.size()) + " voxels");
  if (!p.inside(v))
    throw std::invalid_argument("geovoronoi: " + item_name(kind, index) + " at " + describe_voxel(p, v) +
                                " lies on a masked voxel (field value " + std::to_string(double(p.field[v])) + ")");
  return v;
}

/// Checks a list of sources: non-empty, inside, unmasked, distinct voxels, finite non-negative
/// initial distances, non-negative labels.
template <class P>
void validate_sources(const P& p, const std::vector<source<typename P::value_type>>& s, const char* kind = "seed") {
  using T = typename P::value_type;
  if (s.empty()) throw std::invalid_argument(std::string("geovoronoi: the ") + kind + " list is empty");
  if (s.size() > std::size_t(std::numeric_limits<label_t>::max()))
    throw std::invalid_argument("geovoronoi: too many seeds for 32-bit labels");
  for (std::size_t i = 0; i < s.size(); ++i) {
    checked_voxel(p, s[i].voxel, kind, i);
    if (!(s[i].distance >= T(0)) || !(s[i].distance < std::numeric_limits<T>::infinity()))
      throw std::invalid_argument("geovoronoi: " + item_name(kind, i) + " has initial distance " +
                                  std::to_string(double(s[i].distance)) + "; it must be finite and >= 0");
    if (s[i].label < 0) throw std::invalid_argument("geovoronoi: " + item_name(kind, i) + " has a negative label");
  }
  std::vector<std::pair<index_t, std::size_t>> order(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) order[i] = {s[i].voxel, i};
  std::sort(order.begin(), order.end());
  for (std::size_t i = 1; i < order.size(); ++i)
    if (order[i].first == order[i - 1].first)
      throw std::invalid_argument("geovoronoi: " + std::string(kind) + "s " + std::to_string(order[i - 1].second) +
                                  " and " + std::to_string(order[i].second) + " share the voxel " +
                                  describe_voxel(p, order[i].first));
}

template <class P, class D>
void check_diagram(const P& p, const D& d) {
  if (d.geometry() != p.geometry || d.distance.size() != p.geometry.size() || d.label.geometry() != p.geometry ||
      d.label.size() != p.geometry.size())
    throw std::invalid_argument("geovoronoi: the diagram was computed on another grid than the problem's");
}

}  // namespace geovoronoi::detail

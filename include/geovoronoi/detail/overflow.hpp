#pragma once
// Overflow of the distance type, found the same way by every backend.
//
// A relaxation whose sum fl(d(v) + w(v,u)) is +inf is rejected by the unbounded solves' filter
// (nd < +inf), so without a check u would silently stay "unreachable". The engines only raise a flag
// when they reject an infinite sum (outside the hot path: with an infinite radius nothing else is
// ever rejected). The flag alone is not decisive: the sum may overflow along one edge while u is
// reached, with a finite distance, along another; and which edges a backend evaluates depends on its
// order of work. So a raised flag triggers this scan of the final result, which depends on nothing
// but that result (bitwise the same on every backend): the overflow is real exactly when some voxel
// in the domain stayed unreached although a reached neighbour's distance plus the edge weight is
// +inf. Every backend evaluates that edge (the neighbour is expanded with its final key while u is
// still unreached), so every backend raises the flag in that case, and the scan names the same voxel.

#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/detail/search/stencil_walk.hpp>
#include <geovoronoi/detail/search/topology.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <cstdio>
#include <limits>
#include <string>
#include <type_traits>

namespace geovoronoi::detail {

/// The voxel whose distance overflowed, its reached neighbour, that neighbour's distance and the weight.
template <class T>
struct overflow_site {
  index_t voxel = no_index;
  index_t from = no_index;
  T distance = T(0);
  T weight = T(0);
};

inline std::string short_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

template <int Dim>
std::string coords_text(const grid<Dim>& g, index_t v) {
  const auto c = g.coords(v);
  std::string s = "(";
  for (int a = 0; a < Dim; ++a) s += (a ? "," : "") + std::to_string(c[a]);
  return s + ")";
}

/// The error for an overflow at @p s, its nodes named by @p text(v), the overflowing one after @p at.
template <class T, class Text>
overflow_error overflow_error_named(Text&& text, const overflow_site<T>& s, const char* at) {
  const char* type = std::is_same_v<T, float> ? "float" : "double";
  const bool weight = !(s.weight <= std::numeric_limits<T>::max());
  std::string why = weight ? "the edge weight from its neighbour " + text(s.from) + " is +inf in " + type
                           : "its neighbour " + text(s.from) + " is at distance " +
                                 short_number(double(s.distance)) + " and the edge weight " +
                                 short_number(double(s.weight)) + " takes the sum past the largest " + type + " (" +
                                 short_number(double(std::numeric_limits<T>::max())) + ")";
  return overflow_error("geovoronoi: the distance overflows " + std::string(type) + " at " + at + text(s.voxel) + ": " +
                        why + ", so a voxel that a path reaches would come out unreachable; " +
                        (std::is_same_v<T, float> ? "compute in double precision (a double field), or rescale the "
                                                    "field or the spacing"
                                                  : "rescale the field or the spacing"));
}

/// The error for an overflow at @p s on grid @p g.
template <class T, int Dim>
overflow_error overflow_error_at(const grid<Dim>& g, const overflow_site<T>& s) {
  return overflow_error_named([&](index_t v) { return coords_text(g, v); }, s, "voxel ");
}

/// The error for an overflow at @p s on problem @p p: voxels named by their coordinates, the nodes
/// of an explicit graph by the problem's node_text.
template <class P, class T>
overflow_error overflow_error_on(const P& p, const overflow_site<T>& s) {
  if constexpr (search::implicit_grid_v<P>)
    return overflow_error_at(p.geometry, s);
  else
    return overflow_error_named([&](index_t v) { return p.node_text(v); }, s, "");
}

/**
 * Scans a finished solve for an overflow (see the top of this file). @p each_reached(f) calls
 * f(v, d(v)) for every reached voxel; @p reached(u) says whether u was reached. Throws
 * geovoronoi::overflow_error naming the lowest such voxel (then its lowest reached neighbour).
 */
template <class P, class EachReached, class Reached>
void throw_if_overflowed(const P& p, EachReached&& each_reached, Reached&& reached) {
  using T = typename P::value_type;
  const search::walker_t<P> walk(p);
  overflow_site<T> best;
  each_reached([&](index_t v, T dv) {
    const T fv = p.field[v];
    walk.for_each_neighbour(p, v, [&](int k, index_t u) {
      if (best.voxel != no_index && (u > best.voxel || (u == best.voxel && v > best.from))) return;
      const T fu = p.field[u];
      if (!inside<typename P::metric_type>(fu) || reached(u)) return;
      const T w = search::edge_weight(p.metric, p.edges.length[k], fv, fu);
      const T nd = search::extend(dv, w);
      if (nd <= std::numeric_limits<T>::max()) return;
      best = {u, v, dv, w};
    });
  });
  if (best.voxel != no_index) throw overflow_error_on(p, best);
}

/// The scan on a dense result: @p distance holds +inf where unreached.
template <class P>
void throw_if_overflowed_dense(const P& p, const typename P::value_type* distance) {
  using T = typename P::value_type;
  const index_t n = search::node_count(p);
  const T inf = std::numeric_limits<T>::infinity();
  throw_if_overflowed(
      p,
      [&](auto&& f) {
        for (index_t v = 0; v < n; ++v)
          if (distance[v] < inf) f(v, distance[v]);
      },
      [&](index_t u) { return distance[u] < inf; });
}

/// The scan on a sparse result: @p voxel sorted, @p distance alongside, @p count entries.
template <class P>
void throw_if_overflowed_sparse(const P& p, const index_t* voxel, const typename P::value_type* distance,
                                std::size_t count) {
  throw_if_overflowed(
      p,
      [&](auto&& f) {
        for (std::size_t i = 0; i < count; ++i) f(voxel[i], distance[i]);
      },
      [&](index_t u) {
        std::size_t lo = 0, hi = count;
        while (lo < hi) {
          const std::size_t mid = lo + (hi - lo) / 2;
          if (voxel[mid] < u)
            lo = mid + 1;
          else
            hi = mid;
        }
        return lo < count && voxel[lo] == u;
      });
}

}  // namespace geovoronoi::detail

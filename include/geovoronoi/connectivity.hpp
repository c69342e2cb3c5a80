#pragma once
/// @file connectivity.hpp
/// @brief Neighbourhood policies (4/8 in 2D, 6/18/26 in 3D) and the per-grid stencil built from them.

#include <geovoronoi/config.hpp>
#include <geovoronoi/grid.hpp>

#include <array>
#include <cmath>

namespace geovoronoi {

/**
 * @brief Which neighbours a voxel is joined to: 4 or 8 in 2D; 6 (faces), 18 (faces and edges) or
 *        26 (faces, edges and corners) in 3D.
 *
 * The offsets are a constexpr table, ordered with z outermost and x innermost, each coordinate from
 * -1 to 1 (the order SOFA's Dijkstra loops in). Only their set matters for results: the tie rule
 * makes every solver independent of the visiting order.
 */
template <int N>
struct connectivity {
  static_assert(N == 4 || N == 8 || N == 6 || N == 18 || N == 26,
                "geovoronoi::connectivity<N>: N must be 4 or 8 (2D) or 6, 18 or 26 (3D)");
  /// Dimension of the grids this connectivity applies to.
  static constexpr int dim = (N == 4 || N == 8) ? 2 : 3;
  /// Number of neighbours.
  static constexpr int size = N;
  /// Largest number of non-zero components an offset may have (1 = faces only).
  static constexpr int max_order = (N == 4 || N == 6) ? 1 : (N == 18 ? 2 : dim);

  using offset_type = std::array<int, dim>;

  /// The N neighbour offsets.
  static constexpr std::array<offset_type, N> offsets() noexcept {
    std::array<offset_type, N> out{};
    int n = 0;
    if constexpr (dim == 2) {
      for (int y = -1; y <= 1; ++y)
        for (int x = -1; x <= 1; ++x) {
          const int order = (x != 0) + (y != 0);
          if (order == 0 || order > max_order) continue;
          out[n++] = offset_type{x, y};
        }
    } else {
      for (int z = -1; z <= 1; ++z)
        for (int y = -1; y <= 1; ++y)
          for (int x = -1; x <= 1; ++x) {
            const int order = (x != 0) + (y != 0) + (z != 0);
            if (order == 0 || order > max_order) continue;
            out[n++] = offset_type{x, y, z};
          }
    }
    return out;
  }
};

namespace detail {
template <class C>
struct is_connectivity : std::false_type {};
template <int N>
struct is_connectivity<connectivity<N>> : std::true_type {};
}  // namespace detail

/**
 * @brief The connectivity resolved against one grid: per-neighbour offsets, linear index deltas and
 *        physical edge lengths ||offset (.) spacing||_2 rounded once, on the host, to T.
 *
 * Every backend reads edge lengths from this table, so they are bitwise identical everywhere.
 * Trivially copyable; pass it to kernels by value.
 */
template <class T, int Dim, int N>
struct stencil {
  static_assert(connectivity<N>::dim == Dim, "geovoronoi::stencil: connectivity does not match the grid dimension");
  static constexpr int size = N;
  int offset[N][3];   ///< (dx, dy, dz); dz = 0 in 2D
  index_t delta[N];   ///< linear index difference of each neighbour
  T length[N];        ///< physical length of each edge

  stencil() = default;
  stencil(const grid<Dim>& g, connectivity<N> = {}) {
    constexpr auto offs = connectivity<N>::offsets();
    for (int n = 0; n < N; ++n) {
      double len2 = 0;
      index_t d = 0, stride = 1;
      for (int a = 0; a < 3; ++a) offset[n][a] = 0;
      for (int a = 0; a < Dim; ++a) {
        offset[n][a] = offs[n][a];
        const double s = offs[n][a] * g.spacing(a);
        len2 += s * s;
        d += offs[n][a] * stride;
        stride *= g.extent(a);
      }
      delta[n] = d;
      length[n] = static_cast<T>(std::sqrt(len2));
    }
  }
};

}  // namespace geovoronoi

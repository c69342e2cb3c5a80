#pragma once
/// @file bench/voronoi/sofa_set.hpp
/// @brief The sequential reference the paper compares against: SOFA's multi-source Dijkstra
///        (image plugin, ImageAlgorithms.h `dijkstra`), re-implemented from the description in
///        shared/reference/sofa-voronoi.md section 2.1. Benchmark use only; not part of the library.
///
/// What it keeps from SOFA, because that is what the speed-ups are measured against:
///  - the queue is a std::set of (distance, (x, y, z)) pairs; the smallest pair is taken first, so
///    equal distances come out in lexicographic (x, y, z) order;
///  - decrease-key = erase the exact (old distance, voxel) pair, insert the new one; no closed set;
///  - the 26-neighbourhood, visited z outer, then y, then x, each from -1 to 1;
///  - edge weight = length / min(b_u, b_v) with anisotropic lengths;
///  - relaxation only when old > new (strict); the neighbour then copies the label of the voxel
///    being expanded;
///  - all seeds get distance 0 and their label first, then one Dijkstra run;
///  - voxels outside the object carry distance -1, so the strict test never enters them.
/// What differs: edge lengths come from the library's stencil (rounded once to float, as every
/// backend uses them) and distances are float, so the distances are bitwise comparable with the
/// library's; seeds are voxel coordinates validated by the caller.

#include <geovoronoi.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <set>
#include <utility>
#include <vector>

namespace geovoronoi::bench::sofa {

/// Output of the SOFA-style solve, in the library's conventions (+inf / -1 where not reached).
struct solution {
  std::vector<float> distance;
  std::vector<label_t> label;
  std::int64_t pops = 0;         ///< elements taken off the queue
  std::int64_t relaxations = 0;  ///< successful (strict) relaxations, each an insert into the set
};

/// SOFA's Dijkstra with a std::set queue on a 26-connected min_stiffness problem.
/// @param p     a problem built with connectivity<26> (its stencil gives the edge lengths, in SOFA's
///              z-y-x loop order) and min_stiffness.
/// @param seeds distinct seed voxels inside the domain; label i for the i-th.
template <class P>
solution dijkstra_set(const P& p, const std::vector<coord<3>>& seeds) {
  static_assert(P::dim == 3 && P::neighbours == 26, "sofa::dijkstra_set: SOFA's Dijkstra is 26-connected 3D");
  using voxel = std::array<int, 3>;  // (x, y, z); std::array compares x first, like SOFA's fixed_array
  using entry = std::pair<float, voxel>;

  const auto& g = p.geometry;
  const int nx = int(g.extent(0)), ny = int(g.extent(1)), nz = int(g.extent(2));
  const auto at = [nx, ny](int x, int y, int z) {
    return std::size_t(x) + std::size_t(nx) * (std::size_t(y) + std::size_t(ny) * std::size_t(z));
  };
  const std::size_t n = std::size_t(g.size());
  const float far = std::numeric_limits<float>::max();

  // distance: -1 outside the object, "max" inside; labels 0 = none (SOFA stores seed index + 1)
  std::vector<float> d(n);
  std::vector<label_t> lab(n, 0);
  for (std::size_t v = 0; v < n; ++v) d[v] = p.field[v] > 0.0f ? far : -1.0f;

  std::set<entry> queue;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    const voxel c{int(seeds[i][0]), int(seeds[i][1]), int(seeds[i][2])};
    const std::size_t v = at(c[0], c[1], c[2]);
    if (d[v] < 0) continue;  // SOFA skips seeds outside the object
    d[v] = 0.0f;
    lab[v] = label_t(i + 1);
    queue.insert(entry{0.0f, c});
  }

  solution out;
  while (!queue.empty()) {
    const entry top = *queue.begin();
    queue.erase(queue.begin());
    ++out.pops;
    const voxel c = top.second;
    const std::size_t u = at(c[0], c[1], c[2]);
    const float du = d[u];
    const float bu = p.field[u];
    int k = 0;  // index into the stencil: same z, y, x order, zero offset skipped
    for (int oz = -1; oz <= 1; ++oz)
      for (int oy = -1; oy <= 1; ++oy)
        for (int ox = -1; ox <= 1; ++ox) {
          if (ox == 0 && oy == 0 && oz == 0) continue;
          const int kk = k++;
          const int x = c[0] + ox, y = c[1] + oy, z = c[2] + oz;
          if (x < 0 || y < 0 || z < 0 || x >= nx || y >= ny || z >= nz) continue;
          const std::size_t v = at(x, y, z);
          const float bv = p.field[v];
          const float w = p.edges.length[kk] / std::min(bu, bv);
          const float nd = du + w;
          const float old = d[v];
          if (old > nd) {
            if (old != far) queue.erase(entry{old, voxel{x, y, z}});
            d[v] = nd;
            lab[v] = lab[u];
            queue.insert(entry{nd, voxel{x, y, z}});
            ++out.relaxations;
          }
        }
  }

  out.distance.assign(n, std::numeric_limits<float>::infinity());
  out.label.assign(n, no_label);
  for (std::size_t v = 0; v < n; ++v)
    if (d[v] >= 0 && d[v] != far) {
      out.distance[v] = d[v];
      out.label[v] = lab[v] - 1;
    }
  return out;
}

}  // namespace geovoronoi::bench::sofa

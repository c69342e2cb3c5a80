#pragma once
// The per-voxel steps of the CUDA kernels, written once as host-device functions so that the same
// code runs inside the kernels (engine.cuh, repair.cuh, insert.cuh) and in the host model of the
// algorithm that tests/cuda_tile_model.test.cpp runs with g++ on machines without a GPU:
//   - the relaxation rules (what a candidate state word is);
//   - loading one slot of a haloed tile, pulling the best candidate into a tile voxel, computing
//     the candidate pushed into a halo voxel;
//   - the label recovery step of double solves; the pull step of an insert-query box.
// Shared-memory arrays are plain pointers here; the kernels supply the barriers between steps.

#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/cut.hpp>
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/metric.hpp>

#include <cstdint>
#include <type_traits>

namespace geovoronoi::cuda {

/**
 * @brief Customisation point: the metric object kernels evaluate for a problem's metric type.
 *
 * The default is the metric itself, which must then have a host-device call operator (the core's
 * metrics do). Specialise it to map a host-only metric to an equivalent device-capable one.
 */
template <class Metric>
struct device_metric {
  using type = Metric;
  static GEOVORONOI_HOST_DEVICE const Metric& convert(const Metric& m) noexcept { return m; }
};

namespace detail {

template <class P>
using dmetric_t = typename device_metric<typename P::metric_type>::type;

/// Edge weight from a voxel with field @p from to one with field @p to through neighbour k: the
/// relaxation step's weight (detail/search/relax.hpp) with the device form of the metric.
template <class P>
GEOVORONOI_HOST_DEVICE inline typename P::value_type edge_weight(const P& p, int k, typename P::value_type from,
                                                                 typename P::value_type to) {
  return geovoronoi::detail::search::edge_weight(device_metric<typename P::metric_type>::convert(p.metric),
                                                 p.edges.length[k], from, to);
}

/// The relaxation step's addition (detail/search/relax.hpp).
using geovoronoi::detail::search::extend;

template <class P>
GEOVORONOI_HOST_DEVICE inline bool in_domain(typename P::value_type f) {
  return geovoronoi::detail::inside<dmetric_t<P>>(f);
}

// ---- rules ---------------------------------------------------------------------------------------

/// Whether a sum is beyond the finite range of its type (+inf: an overflow).
GEOVORONOI_HOST_DEVICE inline bool beyond_range(float x) noexcept { return x > 3.40282347e+38f; }
GEOVORONOI_HOST_DEVICE inline bool beyond_range(double x) noexcept { return x > 1.7976931348623157e+308; }

/// Records a rejected candidate whose sum is +inf in @p flag (when set): the host then checks the
/// result for an overflow (geovoronoi/detail/overflow.hpp). A plain store: every writer writes 1.
template <class T>
GEOVORONOI_HOST_DEVICE inline void note_overflow(int* flag, T nd) noexcept {
  if (flag && beyond_range(nd)) *flag = 1;
}

/// float Voronoi: packed (distance, label) keys; accepts distances below the radius.
struct rule_voronoi {
  float radius;
  int* overflow = nullptr;  ///< device flag set when a candidate's sum is +inf (optional)
  GEOVORONOI_HOST_DEVICE uint64_t candidate(uint64_t from, float w, index_t, uint64_t) const {
    const float nd = extend(key_distance(from), w);
    if (nd < radius) return pack(nd, key_label(from));
    note_overflow(overflow, nd);
    return unreached;
  }
};

/// float labels, second pass: distances are final; a voxel takes the label of a neighbour that
/// realises its distance bit for bit, if that label is smaller. Needed because label-correcting
/// relaxation can leave a label that arrived through a stale key: when fl(d' + w) == fl(d + w) for
/// a neighbour's earlier distance d' > d, the voxel keeps the earlier (smaller) label although
/// Dijkstra, which relaxes from final keys only, gives the label of the final key.
struct rule_label {
  GEOVORONOI_HOST_DEVICE uint64_t candidate(uint64_t from, float w, index_t, uint64_t to) const {
    if (to == unreached) return unreached;
    const float nd = extend(key_distance(from), w);
    return float_bits(nd) == uint32_t(to >> 32) ? pack(key_distance(to), key_label(from)) : unreached;
  }
};

/// The first-pass key with its label cleared (all ones), for the label pass to refill.
GEOVORONOI_HOST_DEVICE inline uint64_t clear_label(uint64_t key) noexcept {
  return key == unreached ? key : (key | uint64_t(0xFFFFFFFFu));
}

/// Distances only (double solves; labels follow in a separate pass).
template <class T>
struct rule_distance {
  T radius;
  int* overflow = nullptr;  ///< as rule_voronoi::overflow
  GEOVORONOI_HOST_DEVICE uint64_t candidate(uint64_t from, T w, index_t, uint64_t) const {
    const T nd = extend(word_distance<T>(from), w);
    if (nd < radius) return distance_word(nd);
    note_overflow(overflow, nd);
    return unreached;
  }
};

/// Insert query: distances from the query, accepted only where strictly below the diagram's.
template <class T>
struct rule_insert {
  const T* old;
  GEOVORONOI_HOST_DEVICE uint64_t candidate(uint64_t from, T w, index_t v, uint64_t) const {
    const T nd = extend(word_distance<T>(from), w);
    return nd < old[v] ? distance_word(nd) : unreached;
  }
};

// ---- tile steps ----------------------------------------------------------------------------------

/// Origin (first voxel) of a tile.
struct tile_origin {
  index_t x, y, z;
};
GEOVORONOI_HOST_DEVICE inline tile_origin origin_of(const tiling& t, index_t tile) {
  index_t a, b, c;
  t.tile_coords(tile, a, b, c);
  return {a * t.tx, b * t.ty, c * t.tz};
}

/// Fills haloed slot @p s: field value and state word (all ones outside the grid or the domain).
/// @p load reads a state word from global memory.
template <class P, class Word, class Load>
GEOVORONOI_HOST_DEVICE inline void load_slot(const P& p, const tiling& t, tile_origin o, int s, Word* sw,
                                             typename P::value_type* sf, Load&& load) {
  using T = typename P::value_type;
  int lx, ly, lz;
  halo_coords<P::dim>(s, lx, ly, lz);
  const index_t gx = o.x + lx, gy = o.y + ly, gz = o.z + lz;
  if (t.in_grid(gx, gy, gz)) {
    const index_t v = t.voxel(gx, gy, gz);
    const T f = p.field[v];
    sf[s] = f;
    sw[s] = in_domain<P>(f) ? Word(load(v)) : Word(unreached);
  } else {
    sf[s] = T(0);
    sw[s] = Word(unreached);
  }
}

/// Best state word of the tile voxel at local (lx, ly, lz), voxel @p v, from its haloed neighbours.
/// Sets *bad on a negative or NaN weight.
template <class P, class Rule, class Word>
GEOVORONOI_HOST_DEVICE inline uint64_t pull(const P& p, const Rule& rule, const Word* sw,
                                            const typename P::value_type* sf, int lx, int ly, int lz, index_t v,
                                            bool& bad) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim;
  const int me = halo_slot<Dim>(lx, ly, lz);
  uint64_t best = sw[me];
  const T fv = sf[me];
  const cut_mask_t cut = p.cut_mask(v);  // 0 (a constant) for a problem without cuts
#ifdef __CUDA_ARCH__
#pragma unroll
#endif
  for (int k = 0; k < P::neighbours; ++k) {
    if ((cut >> k) & 1u) continue;
    const int s = halo_slot<Dim>(lx + p.edges.offset[k][0], ly + p.edges.offset[k][1], lz + p.edges.offset[k][2]);
    const uint64_t su = sw[s];
    if (su == unreached) continue;
    const T w = edge_weight(p, k, sf[s], fv);
    if (!(w >= T(0))) {
      bad = true;
      continue;
    }
    const uint64_t c = rule.candidate(su, w, v, uint64_t(sw[me]));
    if (c < best) best = c;
  }
  return best;
}

/// Candidate for halo slot (lx, ly, lz) (voxel @p h, in the domain) from the tile's own voxels;
/// all ones if none improves on its loaded word.
template <class P, class Rule, class Word>
GEOVORONOI_HOST_DEVICE inline uint64_t push_candidate(const P& p, const Rule& rule, const Word* sw,
                                                      const typename P::value_type* sf, int lx, int ly, int lz,
                                                      index_t h, bool& bad) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim;
  const int hs = halo_slot<Dim>(lx, ly, lz);
  const T fh = sf[hs];
  uint64_t best = sw[hs];
  const cut_mask_t cut = p.cut_mask(h);
#ifdef __CUDA_ARCH__
#pragma unroll
#endif
  for (int k = 0; k < P::neighbours; ++k) {
    if ((cut >> k) & 1u) continue;
    const int ux = lx + p.edges.offset[k][0], uy = ly + p.edges.offset[k][1], uz = lz + p.edges.offset[k][2];
    if (is_halo<Dim>(ux, uy, uz)) continue;
    const int s = halo_slot<Dim>(ux, uy, uz);
    const uint64_t su = sw[s];
    if (su == unreached) continue;
    const T w = edge_weight(p, k, sf[s], fh);
    if (!(w >= T(0))) {
      bad = true;
      continue;
    }
    const uint64_t c = rule.candidate(su, w, h, uint64_t(sw[hs]));
    if (c < best) best = c;
  }
  return best < uint64_t(sw[hs]) ? best : unreached;
}

// ---- double labels -------------------------------------------------------------------------------

/// Least label among the neighbours of reached voxel @p v that realise its distance word @p dv,
/// and @p current. @p label_at reads a neighbour's current label.
template <class P, class Words, class LabelAt>
GEOVORONOI_HOST_DEVICE inline std::uint32_t realising_label(const P& p, const tiling& t, const Words* words,
                                                            index_t v, uint64_t dv, std::uint32_t current,
                                                            LabelAt&& label_at) {
  using T = typename P::value_type;
  const index_t x = v % t.nx, r = v / t.nx, y = r % t.ny, z = r / t.ny;
  const T fv = p.field[v];
  std::uint32_t best = current;
  const cut_mask_t cut = p.cut_mask(v);
  for (int k = 0; k < P::neighbours; ++k) {
    if ((cut >> k) & 1u) continue;
    const index_t ux = x + p.edges.offset[k][0], uy = y + p.edges.offset[k][1], uz = z + p.edges.offset[k][2];
    if (!t.in_grid(ux, uy, uz)) continue;
    const index_t u = v + p.edges.delta[k];
    const uint64_t du = words[u];
    if (du == unreached) continue;
    const T w = edge_weight(p, k, p.field[u], fv);
    if (distance_word(extend(word_distance<T>(du), w)) != dv) continue;
    const std::uint32_t lu = label_at(u);
    if (lu < best) best = lu;
  }
  return best;
}

// ---- insert-query boxes --------------------------------------------------------------------------

/// Geometry of one query's box.
struct query_box {
  box_axis ax, ay, az;
  GEOVORONOI_HOST_DEVICE int lx() const { return int(ax.len); }
  GEOVORONOI_HOST_DEVICE int ly() const { return int(ay.len); }
  GEOVORONOI_HOST_DEVICE int lz() const { return int(az.len); }
  GEOVORONOI_HOST_DEVICE int used() const { return lx() * ly() * lz(); }
  GEOVORONOI_HOST_DEVICE index_t voxel(const tiling& t, int s) const {
    const int bx = s % lx(), by = (s / lx()) % ly(), bz = s / (lx() * ly());
    return t.voxel(ax.lo + bx, ay.lo + by, az.lo + bz);
  }
  /// Whether slot s lies on a face with grid beyond it.
  GEOVORONOI_HOST_DEVICE bool open(const tiling& t, int s) const {
    const int bx = s % lx(), by = (s / lx()) % ly(), bz = s / (lx() * ly());
    return open_face(ax, bx, t.nx) || open_face(ay, by, t.ny) || open_face(az, bz, t.nz);
  }
};
template <int Dim>
GEOVORONOI_HOST_DEVICE inline query_box box_around(const tiling& t, index_t q) {
  using B = query_box_shape<Dim>;
  const index_t qx = q % t.nx, qr = q / t.nx, qy = qr % t.ny, qz = qr / t.ny;
  return {place_box(qx, t.nx, B::bx), place_box(qy, t.ny, B::by), place_box(qz, t.nz, B::bz)};
}

/// Best distance word of box slot @p s (in the domain, below the diagram's distance) from its box
/// neighbours; @p current if none is better.
template <class P, class Words>
GEOVORONOI_HOST_DEVICE inline uint64_t box_pull(const P& p, const tiling& t, const query_box& b, const Words* sw,
                                                const typename P::value_type* old, int s, uint64_t current) {
  using T = typename P::value_type;
  const int lx = b.lx(), ly = b.ly(), lz = b.lz();
  const int bx = s % lx, by = (s / lx) % ly, bz = s / (lx * ly);
  const index_t v = t.voxel(b.ax.lo + bx, b.ay.lo + by, b.az.lo + bz);
  const T fv = p.field[v];
  if (!in_domain<P>(fv)) return current;
  const T dold = old[v];
  uint64_t best = current;
  const cut_mask_t cut = p.cut_mask(v);
  for (int k = 0; k < P::neighbours; ++k) {
    if ((cut >> k) & 1u) continue;
    const int ux = bx + p.edges.offset[k][0], uy = by + p.edges.offset[k][1], uz = bz + p.edges.offset[k][2];
    if (ux < 0 || ux >= lx || uy < 0 || uy >= ly || uz < 0 || uz >= lz) continue;
    const uint64_t su = sw[ux + lx * (uy + ly * uz)];
    if (su == unreached) continue;
    const T w = edge_weight(p, k, p.field[v + p.edges.delta[k]], fv);
    if (!(w >= T(0))) continue;  // the diagram's own solve reports bad weights
    const T nd = extend(word_distance<T>(su), w);
    if (!(nd < dold)) continue;
    const uint64_t c = distance_word(nd);
    if (c < best) best = c;
  }
  return best;
}

}  // namespace detail
}  // namespace geovoronoi::cuda

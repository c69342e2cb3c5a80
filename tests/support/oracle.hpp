#pragma once
// Brute-force references for the tests: Bellman-Ford iteration to the fixed point over packed
// (distance, label) keys, written independently of the solvers' neighbour walking, and random
// problem generators with masks, anisotropic spacing and deliberate ties.

#include <geovoronoi.hpp>

#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace gvtest {

namespace gv = geovoronoi;

/// Exact bit pattern of a float/double, so tests compare bits, not values (catches -0/+0, NaN).
template <class T>
auto bits(T x) {
  if constexpr (sizeof(T) == 4) {
    std::uint32_t b;
    std::memcpy(&b, &x, 4);
    return b;
  } else {
    std::uint64_t b;
    std::memcpy(&b, &x, 8);
    return b;
  }
}

/// Whether the edge from voxel @p v in stencil direction @p k is cut (never, for a problem without
/// cuts). Reads the cut table's plain lookup, not the solvers' walker.
template <class P>
bool cut_edge(const P& p, gv::index_t v, int k) {
  if constexpr (P::has_cuts) return p.cuts.cut(v, k);
  else return false;
}

/// Bellman-Ford oracle: returns (distance, label) for every voxel; cut edges (if the problem has
/// cuts) are not edges.
template <class P>
gv::diagram<typename P::value_type, P::dim> oracle(const P& p, const std::vector<gv::source<typename P::value_type>>& src) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim;
  const auto& g = p.geometry;
  const gv::index_t n = g.size();
  std::vector<T> d(n, std::numeric_limits<T>::infinity());
  std::vector<gv::label_t> l(n, gv::no_label);
  auto better = [](T d1, gv::label_t l1, T d2, gv::label_t l2) { return d1 < d2 || (d1 == d2 && l2 != gv::no_label && l1 < l2) || (d1 == d2 && l2 == gv::no_label); };
  for (const auto& s : src)
    if (better(s.distance, s.label, d[s.voxel], l[s.voxel])) d[s.voxel] = s.distance, l[s.voxel] = s.label;
  constexpr auto offs = gv::connectivity<P::neighbours>::offsets();
  bool changed = true;
  while (changed) {
    changed = false;
    for (gv::index_t v = 0; v < n; ++v) {
      if (!p.inside(v)) continue;
      const auto cv = g.coords(v);
      for (int k = 0; k < P::neighbours; ++k) {
        gv::coord<Dim> cu = cv;
        for (int a = 0; a < Dim; ++a) cu[a] += offs[k][a];
        if (!g.contains(cu)) continue;
        if (cut_edge(p, v, k)) continue;
        const gv::index_t u = g.index(cu);
        if (!p.inside(u) || l[u] == gv::no_label) continue;
        // the edge u -> v has the same length as v -> u
        const T w = p.metric(p.edges.length[k], p.field[u], p.field[v]);
        const T nd = d[u] + w;
        if (better(nd, l[u], d[v], l[v])) {
          d[v] = nd;
          l[v] = l[u];
          changed = true;
        }
      }
    }
  }
  // Bellman-Ford's distances are the unique fixed point, but a label can survive from a proposal made
  // through a neighbour's earlier, larger distance that happened to round to the same sum. The labels
  // the tie rule defines are those realised by final distances only: recompute them from "none",
  // taking at each voxel the smallest label among the sources and neighbours that realise its
  // distance, until nothing changes (the greatest fixed point, which is what Dijkstra produces).
  std::vector<gv::label_t> fin(n, gv::no_label);
  auto lower = [](gv::label_t cand, gv::label_t cur) { return cand != gv::no_label && (cur == gv::no_label || cand < cur); };
  for (const auto& s : src)
    if (s.distance == d[s.voxel] && lower(s.label, fin[s.voxel])) fin[s.voxel] = s.label;
  changed = true;
  while (changed) {
    changed = false;
    for (gv::index_t v = 0; v < n; ++v) {
      if (!p.inside(v) || l[v] == gv::no_label) continue;
      const auto cv = g.coords(v);
      for (int k = 0; k < P::neighbours; ++k) {
        gv::coord<Dim> cu = cv;
        for (int a = 0; a < Dim; ++a) cu[a] += offs[k][a];
        if (!g.contains(cu)) continue;
        if (cut_edge(p, v, k)) continue;
        const gv::index_t u = g.index(cu);
        if (!p.inside(u) || fin[u] == gv::no_label) continue;
        const T w = p.metric(p.edges.length[k], p.field[u], p.field[v]);
        const T nd = d[u] + w;
        if (nd == d[v] && lower(fin[u], fin[v])) {
          fin[v] = fin[u];
          changed = true;
        }
      }
    }
  }
  l = std::move(fin);
  gv::diagram<T, Dim> r;
  r.distance = gv::image<T, Dim>(g, std::move(d));
  r.label = gv::image<gv::label_t, Dim>(g, std::move(l));
  return r;
}

/// A user-defined metric (asymmetric on purpose: it charges the destination's cost).
struct destination_cost {
  template <class T>
  GEOVORONOI_HOST_DEVICE T operator()(T length, T, T to) const noexcept {
    return length * to;
  }
  template <class T>
  GEOVORONOI_HOST_DEVICE static bool inside(T v) noexcept {
    return v > T(0) && v < T(100);
  }
};

/// Random small grid with random extents (1-thick slabs included) and spacing.
template <int Dim>
gv::grid<Dim> random_grid(std::mt19937_64& rng, bool anisotropic) {
  gv::coord<Dim> e{};
  gv::point<Dim> s{};
  std::uniform_int_distribution<int> ext(1, Dim == 2 ? 14 : 8);
  std::uniform_real_distribution<double> sp(0.3, 2.0);
  for (int a = 0; a < Dim; ++a) {
    e[a] = ext(rng);
    s[a] = anisotropic ? sp(rng) : 1.0;
  }
  return gv::grid<Dim>(e, s, {});
}

/// Random field: with `ties` the values come from {1, 2, 4} (exact ties everywhere), else continuous;
/// about `mask` of the voxels masked out (value 0, or -1 for costs, or NaN).
template <class T>
std::vector<T> random_field(std::mt19937_64& rng, gv::index_t n, bool ties, double mask, bool cost) {
  std::vector<T> f(n);
  std::uniform_real_distribution<double> u(0, 1);
  const T levels[] = {T(1), T(2), T(4)};
  for (auto& x : f) {
    const double r = u(rng);
    if (r < mask) {
      x = r < mask / 3 ? std::numeric_limits<T>::quiet_NaN() : (cost ? T(-1) : T(0));
      if (cost && r >= mask / 3 && r < 2 * mask / 3) x = std::numeric_limits<T>::infinity();
    } else
      x = ties ? levels[rng() % 3] : T(0.25 + 4 * u(rng));
  }
  return f;
}

/// A random set of cut edges of grid @p g under connectivity<N>: each edge cut with probability
/// @p prob.
template <int Dim, int N>
gv::cut_set<Dim> random_cuts(std::mt19937_64& rng, const gv::grid<Dim>& g, gv::connectivity<N> c, double prob) {
  gv::cut_builder<Dim> b(g, c);
  std::uniform_real_distribution<double> u(0, 1);
  constexpr auto offs = gv::connectivity<N>::offsets();
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto cv = g.coords(v);
    for (int d = N / 2; d < N; ++d) {
      auto cu = cv;
      for (int a = 0; a < Dim; ++a) cu[a] += offs[d][a];
      if (g.contains(cu) && u(rng) < prob) b.insert(v, d);
    }
  }
  return b.build();
}

/// Up to `k` distinct unmasked voxels, as seeds (coordinates); empty if the domain is empty.
template <class P>
std::vector<gv::coord<P::dim>> random_seeds(std::mt19937_64& rng, const P& p, int k) {
  std::vector<gv::index_t> in;
  for (gv::index_t v = 0; v < p.geometry.size(); ++v)
    if (p.inside(v)) in.push_back(v);
  std::shuffle(in.begin(), in.end(), rng);
  std::vector<gv::coord<P::dim>> s;
  for (int i = 0; i < k && i < int(in.size()); ++i) s.push_back(p.geometry.coords(in[i]));
  return s;
}

template <class P>
std::vector<gv::source<typename P::value_type>> as_sources(const P& p, const std::vector<gv::coord<P::dim>>& s) {
  std::vector<gv::source<typename P::value_type>> out;
  for (std::size_t i = 0; i < s.size(); ++i) out.push_back({p.geometry.index(s[i]), typename P::value_type(0), gv::label_t(i)});
  return out;
}

}  // namespace gvtest

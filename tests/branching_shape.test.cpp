// Tests of geovoronoi/branching_shape.hpp: every copy's Distance Ratio, Sibson and Laplace row against
// brute-force oracles written from the definitions on the explicit copy graph (the grid's public CSR,
// plain Dijkstra); factor 1 against the regular grid's shape functions bit for bit; the fingers
// phantom (a fingertip's weights stay off the neighbouring finger); rows at fine voxels and world
// points; paint_fine; a cut narrower than a coarse cell that splits a copy; the update after a cut
// against a full recompute bit for bit; seq against Thrust on OpenMP bit for bit.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/branching_shape.hpp>

#include "support/core_helpers.hpp"

#ifdef GEOVORONOI_TEST_WITH_THRUST
#include <geovoronoi/backend/thrust.hpp>
#include <thrust/system/omp/execution_policy.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <queue>
#include <random>
#include <set>
#include <utility>
#include <vector>

namespace {
namespace gv = geovoronoi;
constexpr int N = 6;  // one connectivity for the whole suite (one instantiation)
using bgrid = gv::branching_grid<3, float, N>;
using bproblem = gv::branching_problem<float, 3, gv::min_stiffness, N>;
constexpr float inf = std::numeric_limits<float>::infinity();

gv::image<float, 3> random_image(std::mt19937_64& rng, const gv::coord<3>& n, double empty) {
  gv::image<float, 3> f{gv::grid<3>(n, {1.0, 1.5, 0.75}, {2.0, -1.0, 0.5})};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& x : f) x = u(rng) < empty ? 0.0f : float(0.5 + 3.5 * u(rng));
  return f;
}

/// Seeds: @p count fine voxels of distinct copies, drawn at random.
std::vector<gv::coord<3>> random_seeds(std::mt19937_64& rng, const bgrid& bg, int count) {
  std::vector<gv::coord<3>> out;
  std::set<gv::index_t> used;
  std::uniform_int_distribution<gv::index_t> pick(0, bg.fine().size() - 1);
  while (int(out.size()) < count) {
    const gv::index_t v = pick(rng);
    const gv::index_t c = bg.fine_copy()[v];
    if (c < 0 || !used.insert(c).second) continue;
    out.push_back(bg.fine().coords(v));
  }
  return out;
}

// ---- the oracle: the copy graph from the public CSR, plain Dijkstra, the definitions ----------------

struct oracle {
  const bgrid& bg;
  gv::stencil<float, 3, N> st;
  std::vector<int> face_axis;  // per coarse direction, -1 when not a face
  double area[3];
  explicit oracle(const bgrid& g) : bg(g), st(g.coarse(), gv::connectivity<N>{}), face_axis(N, -1) {
    for (int k = 0; k < N; ++k) {
      int nz = 0, axis = -1;
      for (int a = 0; a < 3; ++a)
        if (st.offset[k][a] != 0) ++nz, axis = a;
      if (nz == 1) face_axis[std::size_t(k)] = axis;
    }
    for (int a = 0; a < 3; ++a) {
      area[a] = 1;
      for (int b = 0; b < 3; ++b)
        if (b != a) area[a] *= bg.coarse().spacing(b);
    }
  }
  float w(gv::index_t a, gv::index_t b, int k) const {
    return gv::min_stiffness{}(st.length[k], bg.stiffness()[std::size_t(a)], bg.stiffness()[std::size_t(b)]);
  }
  template <class F>
  void links(gv::index_t a, F&& f) const {
    for (gv::index_t i = bg.link_begin()[std::size_t(a)]; i < bg.link_begin()[std::size_t(a) + 1]; ++i)
      f(bg.link_copy()[std::size_t(i)], int(bg.link_dir()[std::size_t(i)]));
  }
  /// Distances from sources (copy, initial distance), every copy.
  std::vector<float> dijkstra(const std::vector<std::pair<gv::index_t, float>>& src) const {
    std::vector<float> d(std::size_t(bg.copies()), inf);
    using item = std::pair<float, gv::index_t>;
    std::priority_queue<item, std::vector<item>, std::greater<item>> q;
    for (auto [c, x] : src)
      if (x < d[std::size_t(c)]) d[std::size_t(c)] = x, q.push({x, c});
    while (!q.empty()) {
      const float x = q.top().first;
      const gv::index_t a = q.top().second;
      q.pop();
      if (x != d[std::size_t(a)]) continue;
      links(a, [&](gv::index_t b, int k) {
        const float nd = x + w(a, b, k);
        if (nd < d[std::size_t(b)]) d[std::size_t(b)] = nd, q.push({nd, b});
      });
    }
    return d;
  }
  /// A row from raw weights: the K heaviest (ties to the lower node), normalised.
  static std::vector<std::pair<gv::label_t, double>> row(std::map<gv::label_t, double> raw, int K) {
    std::vector<std::pair<gv::label_t, double>> r;
    for (auto [n, x] : raw)
      if (x > 0) r.push_back({n, x});
    std::sort(r.begin(), r.end(), [](auto a, auto b) { return a.second > b.second || (a.second == b.second && a.first < b.first); });
    if (int(r.size()) > K) r.resize(std::size_t(K));
    double s = 0;
    for (auto& e : r) s += e.second;
    for (auto& e : r) e.second /= s;
    return r;
  }
  /// Sibson (laplace false) or Laplace row of copy q by the definitions.
  std::vector<std::pair<gv::label_t, double>> natural(const gv::node_diagram<float>& d, gv::index_t q, bool laplace,
                                                       int K) const {
    if (d.label[std::size_t(q)] < 0) return {};
    if (d.distance[std::size_t(q)] == 0) return {{d.label[std::size_t(q)], 1.0}};
    const auto dq = dijkstra({{q, 0.0f}});
    std::vector<char> in(std::size_t(bg.copies()), 0);
    std::map<gv::label_t, double> vol, s, h;
    for (gv::index_t v = 0; v < bg.copies(); ++v)
      if (dq[std::size_t(v)] < d.distance[std::size_t(v)]) {
        in[std::size_t(v)] = 1;
        if (d.label[std::size_t(v)] >= 0)
          vol[d.label[std::size_t(v)]] += double(bg.voxel_count()[std::size_t(v)]) * bg.fine().voxel_volume();
      }
    if (!laplace) return row(vol, K);
    for (gv::index_t v = 0; v < bg.copies(); ++v) {
      if (!in[std::size_t(v)]) continue;
      links(v, [&](gv::index_t u, int k) {
        const int axis = face_axis[std::size_t(k)];
        const gv::label_t l = d.label[std::size_t(u)];
        if (axis < 0 || in[std::size_t(u)] || l < 0) return;
        s[l] += area[axis];
        const double hh = double((dq[std::size_t(v)] + w(v, u, k)) + d.distance[std::size_t(u)]);
        h[l] = h.count(l) ? std::min(h[l], hh) : hh;
      });
    }
    if (s.empty()) return row(vol, K);
    std::map<gv::label_t, double> raw;
    for (auto [l, x] : s) raw[l] = x / h[l];
    return row(raw, K);
  }
  /// Distance Ratio rows of every copy by the definition (docs/shape-functions.md on copies).
  std::vector<std::vector<std::pair<gv::label_t, double>>> distance_ratio(const gv::node_diagram<float>& d, int K) const {
    const auto n = std::size_t(bg.copies());
    std::vector<std::map<gv::label_t, double>> raw(n);
    for (std::size_t i = 0; i < d.seeds.size(); ++i) {
      const auto li = gv::label_t(i);
      float dmax = 0;
      for (gv::index_t x = 0; x < bg.copies(); ++x) {
        if (d.label[std::size_t(x)] != li) continue;
        dmax = std::max(dmax, d.distance[std::size_t(x)]);
        links(x, [&](gv::index_t y, int k) {
          const gv::label_t ly = d.label[std::size_t(y)];
          if (face_axis[std::size_t(k)] >= 0 && ly >= 0 && ly != li) dmax = std::max(dmax, d.distance[std::size_t(y)]);
        });
      }
      if (!(dmax > 0)) {
        raw[std::size_t(d.seeds[i])][li] = 1;
        continue;
      }
      const auto di = dijkstra({{d.seeds[i], 0.0f}});
      auto di_at = [&](gv::index_t v) { return di[std::size_t(v)] < 2 * dmax ? di[std::size_t(v)] : inf; };
      std::map<gv::index_t, float> src;
      auto add = [&](gv::index_t v, float x) {
        if (x < dmax) src[v] = src.count(v) ? std::min(src[v], x) : x;
      };
      for (gv::index_t x = 0; x < bg.copies(); ++x) {
        if (d.label[std::size_t(x)] != li) continue;
        links(x, [&](gv::index_t y, int k) {
          const gv::label_t ly = d.label[std::size_t(y)];
          if (face_axis[std::size_t(k)] < 0 || ly < 0 || ly == li || !(di_at(y) < inf)) return;
          const float diy = di_at(y), dy = d.distance[std::size_t(y)], dx = d.distance[std::size_t(x)];
          add(y, 0.5f * (diy - dy));
          add(x, std::max(0.0f, 0.5f * (dy + diy) - dx));
        });
      }
      std::vector<std::pair<gv::index_t, float>> s(src.begin(), src.end());
      const auto db = s.empty() ? std::vector<float>(n, inf) : dijkstra(s);
      for (gv::index_t v = 0; v < bg.copies(); ++v) {
        const float dp = di_at(v);
        if (!(dp < inf)) continue;
        const double b = db[std::size_t(v)] < dmax ? double(db[std::size_t(v)]) : double(dmax);
        double wv;
        if (dp == 0) wv = 1;
        else if (d.label[std::size_t(v)] == li) wv = 0.5 * (1 + b / (double(dp) + b));
        else wv = double(dp) <= b ? 0 : std::max(0.0, 0.5 * (1 - b / (double(dp) - b)));
        if (wv > 0) raw[std::size_t(v)][li] = wv;
      }
    }
    std::vector<std::vector<std::pair<gv::label_t, double>>> out(n);
    for (std::size_t v = 0; v < n; ++v) {
      if (d.label[v] < 0) continue;
      out[v] = d.distance[v] == 0 ? std::vector<std::pair<gv::label_t, double>>{{d.label[v], 1.0}} : row(raw[v], K);
    }
    return out;
  }
};

void check_row(const gv::copy_weights<float>& w, gv::index_t c, const std::vector<std::pair<gv::label_t, double>>& want) {
  for (int s = 0; s < w.k; ++s) {
    const std::size_t at = std::size_t(c) * std::size_t(w.k) + std::size_t(s);
    if (std::size_t(s) < want.size()) {
      CHECK(w.node[at] == want[std::size_t(s)].first);
      CHECK(std::abs(double(w.weight[at]) - want[std::size_t(s)].second) < 1e-5);
    } else {
      CHECK(w.node[at] == gv::no_label);
    }
  }
}

bool same_bits(const gv::copy_weights<float>& a, const gv::copy_weights<float>& b) {
  return a.copies == b.copies && a.k == b.k && a.nodes == b.nodes && a.node == b.node &&
         std::memcmp(a.weight.data(), b.weight.data(), a.weight.size() * sizeof(float)) == 0 &&
         a.weight.size() == b.weight.size();
}

bool same_bits(const gv::node_diagram<float>& a, const gv::node_diagram<float>& b) {
  return a.label == b.label && a.parent == b.parent && a.seeds == b.seeds && a.distance.size() == b.distance.size() &&
         std::memcmp(a.distance.data(), b.distance.data(), a.distance.size() * sizeof(float)) == 0;
}

gv::shape_options with(gv::shape_method m, int k = 4) {
  gv::shape_options o;
  o.method = m;
  o.max_nodes_per_voxel = k;
  return o;
}


/// The direction of offset (1, 0, 0) in connectivity<N>.
int plus_x() {
  constexpr auto offs = gv::connectivity<N>::offsets();
  for (int k = 0; k < N; ++k)
    if (offs[k][0] == 1 && offs[k][1] == 0 && offs[k][2] == 0) return k;
  return -1;
}

/// A blade: the fine edges from x to x + 1 for y in [y0, y1) and every z.
gv::cut_set<3> blade(const gv::grid<3>& g, gv::index_t x, gv::index_t y0, gv::index_t y1) {
  gv::cut_set<3> c(g, gv::connectivity<N>{});
  for (gv::index_t z = 0; z < g.extent(2); ++z)
    for (gv::index_t y = y0; y < y1; ++y) c.insert(g.index({x, y, z}), plus_x());
  return c;
}

const gv::shape_method methods[] = {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace};

}  // namespace

TEST_CASE("branching shape functions: every copy's row against the oracles on random fine images") {
  std::mt19937_64 rng(2026);
  for (int trial = 0; trial < 3; ++trial) {
    const auto f = random_image(rng, {10, 9, 4}, 0.3);
    const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<N>{});
    const auto p = gv::make_problem(bg, gv::min_stiffness{});
    const auto seeds = random_seeds(rng, bg, 5);
    const auto d = gv::voronoi(gv::seq, p, seeds);
    const oracle o(bg);
    const int K = 3;  // fewer than the nodes: the K largest are kept
    for (auto m : methods) {
      CAPTURE(int(m));
      const auto w = gv::shape_functions(gv::seq, p, d, with(m, K));
      REQUIRE(w.copies == bg.copies());
      if (m == gv::shape_method::distance_ratio) {
        const auto want = o.distance_ratio(d, K);
        for (gv::index_t c = 0; c < bg.copies(); ++c) check_row(w, c, want[std::size_t(c)]);
      } else {
        for (gv::index_t c = 0; c < bg.copies(); ++c)
          check_row(w, c, o.natural(d, c, m == gv::shape_method::laplace, K));
      }
      // partition of unity where reached, the sparse matrix and interpolation agree
      const auto sm = w.to_sparse_matrix();
      Eigen::MatrixXf ones = Eigen::MatrixXf::Ones(Eigen::Index(w.nodes), 1);
      const auto u = gv::interpolate(w, ones);
      for (gv::index_t c = 0; c < bg.copies(); ++c) {
        const bool reached = d.label[std::size_t(c)] >= 0;
        CHECK(std::abs(u(Eigen::Index(c), 0) - (reached ? 1.0f : 0.0f)) < 1e-5f);
        CHECK(std::abs(sm.row(Eigen::Index(c)).sum() - (reached ? 1.0f : 0.0f)) < 1e-5f);
      }
    }
  }
}

TEST_CASE("branching shape functions: factor 1 gives the regular grid's weights bit for bit") {
  std::mt19937_64 rng(7);
  const auto f = random_image(rng, {9, 7, 4}, 0.2);
  const auto bg = gv::make_branching_grid(f, 1, gv::connectivity<N>{});
  const auto bp = gv::make_problem(bg, gv::min_stiffness{});
  const auto rp = gv::make_problem(f.geometry(), f, gv::min_stiffness{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, bg, 4);
  const auto bd = gv::voronoi(gv::seq, bp, seeds);
  const auto rd = gv::voronoi(gv::seq, rp, seeds);
  for (auto m : methods) {
    CAPTURE(int(m));
    const auto bw = gv::shape_functions(gv::seq, bp, bd, with(m, 3));
    const auto rw = gv::shape_functions(gv::seq, rp, rd, with(m, 3));
    const auto painted = gv::paint_fine(bg, bw);
    CHECK(painted.node == rw.node);
    CHECK(std::memcmp(painted.weight.data(), rw.weight.data(), rw.weight.size() * sizeof(float)) == 0);
  }
}

TEST_CASE("branching shape functions: a fingertip's weights do not leak to the neighbouring finger") {
  // fingers 6 voxels wide, one-voxel gaps at x = 6, 13, 20; a factor of 4 puts both sides of a gap
  // in one coarse cell
  const gv::grid<3> g({27, 24, 2});
  const auto f = gv::phantom::fingers(g, 4, 1);
  const auto bg = gv::make_branching_grid(f, 4, gv::connectivity<N>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<3>>{{2, 22, 0}, {9, 22, 0}, {16, 2, 0}});
  for (auto m : methods) {
    CAPTURE(int(m));
    const auto w = gv::paint_fine(bg, gv::shape_functions(gv::seq, p, d, with(m, 3)));
    auto weight_of = [&](gv::index_t v, gv::label_t node) {
      for (int s = 0; s < w.k; ++s)
        if (w.node[std::size_t(v) * 3 + std::size_t(s)] == node) return w.weight[std::size_t(v) * 3 + std::size_t(s)];
      return 0.0f;
    };
    // node 0 (the first fingertip) on the second finger's upper half, node 1 on the first finger's
    // (lower down, a query's new cell reaches into the palm, where it meets the other fingertip's cell,
    // and a Distance Ratio support, d < 2 d_max, reaches up the other finger: paths through the palm,
    // not across the gap; the rows of the tips' coarse cells have none)
    for (gv::index_t y = 20; y < 24; ++y)
      for (gv::index_t x = 0; x < 6; ++x) {
        CHECK(weight_of(g.index({x + 7, y, 0}), 0) == 0.0f);
        CHECK(weight_of(g.index({x, y, 0}), 1) == 0.0f);
      }
    CHECK(weight_of(g.index({2, 22, 0}), 0) == 1.0f);
  }
  // the regular coarse grid glues the fingers: node 0 reaches the second finger there
  gv::image<float, 3> coarse(bg.coarse(), 0.0f);
  for (gv::index_t c = 0; c < bg.copies(); ++c) coarse[bg.copy_cell()[std::size_t(c)]] = 1.0f;
  const auto rp = gv::make_problem(coarse.geometry(), coarse, gv::min_stiffness{}, gv::connectivity<N>{});
  const auto rd = gv::voronoi(gv::seq, rp, std::vector<gv::coord<3>>{{0, 5, 0}, {2, 5, 0}, {4, 0, 0}});
  const auto rw = gv::shape_functions(gv::seq, rp, rd, with(gv::shape_method::sibson, 3));
  bool leaks = false;
  const gv::index_t v = coarse.geometry().index({1, 5, 0});  // the cell holding both fingers' tips
  for (int s = 0; s < 3; ++s) leaks = leaks || (rw.node[std::size_t(v) * 3 + std::size_t(s)] == 0);
  CHECK(leaks);
}

TEST_CASE("branching shape functions: rows at fine voxels and world points are the copies' rows") {
  std::mt19937_64 rng(11);
  const auto f = random_image(rng, {8, 8, 4}, 0.3);
  const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<N>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, bg, 4));
  std::vector<gv::coord<3>> pts;
  std::vector<gv::point<3>> world;
  for (gv::index_t v = 0; v < bg.fine().size(); v += 3) {
    pts.push_back(bg.fine().coords(v));
    world.push_back(bg.fine().world(pts.back()));
  }
  pts.push_back(pts.front());  // a repeat
  world.push_back(world.front());
  for (auto m : methods) {
    CAPTURE(int(m));
    const auto w = gv::shape_functions(gv::seq, p, d, with(m, 3));
    const auto at = gv::shape_functions_at(gv::seq, p, d, pts, with(m, 3));
    const auto atw = gv::shape_functions_at(gv::seq, p, d, world, with(m, 3));
    REQUIRE(at.points == pts.size());
    CHECK(at.node == atw.node);
    CHECK(at.weight == atw.weight);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      CHECK(at.voxel[i] == bg.fine().index(pts[i]));
      const gv::index_t c = bg.fine_copy()[at.voxel[i]];
      for (int s = 0; s < 3; ++s) {
        const std::size_t a = i * 3 + std::size_t(s);
        if (c < 0) {
          CHECK(at.node[a] == gv::no_label);
        } else {
          CHECK(at.node[a] == w.node[std::size_t(c) * 3 + std::size_t(s)]);
          CHECK(std::memcmp(&at.weight[a], &w.weight[std::size_t(c) * 3 + std::size_t(s)], sizeof(float)) == 0);
        }
      }
    }
  }
  GV_CHECK_INVALID(gv::shape_functions_at(gv::seq, p, d, std::vector<gv::coord<3>>{{0, 0, 0}, {8, 0, 0}}),
                   "point 1", "outside the fine grid");
  GV_CHECK_INVALID(gv::shape_functions_at(gv::seq, p, d, std::vector<gv::point<3>>{{1e9, 0.0, 0.0}}), "point 0");
  gv::copy_weights<float> wrong;
  GV_CHECK_INVALID(gv::paint_fine(bg, wrong), "copies");
}


TEST_CASE("branching grids with a cut: a blade narrower than a coarse cell splits its copy") {
  const gv::grid<3> g({16, 8, 2});
  const gv::image<float, 3> f(g, 1.0f);
  // the blade between fine x = 5 and 6, inside coarse column 1 (fine x 4..7), over rows 0..5 of 8
  const auto c = blade(g, 5, 0, 6);
  const auto bg = gv::make_branching_grid(f, 4, gv::connectivity<N>{});
  const auto cut = gv::make_branching_grid(f, 4, gv::connectivity<N>{}, c);
  const gv::index_t cell = bg.coarse().index({1, 0, 0});
  CHECK(bg.cell_begin()[std::size_t(cell) + 1] - bg.cell_begin()[std::size_t(cell)] == 1);
  REQUIRE(cut.cell_begin()[std::size_t(cell) + 1] - cut.cell_begin()[std::size_t(cell)] == 2);
  const gv::index_t left = cut.fine_copy()({5, 1, 0}), right = cut.fine_copy()({6, 1, 0});
  CHECK(left != right);
  CHECK(bg.fine_copy()({5, 1, 0}) == bg.fine_copy()({6, 1, 0}));
  CHECK(cut.voxel_count()[std::size_t(left)] == 16);  // x 4..5, y 0..3, z 0..1
  // the two lips: the path between them goes around the blade's end, through the row above
  const auto p0 = gv::make_problem(bg, gv::min_stiffness{});
  const auto p1 = gv::make_problem(cut, gv::min_stiffness{});
  const std::vector<gv::coord<3>> seeds{{5, 1, 0}, {15, 7, 1}};
  const auto d0 = gv::voronoi(gv::seq, p0, seeds);
  const auto d1 = gv::voronoi(gv::seq, p1, seeds);
  CHECK(d0.distance[std::size_t(bg.fine_copy()({6, 1, 0}))] == 0.0f);
  CHECK(d1.distance[std::size_t(right)] > 3.0f);
  // and the weights of the left lip's node drop on the right lip
  const auto w1 = gv::shape_functions(gv::seq, p1, d1, with(gv::shape_method::sibson, 2));
  CHECK(w1.node[std::size_t(left) * 2] == 0);
  CHECK(w1.weight[std::size_t(left) * 2] == 1.0f);
  CHECK(w1.weight[std::size_t(right) * 2] < 1.0f);
  GV_CHECK_INVALID(gv::make_branching_grid(f, 4, gv::connectivity<N>{}, gv::cut_set<3>(gv::grid<3>({4, 4, 4}), gv::connectivity<N>{})),
                   "another grid");
}

TEST_CASE("branching grids with a cut: the updates equal a full recompute bit for bit") {
  std::mt19937_64 rng(99);
  for (int trial = 0; trial < 3; ++trial) {
    const auto f = random_image(rng, {12, 10, 4}, 0.15);
    const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<N>{});
    const auto p = gv::make_problem(bg, gv::min_stiffness{});
    const auto seeds = random_seeds(rng, bg, 5);
    gv::solve_options so;
    so.with_parent = true;
    const auto d = gv::voronoi(gv::seq, p, seeds, so);
    // two blades, one after the other, each inside a coarse column
    auto c1 = blade(f.geometry(), 4, 1, 7);
    const auto g1 = gv::make_branching_grid(f, 2, gv::connectivity<N>{}, c1);
    auto c2 = c1;
    c2.merge(blade(f.geometry(), 8, 3, 10));
    const auto g2 = gv::make_branching_grid(f, 2, gv::connectivity<N>{}, c2);
    const auto p1 = gv::make_problem(g1, gv::min_stiffness{});
    const auto p2 = gv::make_problem(g2, gv::min_stiffness{});
    gv::node_diagram<float> full1, full2;
    try {
      full1 = gv::voronoi(gv::seq, p1, seeds, so);
      full2 = gv::voronoi(gv::seq, p2, seeds, so);
    } catch (const std::invalid_argument&) {
      continue;  // a seed whose copy the cut moved out of the metric's domain: not this test's case
    }
    gv::update_stats st;
    const auto u1 = gv::update(gv::seq, p1, bg, d, seeds, &st);
    CHECK(same_bits(u1, full1));
    CHECK(st.settled < std::size_t(g1.copies()));
    if (trial == 0) {
      GV_CHECK_INVALID(gv::update(gv::seq, p1, bg, gv::voronoi(gv::seq, p, seeds), seeds), "no parents");
      auto other = seeds;
      std::swap(other[0], other[1]);
      GV_CHECK_INVALID(gv::update(gv::seq, p1, bg, d, other), "not the diagram's seed");
    }
    const auto u2 = gv::update(gv::seq, p2, g1, u1, seeds);
    CHECK(same_bits(u2, full2));
    for (auto m : methods) {
      CAPTURE(int(m));
      auto o = with(m, 3);
      o.keep_update_state = true;
      const auto w0 = gv::shape_functions(gv::seq, p, d, o);
      const auto w1 = gv::update_shape_functions(gv::seq, p1, bg, d, u1, w0, o);
      CHECK(same_bits(w1, gv::shape_functions(gv::seq, p1, full1, o)));
      const auto w2 = gv::update_shape_functions(gv::seq, p2, g1, u1, u2, w1, o);
      CHECK(same_bits(w2, gv::shape_functions(gv::seq, p2, full2, o)));
      if (m == gv::shape_method::distance_ratio) CHECK(w2.update_state != nullptr);
    }
  }
}

#ifdef GEOVORONOI_TEST_WITH_THRUST
TEST_CASE("branching shape functions: seq and Thrust on OpenMP give the same bits") {
  std::mt19937_64 rng(5);
  const auto f = random_image(rng, {16, 12, 6}, 0.25);
  const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<N>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, bg, 6));
  const auto omp = gv::thrust::par_on(::thrust::omp::par);
  for (auto m : methods) {
    CAPTURE(int(m));
    auto o = with(m, 4);
    o.threads = 2;
    CHECK(same_bits(gv::shape_functions(gv::seq, p, d, o), gv::shape_functions(omp, p, d, o)));
    std::vector<gv::coord<3>> pts{{0, 0, 0}, {5, 7, 3}, {15, 11, 5}};
    const auto a = gv::shape_functions_at(gv::seq, p, d, pts, o), b = gv::shape_functions_at(omp, p, d, pts, o);
    CHECK(a.node == b.node);
    CHECK(a.weight == b.weight);
  }
  // the update after a cut, with the kept state
  gv::solve_options so;
  so.with_parent = true;
  const auto seeds = random_seeds(rng, bg, 4);
  const auto dp = gv::voronoi(gv::seq, p, seeds, so);
  const auto cg = gv::make_branching_grid(f, 2, gv::connectivity<N>{}, blade(f.geometry(), 6, 0, 8));
  const auto pc = gv::make_problem(cg, gv::min_stiffness{});
  auto o = with(gv::shape_method::distance_ratio, 4);
  o.keep_update_state = true;
  const auto w0 = gv::shape_functions(omp, p, dp, o);
  const auto u = gv::update(omp, pc, bg, dp, seeds);
  CHECK(same_bits(u, gv::update(gv::seq, pc, bg, dp, seeds)));
  CHECK(same_bits(gv::update_shape_functions(omp, pc, bg, dp, u, w0, o),
                  gv::update_shape_functions(gv::seq, pc, bg, dp, u, w0, o)));
}
#endif

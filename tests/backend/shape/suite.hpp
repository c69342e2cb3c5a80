// The shape-function test suite, written once. A test file defines
//   GEOVORONOI_SHAPE_BACKEND_NAME  "seq", "thrust_omp", ...
//   GEOVORONOI_SHAPE_POLICY()      an expression yielding the policy object
// and includes this file. Sibson and Laplace are compared, weight for weight and bit for bit, against a
// brute-force definition that rebuilds the whole diagram with the query added as an extra seed
// (voronoi(seq, ...) on n + 1 seeds) and counts stolen voxels, facet faces and path lengths directly.
// Every backend other than seq is also compared bit for bit with seq.

#include <doctest/doctest.h>

#include "support/oracle.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

namespace gvshape {
namespace gv = geovoronoi;
using namespace gvtest;

inline const char* method_name(gv::shape_method m) {
  return m == gv::shape_method::sibson ? "sibson" : m == gv::shape_method::laplace ? "laplace" : "distance_ratio";
}

template <class P>
auto compute(const P& p, const gv::diagram<typename P::value_type, P::dim>& d, gv::shape_method m, int k,
             std::size_t batch = 4096) {
  gv::shape_options o;
  o.method = m;
  o.max_nodes_per_voxel = k;
  o.batch_size = batch;
  return gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
}

/// The diagrams of @p seeds plus one query voxel, solved once per voxel (on first use) and kept, so that
/// the brute-force rows of every method and K at that voxel share one solve.
template <class P>
class inserted_diagrams {
 public:
  using diagram_type = gv::diagram<typename P::value_type, P::dim>;
  inserted_diagrams(const P& p, const std::vector<gv::coord<P::dim>>& seeds)
      : p_(p), seeds_(seeds), solved_(std::size_t(p.geometry.size())) {}
  const diagram_type& operator()(gv::index_t q) {
    auto& slot = solved_[std::size_t(q)];
    if (!slot) {
      auto with_q = seeds_;
      with_q.push_back(p_.geometry.coords(q));
      slot = std::make_unique<diagram_type>(gv::voronoi(gv::seq, p_, with_q));
    }
    return *slot;
  }
  const std::vector<gv::coord<P::dim>>& seeds() const { return seeds_; }

 private:
  const P& p_;
  std::vector<gv::coord<P::dim>> seeds_;
  std::vector<std::unique_ptr<diagram_type>> solved_;
};

/// Slot arrays of one voxel by the brute-force definition (same arithmetic as the library: raw weights
/// in double, K heaviest by (raw desc, node asc), sum in slot order, raw / sum rounded to T).
/// @p inserted holds the diagram with the query added as an extra seed (voronoi(seq, ...) on n + 1 seeds).
template <class P>
std::vector<std::pair<gv::label_t, typename P::value_type>> brute_force(
    const P& p, const gv::diagram<typename P::value_type, P::dim>& d, inserted_diagrams<P>& inserted,
    gv::index_t q, bool laplace, int k) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim;
  const auto& g = p.geometry;
  const auto& seeds = inserted.seeds();
  std::vector<std::pair<gv::label_t, T>> out;
  if (d.label[q] == gv::no_label) return out;
  if (d.distance[q] == T(0)) return {{d.label[q], T(1)}};
  const auto& d2 = inserted(q);
  const gv::label_t qn = gv::label_t(seeds.size());
  const std::size_t n = seeds.size();
  std::vector<long> volume(n, 0), faces(n * 3, 0);
  std::vector<double> h(n, std::numeric_limits<double>::infinity());
  bool facet = false;
  // C_q = {v : d_q(v) < d(v)}. In the rebuilt diagram d2.distance = min(d, d_q), so that is d2 < d; the
  // label alone is not enough: a voxel with d_q(v) == d(v) whose every shortest path runs through the new
  // cell carries the query's label in the rebuilt diagram without being strictly closer to it.
  auto in_cell = [&](gv::index_t v) { return d2.label[v] == qn && d2.distance[v] < d.distance[v]; };
  for (gv::index_t v = 0; v < g.size(); ++v) {
    if (!in_cell(v)) continue;
    REQUIRE(d.label[v] >= 0);
    ++volume[std::size_t(d.label[v])];
    if (!laplace) continue;
    for (int a = 0; a < Dim; ++a)
      for (int dir = -1; dir <= 1; dir += 2) {
        auto c = g.coords(v);
        c[a] += dir;
        if (!g.contains(c)) continue;
        const gv::index_t w = g.index(c);
        if (!p.inside(w) || d.label[w] == gv::no_label || in_cell(w)) continue;
        int edge = -1;
        for (int e = 0; e < P::neighbours; ++e) {
          bool match = true;
          for (int b = 0; b < 3; ++b) match = match && p.edges.offset[e][b] == (b == a ? dir : 0);
          if (match) edge = e;
        }
        REQUIRE(edge >= 0);
        if (cut_edge(p, v, edge)) continue;  // a cut face is no facet
        const std::size_t kk = std::size_t(d.label[w]);
        ++faces[kk * 3 + std::size_t(a)];
        facet = true;
        T path = d2.distance[v] + p.metric(p.edges.length[edge], p.field[v], p.field[w]);
        path = path + d.distance[w];
        h[kk] = std::min(h[kk], double(path));
      }
  }
  struct c_t {
    gv::label_t node;
    double raw;
  };
  std::vector<c_t> c;
  for (std::size_t i = 0; i < n; ++i) {
    if (laplace && facet) {
      double s = 0;
      for (int a = 0; a < Dim; ++a) {
        double area = 1;
        for (int b = 0; b < Dim; ++b)
          if (b != a) area *= g.spacing(b);
        s += double(faces[i * 3 + std::size_t(a)]) * area;
      }
      if (s > 0) {
        REQUIRE(h[i] > 0);  // positive metrics in these tests
        c.push_back({gv::label_t(i), s / h[i]});
      }
    } else if (volume[i] > 0) {
      c.push_back({gv::label_t(i), double(volume[i]) * g.voxel_volume()});
    }
  }
  std::sort(c.begin(), c.end(), [](const c_t& a, const c_t& b) { return a.raw > b.raw || (a.raw == b.raw && a.node < b.node); });
  if (c.size() > std::size_t(k)) c.resize(std::size_t(k));
  double sum = 0;
  for (const auto& x : c) sum += x.raw;
  for (const auto& x : c) out.push_back({x.node, T(x.raw / sum)});
  // the published order holds for the stored (rounded) weights: heavier first, ties to the lower node
  std::sort(out.begin(), out.end(),
            [](const auto& a, const auto& b) { return a.second > b.second || (a.second == b.second && a.first < b.first); });
  return out;
}

/// Partition of unity, non-negativity, slot order, empty outside the domain, Kronecker delta at nodes.
template <class T, int Dim>
void check_properties(const gv::shape_weights<T, Dim>& w, const gv::diagram<T, Dim>& d, const std::string& what) {
  INFO(what);
  const int k = w.k;
  REQUIRE(w.node.size() == std::size_t(w.geometry.size()) * std::size_t(k));
  REQUIRE(w.weight.size() == w.node.size());
  bool ok = true;
  for (gv::index_t v = 0; v < w.geometry.size() && ok; ++v) {
    const std::size_t at = std::size_t(v) * std::size_t(k);
    double sum = 0;
    int filled = 0;
    for (int s = 0; s < k; ++s) {
      const auto n = w.node[at + std::size_t(s)];
      const T x = w.weight[at + std::size_t(s)];
      if (n == gv::no_label) {
        ok = ok && x == T(0);
        // empty slots only at the end
        for (int t = s; t < k; ++t) ok = ok && w.node[at + std::size_t(t)] == gv::no_label;
        break;
      }
      ++filled;
      ok = ok && x > T(0) && x <= T(1) && n >= 0 && std::size_t(n) < w.nodes;
      if (s > 0) {
        const T prev = w.weight[at + std::size_t(s) - 1];
        ok = ok && (prev > x || (prev == x && w.node[at + std::size_t(s) - 1] < n));
      }
      sum += double(x);
    }
    if (d.label[v] == gv::no_label) {
      ok = ok && filled == 0;
    } else {
      ok = ok && filled >= 1 && std::abs(sum - 1.0) <= 1e-6;
    }
    if (!ok) INFO("first failure at voxel " << v);
    CHECK(ok);
  }
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const std::size_t at = std::size_t(d.seeds[i]) * std::size_t(k);
    CHECK(w.node[at] == gv::label_t(i));
    CHECK(w.weight[at] == T(1));
    if (k > 1) CHECK(w.node[at + 1] == gv::no_label);
  }
}

inline long compared = 0;

/// field: 0 random with masks (the general path), 1 constant (translation invariant: the shape functions
/// take their exact shortcut, detail/shape/translation_invariant.hpp), 2 varying but unmasked with the
/// uniform metric (also translation invariant).
template <class P>
void brute_force_body(std::mt19937_64& rng, int trial, int field, const P& p);

template <int Dim, int N, class Metric = gv::min_stiffness>
void brute_force_case(std::mt19937_64& rng, int trial, int field = 0, double cut = 0) {
  using T = float;
  gv::coord<Dim> e{};
  gv::point<Dim> sp{};
  const double extreme[] = {1.0, 0.01, 1.0 / 3.0, 1000.0, 0.7};
  for (int a = 0; a < Dim; ++a) {
    e[a] = (Dim == 2 ? 5 : 3) + gv::index_t(rng() % (Dim == 2 ? 9 : 5));
    sp[a] = trial % 2 == 1 ? 0.5 + 0.25 * double(rng() % 5) : field != 0 && trial % 4 == 2 ? extreme[rng() % 5] : 1.0;
  }
  const gv::grid<Dim> g(e, sp);
  const auto f = field == 1   ? std::vector<T>(std::size_t(g.size()), T(1.75))
                 : field == 2 ? random_field<T>(rng, g.size(), trial % 3 == 0, 0.0, false)
                              : random_field<T>(rng, g.size(), trial % 3 == 0, trial % 4 == 0 ? 0.0 : 0.15, false);
  const auto p0 = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  // with cut > 0, every edge is cut with that probability (the problem type carries a cut_view)
  const gv::cut_table table(cut > 0 ? random_cuts(rng, g, gv::connectivity<N>{}, cut)
                                    : gv::cut_set<Dim>(g, gv::connectivity<N>{}));
  if (cut > 0) brute_force_body(rng, trial, field, gv::with_cuts(p0, table));
  else brute_force_body(rng, trial, field, p0);
}

template <class P>
void brute_force_body(std::mt19937_64& rng, int trial, int field, const P& p) {
  using T = typename P::value_type;
  constexpr int Dim = P::dim, N = P::neighbours;
  const auto& g = p.geometry;
  REQUIRE(geovoronoi::detail::shape::translation_invariant(p) == (field != 0 && !P::has_cuts));
  const auto seeds = random_seeds(rng, p, 2 + int(rng() % 5));
  if (seeds.size() < 2) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  inserted_diagrams<P> inserted(p, seeds);
  for (const bool laplace : {false, true})
    for (const int k : {8, 2}) {
      const auto m = laplace ? gv::shape_method::laplace : gv::shape_method::sibson;
      const auto w = compute(p, d, m, k, 1 + rng() % 17);
      const std::string what = std::string(GEOVORONOI_SHAPE_BACKEND_NAME) + " " + method_name(m) + " dim " +
                               std::to_string(Dim) + " N " + std::to_string(N) + " K " + std::to_string(k) +
                               " trial " + std::to_string(trial);
      check_properties(w, d, what);
      gv::index_t bad = -1;
      for (gv::index_t q = 0; q < g.size() && bad < 0; ++q) {
        const auto expect = brute_force(p, d, inserted, q, laplace, k);
        const std::size_t at = std::size_t(q) * std::size_t(k);
        for (int s = 0; s < k; ++s) {
          const bool has = std::size_t(s) < expect.size();
          const auto en = has ? expect[std::size_t(s)].first : gv::no_label;
          const T ew = has ? expect[std::size_t(s)].second : T(0);
          if (w.node[at + std::size_t(s)] != en || bits(w.weight[at + std::size_t(s)]) != bits(ew)) {
            if (bad < 0) {
              std::string slots;
              for (int t = 0; t < k; ++t)
                slots += std::to_string(w.node[at + std::size_t(t)]) + ":" + std::to_string(w.weight[at + std::size_t(t)]) + " ";
              slots += "| expected ";
              for (const auto& [en2, ew2] : expect) slots += std::to_string(en2) + ":" + std::to_string(ew2) + " ";
              MESSAGE(what << " voxel " << q << " (distance " << d.distance[q] << ", label " << d.label[q] << "): " << slots);
            }
            bad = q;
          }
        }
      }
      INFO(what << ": first mismatch with the brute-force definition at voxel " << bad);
      CHECK(bad < 0);
      compared += g.size();
    }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Sibson and Laplace equal the brute-force definition") {
  std::mt19937_64 rng(20261123);
  for (int trial = 0; trial < 4; ++trial) {
    brute_force_case<2, 4>(rng, trial);
    brute_force_case<2, 8>(rng, trial);
    brute_force_case<3, 6>(rng, trial);
    brute_force_case<3, 26>(rng, trial);
  }
  MESSAGE("voxels compared with the brute-force definition: " << compared);
  CHECK(compared > 5000);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: with cut edges, Sibson and Laplace equal the "
          "brute-force definition (no shortcut taken)") {
  std::mt19937_64 rng(1313);
  compared = 0;
  for (int trial = 0; trial < 4; ++trial) {
    brute_force_case<2, 8>(rng, trial, 0, 0.25);
    brute_force_case<2, 4, gv::uniform>(rng, trial, 1, 0.2);  // translation invariant but for the cuts
    brute_force_case<3, 6>(rng, trial, 0, 0.3);
    brute_force_case<3, 26, gv::uniform>(rng, trial, 2, 0.25);
  }
  MESSAGE("voxels compared with the brute-force definition: " << compared);
  CHECK(compared > 2000);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: translation-invariant problems (the table "
          "shortcut) equal the brute-force definition") {
  std::mt19937_64 rng(1123);
  compared = 0;
  for (int trial = 0; trial < 4; ++trial) {
    brute_force_case<2, 4, gv::uniform>(rng, trial, 2);
    brute_force_case<2, 8, gv::min_stiffness>(rng, trial, 1);
    brute_force_case<3, 6, gv::mean_cost>(rng, trial, 1);
    brute_force_case<3, 18, gv::uniform>(rng, trial, 2);
    brute_force_case<3, 26, gv::mean_stiffness>(rng, trial, 1);
    brute_force_case<3, 26, gv::uniform>(rng, trial, 1);
  }
  MESSAGE("voxels compared with the brute-force definition: " << compared);
  CHECK(compared > 5000);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: properties of every method on masked 3D volumes") {
  std::mt19937_64 rng(77);
  for (int trial = 0; trial < 4; ++trial) {
    const gv::grid<3> g({9, 7, 5}, {1.0, 0.7 + 0.2 * trial, 1.3});
    const auto f = random_field<float>(rng, g.size(), trial % 2 == 0, 0.2, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = random_seeds(rng, p, 6);
    const auto d = gv::voronoi(gv::seq, p, seeds);
    for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace})
      for (int k : {1, 3, 8}) {
        const auto w = compute(p, d, m, k);
        check_properties(w, d, std::string(method_name(m)) + " K " + std::to_string(k) + " trial " + std::to_string(trial));
      }
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Distance Ratio vanishes outside its support") {
  std::mt19937_64 rng(5);
  const gv::grid<2> g({16, 11}, {1.0, 1.5});
  const auto f = random_field<float>(rng, g.size(), false, 0.1, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto seeds = random_seeds(rng, p, 5);
  const auto d = gv::voronoi(gv::seq, p, seeds);
  const auto w = compute(p, d, gv::shape_method::distance_ratio, 5);
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    // the bound, recomputed here: largest distance over the cell and its face neighbours in other cells
    float dmax = 0;
    for (gv::index_t x = 0; x < g.size(); ++x) {
      if (d.label[x] != gv::label_t(i)) continue;
      dmax = std::max(dmax, d.distance[x]);
      for (int a = 0; a < 2; ++a)
        for (int dir = -1; dir <= 1; dir += 2) {
          auto c = g.coords(x);
          c[a] += dir;
          if (!g.contains(c)) continue;
          const auto y = g.index(c);
          if (d.label[y] != gv::no_label && d.label[y] != gv::label_t(i)) dmax = std::max(dmax, d.distance[y]);
        }
    }
    const auto di = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{seeds[i]});
    for (gv::index_t x = 0; x < g.size(); ++x)
      for (int s = 0; s < w.k; ++s)
        if (w.node[std::size_t(x) * 5 + std::size_t(s)] == gv::label_t(i)) {
          INFO("node " << i << " voxel " << x);
          CHECK(di.distance[x] < 2 * dmax);
        }
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: invariant under a permutation of the nodes") {
  std::mt19937_64 rng(11);
  const gv::grid<3> g({8, 6, 5}, {1.0, 1.2, 0.8});
  const auto f = random_field<float>(rng, g.size(), false, 0.1, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<18>{});
  const auto seeds = random_seeds(rng, p, 6);
  std::vector<std::size_t> perm(seeds.size());
  for (std::size_t i = 0; i < perm.size(); ++i) perm[i] = i;
  std::shuffle(perm.begin(), perm.end(), rng);
  std::vector<gv::coord<3>> shuffled;
  for (auto i : perm) shuffled.push_back(seeds[i]);  // node j of shuffled = node perm[j] of seeds
  const auto d = gv::voronoi(gv::seq, p, seeds);
  const auto ds = gv::voronoi(gv::seq, p, shuffled);
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    const auto a = compute(p, d, m, 8), b = compute(p, ds, m, 8);
    INFO(method_name(m));
    int bad = 0;
    for (gv::index_t v = 0; v < g.size(); ++v) {
      std::map<gv::label_t, double> ma, mb;
      for (int s = 0; s < 8; ++s) {
        const std::size_t at = std::size_t(v) * 8 + std::size_t(s);
        if (a.node[at] >= 0) ma[a.node[at]] = a.weight[at];
        if (b.node[at] >= 0) mb[gv::label_t(perm[std::size_t(b.node[at])])] = b.weight[at];
      }
      if (ma.size() != mb.size()) {
        ++bad;
        continue;
      }
      for (const auto& [n, x] : ma)
        if (!mb.count(n) || std::abs(mb[n] - x) > 1e-6) ++bad;
    }
    CHECK(bad == 0);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: results do not depend on the batch size") {
  std::mt19937_64 rng(3);
  const gv::grid<2> g({13, 9});
  const auto f = random_field<float>(rng, g.size(), true, 0.1, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, p, 4));
  for (auto m : {gv::shape_method::sibson, gv::shape_method::laplace}) {
    const auto a = compute(p, d, m, 4, 1), b = compute(p, d, m, 4, 10), c = compute(p, d, m, 4);
    CHECK(a.node == c.node);
    CHECK(b.node == c.node);
    CHECK(a.weight == c.weight);
    CHECK(b.weight == c.weight);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Sibson on a 1-voxel line, counted by hand") {
  // nodes at x = 0 and x = 10 of an 11-voxel line: cells {0..5} (the tie at 5 goes to node 0) and {6..10}.
  // Query x = 3: its new cell is {v : |v - 3| < distance to the nearest node} = {2, 3, 4, 5, 6}; it steals
  // {2, 3, 4, 5} from node 0 and {6} from node 1, so phi = (4/5, 1/5).
  const gv::grid<2> g({11, 1});
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {10, 0}});
  const auto w = compute(p, d, gv::shape_method::sibson, 2);
  CHECK(w.node[6] == 0);
  CHECK(w.node[7] == 1);
  CHECK(w.weight[6] == doctest::Approx(0.8).epsilon(1e-7));
  CHECK(w.weight[7] == doctest::Approx(0.2).epsilon(1e-7));
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Sibson reproduces a linear field along a line "
          "up to the voxel discretisation") {
  // The continuous Sibson coordinates reproduce linear fields exactly; counting voxel centres with the
  // strict insertion rule moves each cell boundary by at most half a voxel on either side, so on a line
  // the interpolant of f(x) = a + b x stays within 2 |b| h of f (see docs/shape-functions.md).
  const gv::grid<2> g({40, 1}, {0.5, 1.0});
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<8>{});
  const std::vector<gv::coord<2>> nodes{{0, 0}, {7, 0}, {18, 0}, {25, 0}, {39, 0}};
  const auto d = gv::voronoi(gv::seq, p, nodes);
  const auto w = compute(p, d, gv::shape_method::sibson, 2);  // on a line at most 2 natural neighbours
  Eigen::MatrixXf values(5, 1);
  for (int i = 0; i < 5; ++i) values(i, 0) = 3.0f - 1.5f * float(nodes[std::size_t(i)][0]) * 0.5f;
  const auto u = gv::interpolate(w, values);
  double worst = 0;
  for (gv::index_t x = 0; x < 40; ++x) worst = std::max(worst, std::abs(double(u(x, 0)) - (3.0 - 1.5 * double(x) * 0.5)));
  CHECK(worst <= 2 * 1.5 * 0.5 + 1e-5);
  // exact at the nodes
  for (int i = 0; i < 5; ++i) CHECK(u(nodes[std::size_t(i)][0], 0) == values(i, 0));
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Distance Ratio on a bar with two nodes, by hand") {
  // 10 voxels, nodes at 0 and 9, cells {0..4} and {5..9}. For node 0: d_max = 4 (d at voxel 4 and at its
  // neighbour 5), support d_0 < 8 = voxels 0..7. Frontier between 4 and 5: d_0(5) = 5, d(5) = 4, so
  // d_B(5) = (5 - 4)/2 = 1/2 and d_B(4) = (4 + 5)/2 - 4 = 1/2; d_B(v) = 1/2 + |v - 4| (v <= 4) or
  // 1/2 + (v - 5) (v >= 5), capped at 4. Raw weights of node 0: voxel 1: (1 + 3.5/4.5)/2 = 8/9,
  // 2: 7/9, 3: 2/3, 4: 5/9, 5: (1 - 0.5/4.5)/2 = 4/9, 6: 1/3, 7: 2/9; node 1 mirrors them. After
  // normalisation: voxel 2 -> (7/9, 2/9), 3 -> (2/3, 1/3), 4 -> (5/9, 4/9); voxels 0, 1 -> node 0 alone.
  const gv::grid<2> g({10, 1});
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {9, 0}});
  const auto w = compute(p, d, gv::shape_method::distance_ratio, 4);
  const double expect0[10] = {1, 1, 7.0 / 9, 2.0 / 3, 5.0 / 9, 4.0 / 9, 1.0 / 3, 2.0 / 9, 0, 0};
  for (int x = 0; x < 10; ++x) {
    double w0 = 0, w1 = 0;
    for (int s = 0; s < 4; ++s) {
      const std::size_t at = std::size_t(x) * 4 + std::size_t(s);
      if (w.node[at] == 0) w0 = w.weight[at];
      if (w.node[at] == 1) w1 = w.weight[at];
    }
    INFO("voxel " << x);
    CHECK(w0 == doctest::Approx(expect0[x]).epsilon(1e-6));
    CHECK(w1 == doctest::Approx(1 - expect0[x]).epsilon(1e-6));
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: to_sparse_matrix and interpolate agree with the slots") {
  std::mt19937_64 rng(9);
  const gv::grid<3> g({7, 6, 4});
  const auto f = random_field<float>(rng, g.size(), false, 0.15, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, p, 5));
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    const auto w = compute(p, d, m, 3);
    const auto s = w.to_sparse_matrix();
    REQUIRE(s.rows() == g.size());
    REQUIRE(s.cols() == 5);
    Eigen::MatrixXf dense = Eigen::MatrixXf(s);
    Eigen::MatrixXf slots = Eigen::MatrixXf::Zero(g.size(), 5);
    for (gv::index_t v = 0; v < g.size(); ++v)
      for (int k = 0; k < 3; ++k) {
        const std::size_t at = std::size_t(v) * 3 + std::size_t(k);
        if (w.node[at] >= 0) slots(v, w.node[at]) = w.weight[at];
      }
    CHECK(dense == slots);
    Eigen::MatrixX3f values = Eigen::MatrixX3f::Random(5, 3);
    const auto u = gv::interpolate(w, values);
    REQUIRE(u.rows() == g.size());
    REQUIRE(u.cols() == 3);
    CHECK((u - slots * values).cwiseAbs().maxCoeff() <= 1e-5f);
    CHECK_THROWS_AS(gv::interpolate(w, Eigen::MatrixXf::Zero(4, 3)), std::invalid_argument);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: bad inputs and cancellation") {
  const gv::grid<2> g({8, 8});
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<8>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{1, 1}, {6, 5}});
  gv::shape_options o;
  o.max_nodes_per_voxel = 0;
  CHECK_THROWS_WITH_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o), doctest::Contains("max_nodes_per_voxel"),
                       std::invalid_argument);
  o = {};
  o.batch_size = 0;
  CHECK_THROWS_WITH_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o), doctest::Contains("batch_size"),
                       std::invalid_argument);
  auto empty = d;
  empty.seeds.clear();
  CHECK_THROWS_WITH_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, empty), doctest::Contains("no seeds"),
                       std::invalid_argument);
  const gv::grid<2> g2({8, 7});
  const auto f2 = gv::phantom::constant(g2);
  const auto p2 = gv::make_problem(g2, f2, gv::uniform{}, gv::connectivity<8>{});
  CHECK_THROWS_WITH_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p2, d), doctest::Contains("another grid"),
                       std::invalid_argument);
  auto relabelled = d;
  relabelled.label[10] = 5;
  CHECK_THROWS_WITH_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, relabelled), doctest::Contains("not a node index"),
                       std::invalid_argument);
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    INFO(method_name(m));
    gv::shape_options c;
    c.method = m;
    c.batch_size = 5;
    std::vector<double> seen;
    c.progress = [&](double x) {
      seen.push_back(x);
      return seen.size() < 2;
    };
    CHECK_THROWS_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, c), gv::cancelled);
    CHECK(seen.size() == 2);
    seen.clear();
    c.progress = [&](double x) {
      seen.push_back(x);
      return true;
    };
    CHECK_NOTHROW(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, c));
    REQUIRE(!seen.empty());
    CHECK(std::is_sorted(seen.begin(), seen.end()));
    CHECK(seen.front() >= 0.0);
    CHECK(seen.back() == 1.0);
  }
}

}  // namespace gvshape

#include "backend/shape/piecewise_and_points.hpp"
#include "backend/shape/fast_path.hpp"
#include "backend/shape/single_owner.hpp"

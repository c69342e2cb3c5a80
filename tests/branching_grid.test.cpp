// Tests of geovoronoi/branching_grid.hpp: the copy graph against one built independently here (a
// union-find of each cell's material, a brute-force search for links), the solve against a plain
// Dijkstra on that graph, factor 1 against the regular grid's voronoi() bit for bit, the fingers
// phantom (fingers glued on a regular coarse grid, apart on the branching grid), seq against Thrust
// on OpenMP bit for bit, and the errors.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/branching_grid.hpp>

#include "support/core_helpers.hpp"

#ifdef GEOVORONOI_TEST_WITH_THRUST
#include <geovoronoi/backend/thrust.hpp>
#include <thrust/system/omp/execution_policy.h>
#endif

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <map>
#include <numeric>
#include <queue>
#include <random>
#include <set>
#include <tuple>
#include <vector>

namespace {
namespace gv = geovoronoi;

std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// A fine field of size @p n with a fraction @p empty of zeros, other values in [0.5, 4).
gv::image<float, 3> random_image(std::mt19937_64& rng, const gv::coord<3>& n, double empty) {
  gv::image<float, 3> f{gv::grid<3>(n, {1.0, 1.5, 0.75}, {2.0, -1.0, 0.5})};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (auto& x : f) x = u(rng) < empty ? 0.0f : float(0.5 + 3.5 * u(rng));
  return f;
}

// ---- the oracle's copy graph ------------------------------------------------------------------------

struct oracle_graph {
  std::vector<gv::index_t> copy_of;            // per fine voxel, -1 outside
  std::vector<gv::index_t> cell, lowest;       // per copy
  std::vector<float> stiffness;                // per copy (mean)
  std::vector<std::set<gv::index_t>> links;    // per copy
};

template <int N>
oracle_graph oracle_build(const gv::image<float, 3>& f, int factor) {
  const auto& g = f.geometry();
  const gv::index_t n = g.size();
  gv::coord<3> ce{};
  for (int a = 0; a < 3; ++a) ce[a] = (g.extent(a) + factor - 1) / factor;
  const gv::grid<3> cg(ce);
  auto cell_of = [&](gv::index_t v) {
    auto c = g.coords(v);
    for (auto& x : c) x /= factor;
    return cg.index(c);
  };
  // union-find over material voxels, joined across the connectivity's offsets within one cell
  std::vector<gv::index_t> up(static_cast<std::size_t>(n));
  std::iota(up.begin(), up.end(), gv::index_t(0));
  std::function<gv::index_t(gv::index_t)> root = [&](gv::index_t v) { return up[v] == v ? v : up[v] = root(up[v]); };
  const auto offs = gv::connectivity<N>::offsets();
  auto neighbour = [&](gv::index_t v, const std::array<int, 3>& o, gv::index_t& u) {
    auto c = g.coords(v);
    for (int a = 0; a < 3; ++a) c[a] += o[a];
    if (!g.contains(c)) return false;
    u = g.index(c);
    return true;
  };
  for (gv::index_t v = 0; v < n; ++v) {
    if (!(f[v] > 0)) continue;
    for (const auto& o : offs) {
      gv::index_t u;
      if (neighbour(v, o, u) && f[u] > 0 && cell_of(u) == cell_of(v)) up[root(u)] = root(v);
    }
  }
  // components: (cell, lowest voxel) sorted
  std::map<gv::index_t, gv::index_t> lowest_of_root;
  for (gv::index_t v = 0; v < n; ++v)
    if (f[v] > 0 && !lowest_of_root.count(root(v))) lowest_of_root[root(v)] = v;
  std::vector<std::pair<gv::index_t, gv::index_t>> comps;  // (cell, lowest)
  for (const auto& [r, low] : lowest_of_root) comps.push_back({cell_of(low), low});
  std::sort(comps.begin(), comps.end());
  std::map<gv::index_t, gv::index_t> id_of_lowest;
  oracle_graph o;
  for (std::size_t i = 0; i < comps.size(); ++i) {
    id_of_lowest[comps[i].second] = gv::index_t(i);
    o.cell.push_back(comps[i].first);
    o.lowest.push_back(comps[i].second);
  }
  o.copy_of.assign(std::size_t(n), -1);
  for (gv::index_t v = 0; v < n; ++v)
    if (f[v] > 0) o.copy_of[v] = id_of_lowest[lowest_of_root[root(v)]];
  // stiffness: mean in double over the voxels in index order
  std::vector<double> sum(comps.size(), 0.0);
  std::vector<double> cnt(comps.size(), 0.0);
  for (gv::index_t v = 0; v < n; ++v)
    if (o.copy_of[v] >= 0) sum[o.copy_of[v]] += double(f[v]), cnt[o.copy_of[v]] += 1;
  for (std::size_t i = 0; i < comps.size(); ++i) o.stiffness.push_back(float(sum[i] / cnt[i]));
  // links: every pair of neighbouring material voxels in different cells
  o.links.resize(comps.size());
  for (gv::index_t v = 0; v < n; ++v) {
    if (o.copy_of[v] < 0) continue;
    for (const auto& off : offs) {
      gv::index_t u;
      if (neighbour(v, off, u) && o.copy_of[u] >= 0 && cell_of(u) != cell_of(v)) o.links[o.copy_of[v]].insert(o.copy_of[u]);
    }
  }
  return o;
}

template <int N>
void check_against_oracle(const gv::image<float, 3>& f, int factor) {
  INFO("factor " << factor << ", connectivity " << N);
  const auto bg = gv::make_branching_grid(f, factor, gv::connectivity<N>{});
  const auto o = oracle_build<N>(f, factor);
  REQUIRE(bg.copies() == gv::index_t(o.cell.size()));
  CHECK(bg.copy_cell() == o.cell);
  CHECK(bg.copy_voxel() == o.lowest);
  CHECK(bg.fine_copy().values() == o.copy_of);
  for (gv::index_t c = 0; c < bg.copies(); ++c) CHECK(bits(bg.stiffness()[c]) == bits(o.stiffness[c]));
  // cell_begin: copies of cell c are a block, in order
  REQUIRE(bg.cell_begin().size() == std::size_t(bg.coarse().size() + 1));
  for (gv::index_t c = 0; c < bg.coarse().size(); ++c)
    for (gv::index_t k = bg.cell_begin()[c]; k < bg.cell_begin()[c + 1]; ++k) CHECK(bg.copy_cell()[k] == c);
  const auto offs = gv::connectivity<N>::offsets();
  for (gv::index_t a = 0; a < bg.copies(); ++a) {
    std::vector<gv::index_t> got(bg.link_copy().begin() + bg.link_begin()[a], bg.link_copy().begin() + bg.link_begin()[a + 1]);
    CHECK(got == std::vector<gv::index_t>(o.links[a].begin(), o.links[a].end()));  // sorted, no duplicates
    for (gv::index_t i = bg.link_begin()[a]; i < bg.link_begin()[a + 1]; ++i) {
      const auto ca = bg.coarse().coords(bg.copy_cell()[a]), cb = bg.coarse().coords(bg.copy_cell()[bg.link_copy()[i]]);
      const auto& off = offs[bg.link_dir()[i]];
      for (int ax = 0; ax < 3; ++ax) CHECK(cb[ax] - ca[ax] == off[ax]);
    }
  }
}

TEST_CASE("branching_grid: copies, links, fine_copy and stiffness equal an independent construction") {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 4; ++trial) {
    const auto f = random_image(rng, {13, 11, 9}, trial % 2 ? 0.6 : 0.35);
    for (int factor : {1, 2, 3, 4, 13}) {
      check_against_oracle<6>(f, factor);
      check_against_oracle<18>(f, factor);
      check_against_oracle<26>(f, factor);
    }
  }
}

TEST_CASE("branching_grid: the coarse grid's geometry, padding and the order of a cell's copies") {
  // 5 x 4 x 1 with factor 2: padded to 3 x 2 x 1 cells; cell 0 holds two components
  gv::image<float, 3> f{gv::grid<3>({5, 4, 1}, {0.5, 2.0, 1.0}, {10.0, 20.0, 30.0})};
  f({1, 0, 0}) = 2.0f;  // component A: lowest voxel 1
  f({0, 1, 0}) = 4.0f;  // component B: lowest voxel 5 (not face-adjacent to A)
  f({4, 3, 0}) = 1.0f;  // cell (2, 1, 0), the padded one
  const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<6>{});
  CHECK(bg.coarse().extents() == gv::coord<3>{3, 2, 1});
  CHECK(bg.coarse().spacing() == gv::point<3>{1.0, 4.0, 2.0});
  CHECK(bg.coarse().origin() == gv::point<3>{10.25, 21.0, 30.5});
  REQUIRE(bg.copies() == 3);
  CHECK(bg.copy_voxel() == std::vector<gv::index_t>{1, 5, 19});
  CHECK(bg.cell_begin() == std::vector<gv::index_t>{0, 2, 2, 2, 2, 2, 3});
  CHECK(bg.stiffness() == std::vector<float>{2.0f, 4.0f, 1.0f});
  CHECK(bg.links() == 0);
  // with 26-connectivity the two voxels touch by an edge: one copy, stiffness the mean
  const auto bg26 = gv::make_branching_grid(f, 2, gv::connectivity<26>{});
  CHECK(bg26.copies() == 2);
  CHECK(bg26.stiffness()[0] == 3.0f);
}

TEST_CASE("branching_grid: the stiffness reductions") {
  gv::image<float, 3> f{gv::grid<3>({2, 2, 2})};
  const float vals[8] = {1.0f, 2.0f, 4.0f, 0.0f, 0.1f, 3.0f, 0.3f, 7.0f};
  for (int i = 0; i < 8; ++i) f[i] = vals[i];
  auto with = [&](gv::stiffness_reduction r) {
    gv::branching_options o;
    o.reduction = r;
    const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<26>{}, o);
    REQUIRE(bg.copies() == 1);
    return bg.stiffness()[0];
  };
  double sum = 0, inv = 0;
  for (float v : vals)
    if (v > 0) sum += double(v), inv += 1.0 / double(v);
  CHECK(bits(with(gv::stiffness_reduction::mean)) == bits(float(sum / 7.0)));
  CHECK(with(gv::stiffness_reduction::min) == 0.1f);
  CHECK(with(gv::stiffness_reduction::max) == 7.0f);
  CHECK(bits(with(gv::stiffness_reduction::harmonic_mean)) == bits(float(7.0 / inv)));
  // one voxel keeps its value exactly, whatever the reduction
  gv::image<float, 3> one{gv::grid<3>({1, 1, 1}), 0.1f};
  gv::branching_options h;
  h.reduction = gv::stiffness_reduction::harmonic_mean;
  CHECK(gv::make_branching_grid(one, 1, gv::connectivity<6>{}, h).stiffness()[0] == 0.1f);
}

// ---- the oracle's solve ---------------------------------------------------------------------------

struct oracle_result {
  std::vector<float> distance;
  std::vector<gv::label_t> label;
  std::vector<gv::index_t> parent;
};

/// Dijkstra with std::priority_queue on (distance, label) in float, the metric's expression and one
/// rounded addition, on the oracle's graph; parents by the lowest realising neighbour.
template <int N, class Metric>
oracle_result oracle_solve(const oracle_graph& o, const gv::grid<3>& coarse, const std::vector<gv::index_t>& seeds,
                           Metric metric) {
  const std::size_t n = o.cell.size();
  const gv::stencil<float, 3, N> st(coarse);
  auto dir = [&](gv::index_t a, gv::index_t b) {
    const auto ca = coarse.coords(o.cell[a]), cb = coarse.coords(o.cell[b]);
    for (int k = 0; k < N; ++k)
      if (cb[0] - ca[0] == st.offset[k][0] && cb[1] - ca[1] == st.offset[k][1] && cb[2] - ca[2] == st.offset[k][2])
        return k;
    return -1;
  };
  oracle_result r{std::vector<float>(n, std::numeric_limits<float>::infinity()), std::vector<gv::label_t>(n, -1),
                  std::vector<gv::index_t>(n, -1)};
  using item = std::tuple<float, gv::label_t, gv::index_t>;
  std::priority_queue<item, std::vector<item>, std::greater<item>> q;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    r.distance[seeds[i]] = 0.0f, r.label[seeds[i]] = gv::label_t(i);
    q.push({0.0f, gv::label_t(i), seeds[i]});
  }
  while (!q.empty()) {
    const auto [d, l, v] = q.top();
    q.pop();
    if (d != r.distance[v] || l != r.label[v]) continue;
    for (gv::index_t u : o.links[v]) {
      const float w = metric(st.length[dir(v, u)], o.stiffness[v], o.stiffness[u]);
      const float nd = d + w;
      if (std::make_pair(nd, l) < std::make_pair(r.distance[u], r.label[u])) {
        r.distance[u] = nd, r.label[u] = l;
        q.push({nd, l, u});
      }
    }
  }
  for (std::size_t v = 0; v < n; ++v) {
    if (r.label[v] < 0 || std::find(seeds.begin(), seeds.end(), gv::index_t(v)) != seeds.end()) continue;
    for (gv::index_t u : o.links[v])  // increasing index: the first realiser is the lowest
      if (r.label[u] == r.label[v] &&
          r.distance[u] + metric(st.length[dir(gv::index_t(v), u)], o.stiffness[u], o.stiffness[v]) == r.distance[v]) {
        r.parent[v] = u;
        break;
      }
  }
  return r;
}

template <class D>
void check_equal(const oracle_result& o, const D& d) {
  REQUIRE(d.distance.size() == o.distance.size());
  for (std::size_t v = 0; v < o.distance.size(); ++v) {
    INFO("copy " << v);
    CHECK(bits(d.distance[v]) == bits(o.distance[v]));
    CHECK(d.label[v] == o.label[v]);
    CHECK(d.parent[v] == o.parent[v]);
  }
}

/// @p k seed voxels in the material, in distinct copies.
std::vector<gv::coord<3>> seeds_in_copies(std::mt19937_64& rng, const gv::image<float, 3>& f,
                                          const std::vector<gv::index_t>& copy_of, int k) {
  std::vector<gv::coord<3>> out;
  std::set<gv::index_t> used;
  std::uniform_int_distribution<gv::index_t> pick(0, f.size() - 1);
  for (int tries = 0; int(out.size()) < k && tries < 100000; ++tries) {
    const gv::index_t v = pick(rng);
    if (copy_of[v] < 0 || used.count(copy_of[v])) continue;
    used.insert(copy_of[v]);
    out.push_back(f.geometry().coords(v));
  }
  return out;
}

template <int N, class Metric>
void check_solve(std::mt19937_64& rng, const gv::image<float, 3>& f, int factor, Metric metric) {
  INFO("factor " << factor << ", connectivity " << N);
  const auto bg = gv::make_branching_grid(f, factor, gv::connectivity<N>{});
  const auto o = oracle_build<N>(f, factor);
  const auto p = gv::make_problem(bg, metric);
  const auto seeds = seeds_in_copies(rng, f, o.copy_of, 1 + int(rng() % 5));
  REQUIRE(!seeds.empty());
  std::vector<gv::index_t> seed_copies;
  for (const auto& s : seeds) seed_copies.push_back(o.copy_of[f.geometry().index(s)]);
  const auto want = oracle_solve<N>(o, bg.coarse(), seed_copies, metric);
  gv::solve_options opt;
  opt.with_parent = true;
  const auto d = gv::voronoi(gv::seq, p, seeds, opt);
  check_equal(want, d);
  CHECK(d.seeds == seed_copies);
#ifdef GEOVORONOI_TEST_WITH_THRUST
  for (std::size_t batch : {std::size_t(0), std::size_t(3)}) {
    INFO("thrust_omp, batch " << batch);
    const auto t = gv::voronoi(gv::thrust::par_on(::thrust::omp::par).with_batch(batch), p, seeds, opt);
    check_equal(want, t);
  }
#endif
}

TEST_CASE("branching voronoi: seq and thrust_omp equal a plain Dijkstra on the independently built graph") {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 6; ++trial) {
    const auto f = random_image(rng, {14, 10, 9}, trial % 3 == 0 ? 0.55 : 0.3);
    for (int factor : {1, 2, 3, 4}) {
      check_solve<6>(rng, f, factor, gv::min_stiffness{});
      check_solve<26>(rng, f, factor, gv::min_stiffness{});
    }
    check_solve<26>(rng, f, 2, gv::mean_stiffness{});
  }
}

TEST_CASE("branching voronoi: factor 1 is the regular grid's voronoi() bit for bit") {
  std::mt19937_64 rng(3);
  for (int trial = 0; trial < 4; ++trial) {
    const auto f = random_image(rng, {17, 12, 10}, 0.3);
    auto run = [&](auto conn) {
      const auto bg = gv::make_branching_grid(f, 1, conn);
      const auto p = gv::make_problem(bg, gv::min_stiffness{});
      const auto seeds = seeds_in_copies(rng, f, bg.fine_copy().values(), 6);
      gv::solve_options opt;
      opt.with_parent = true;
      const auto reg = gv::voronoi(gv::seq, gv::make_problem(f.geometry(), f, gv::min_stiffness{}, conn), seeds, opt);
      const auto br = gv::voronoi(gv::seq, p, seeds, opt);
      REQUIRE(bg.copies() == gv::index_t(std::count_if(f.begin(), f.end(), [](float x) { return x > 0; })));
      CHECK(bg.coarse() == f.geometry());
      for (gv::index_t v = 0; v < f.size(); ++v) {
        const gv::index_t c = bg.fine_copy()[v];
        INFO("voxel " << v);
        if (c < 0) {
          CHECK(reg.label[v] == -1);
          continue;
        }
        CHECK(bg.copy_voxel()[c] == v);
        CHECK(bits(br.distance[c]) == bits(reg.distance[v]));
        CHECK(br.label[c] == reg.label[v]);
        CHECK((br.parent[c] < 0 ? gv::index_t(-1) : bg.copy_voxel()[br.parent[c]]) == reg.parent[v]);
      }
      // painted back, the fine images are the regular diagram's
      const auto img = gv::paint_fine(bg, br);
      CHECK(img.label.values() == reg.label.values());
      for (gv::index_t v = 0; v < f.size(); ++v) CHECK(bits(img.distance[v]) == bits(reg.distance[v]));
    };
    run(gv::connectivity<6>{});
    run(gv::connectivity<26>{});
  }
}

// ---- fingers -------------------------------------------------------------------------------------------

TEST_CASE("phantom::fingers: palm, fingers and one-voxel gaps as documented") {
  const auto f = gv::phantom::fingers(gv::grid<3>({29, 20, 3}), 4, 1, 2.0f);  // w = (29 - 3) / 4 = 6
  CHECK(f({0, 0, 0}) == 2.0f);
  CHECK(f({6, 4, 1}) == 2.0f);   // palm rows y < 5 are full
  CHECK(f({6, 5, 1}) == 0.0f);   // first gap
  CHECK(f({5, 19, 2}) == 2.0f);  // finger 0's tip
  CHECK(f({7, 19, 2}) == 2.0f);  // finger 1
  CHECK(f({13, 12, 0}) == 0.0f);  // second gap
  CHECK(f({26, 19, 0}) == 2.0f);  // finger 3: x 21..26
  CHECK(f({27, 19, 0}) == 0.0f);  // columns past the last finger are empty
  CHECK(f({28, 10, 2}) == 0.0f);
  CHECK(f({28, 4, 2}) == 2.0f);   // but the palm spans them
  GV_CHECK_INVALID(gv::phantom::fingers(gv::grid<3>({5, 8, 2}), 4, 1), "do not fit");
  GV_CHECK_INVALID(gv::phantom::fingers(gv::grid<3>({5, 8, 2}), 2, 0), "gap");
}

TEST_CASE("branching voronoi: neighbouring fingertips are apart through the palm; a regular coarse grid glues them") {
  const gv::grid<3> g({55, 48, 8});
  const auto f = gv::phantom::fingers(g, 4, 1);  // fingers 13 voxels wide, gaps at x = 13, 27, 41
  const int factor = 4;
  const auto bg = gv::make_branching_grid(f, factor, gv::connectivity<26>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const gv::coord<3> tip0{12, 47, 4}, tip1{14, 47, 4};  // both in coarse cell x = 3 (fine 12..15)
  CHECK(bg.coarse().coords(bg.copy_cell()[bg.fine_copy()(tip0)]) == bg.coarse().coords(bg.copy_cell()[bg.fine_copy()(tip1)]));
  CHECK(bg.fine_copy()(tip0) != bg.fine_copy()(tip1));
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<3>>{tip0});
  const float branching = d.distance[bg.fine_copy()(tip1)];
  // down one finger and up the other: at least twice the fingers' length (36 rows) minus a cell
  CHECK(branching > float(2 * (48 - 12 - factor)));
  // the regular coarse grid (a cell is material when any of its fine voxels is): one cell
  gv::image<float, 3> coarse(bg.coarse(), 0.0f);
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (f[v] > 0) {
      auto c = g.coords(v);
      for (auto& x : c) x /= factor;
      coarse(c) = 1.0f;
    }
  const auto rp = gv::make_problem(bg.coarse(), coarse, gv::min_stiffness{}, gv::connectivity<26>{});
  gv::coord<3> c0 = tip0, c1 = tip1;
  for (auto& x : c0) x /= factor;
  for (auto& x : c1) x /= factor;
  const auto rd = gv::voronoi(gv::seq, rp, std::vector<gv::coord<3>>{c0});
  CHECK(rd.distance(c1) == 0.0f);  // the same coarse voxel: glued
  CHECK(branching > 10.0f * float(factor));
  // painted back: each fingertip voxel shows its copy's distance, the gaps none
  const auto img = gv::paint_fine(bg, d);
  CHECK(img.distance(tip1) == branching);
  CHECK(img.label(tip1) == 0);
  CHECK(img.distance({13, 47, 4}) == std::numeric_limits<float>::infinity());
  CHECK(img.label({13, 47, 4}) == -1);
#ifdef GEOVORONOI_TEST_WITH_THRUST
  const auto seeds = gv::phantom::spread_seeds(f, 9);
  gv::solve_options opt;
  opt.with_parent = true;
  const auto s = gv::voronoi(gv::seq, p, seeds, opt);
  const auto t = gv::voronoi(gv::thrust::par_on(::thrust::omp::par).with_batch(16), p, seeds, opt);
  CHECK(s.label == t.label);
  CHECK(s.parent == t.parent);
  for (std::size_t c = 0; c < s.size(); ++c) CHECK(bits(s.distance[c]) == bits(t.distance[c]));
#endif
}

// ---- errors --------------------------------------------------------------------------------------------

TEST_CASE("branching_grid: bad input is rejected with a message naming the problem") {
  gv::image<float, 3> f{gv::grid<3>({6, 5, 4}), 1.0f};
  f({2, 2, 2}) = 0.0f;
  GV_CHECK_INVALID(gv::make_branching_grid(f, 0, gv::connectivity<6>{}), "factor is 0", ">= 1");
  GV_CHECK_INVALID(gv::make_branching_grid(f, -3, gv::connectivity<6>{}), "factor is -3");
  const gv::image<float, 3> empty{gv::grid<3>({6, 5, 4}), 0.0f};
  GV_CHECK_INVALID(gv::make_branching_grid(empty, 2, gv::connectivity<6>{}), "no material");
  const auto bg = gv::make_branching_grid(f, 2, gv::connectivity<6>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  using seeds_t = std::vector<gv::coord<3>>;
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t{}), "seed list is empty");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t{{0, 0, 0}, {2, 2, 2}}), "seed 1", "(2, 2, 2)", "empty material");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t{{6, 0, 0}}), "seed 0", "outside the fine grid");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, seeds_t{{0, 0, 0}, {5, 4, 3}, {1, 1, 1}}), "seeds 0 and 2", "same copy 0");
  // world points go through the fine grid's nearest voxel
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, std::vector<gv::point<3>>{{0.2, 0.1, 0.0}, {0.9, 0.6, 1.4}}), "seeds 0 and 1",
                   "same copy");
  GV_CHECK_INVALID(gv::voronoi(gv::seq, p, std::vector<gv::point<3>>{{40.0, 0.0, 0.0}}), "seed 0", "outside the grid");
  const auto w = gv::voronoi(gv::seq, p, std::vector<gv::point<3>>{{0.2, 0.1, 0.0}, {4.6, 3.6, 2.6}});
  CHECK(w.seeds == std::vector<gv::index_t>{0, bg.fine_copy()({5, 4, 3})});
  // a diagram of another grid cannot be painted
  gv::branching_diagram<float> wrong;
  GV_CHECK_INVALID(gv::paint_fine(bg, wrong), "0 entries", "copies");
}

}  // namespace

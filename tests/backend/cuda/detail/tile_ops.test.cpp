// A host model of the CUDA backend's algorithm, built with g++ from the very per-voxel steps the
// kernels run (geovoronoi/backend/cuda/detail/tile_ops.hpp): tiles loaded with a halo, relaxed to
// local convergence by Jacobi pulls, written back and pushed into neighbouring tiles with min, a
// two-list worklist with queued flags; the double label pass; the insert-query boxes and their
// whole-grid fallback. Two schedules bracket what the GPU may do: one tile after the other (fresh
// halos), and every tile of an iteration loading before any writes back (all halos stale). Both
// must give the sequential backend's results bit for bit. This checks the algorithm and the shared
// steps on machines without a GPU; it does not check the kernels' barriers, atomics or launches.
#include <doctest/doctest.h>

#include <geovoronoi.hpp>
#include <geovoronoi/backend/cuda/detail/tile_ops.hpp>

#include "support/oracle.hpp"

#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace cd = geovoronoi::cuda::detail;
using gv::index_t;
using std::uint32_t;
using std::uint64_t;
using gvtest::bits;

enum class schedule { one_by_one, all_stale };

template <class P>
cd::tiling tiling_of(const P& p) {
  const auto& g = p.geometry;
  return cd::make_tiling<P::dim>(g.extent(0), g.extent(1), P::dim == 3 ? g.extent(P::dim - 1) : 1);
}

/// One tile's shared memory in the model.
template <class P>
struct tile_mem {
  using S = cd::tile_shape<P::dim>;
  uint32_t tile = 0;
  cd::tile_origin o{};
  std::vector<uint64_t> sw = std::vector<uint64_t>(S::halo_voxels);
  std::vector<typename P::value_type> sf = std::vector<typename P::value_type>(S::halo_voxels);
  std::vector<uint64_t> loaded = std::vector<uint64_t>(S::voxels);
};

/// The engine (engine.cuh) with the kernels' steps run on the host; returns the iteration count.
template <class P, class Rule>
long long model_engine(const P& p, const Rule& rule, const cd::tiling& t, std::vector<uint64_t>& words,
                       const std::vector<cd::seed_word>& seeds, schedule sched, bool& bad) {
  using S = cd::tile_shape<P::dim>;
  constexpr int Dim = P::dim;
  std::vector<uint32_t> list[2];
  std::vector<uint32_t> queued(static_cast<std::size_t>(t.tiles()), 0);
  auto enqueue = [&](int which, uint32_t tile) {
    if (!queued[tile]) {
      queued[tile] = 1;
      list[which].push_back(tile);
    }
  };
  auto reset = [&](int filled) {
    for (uint32_t tl : list[filled]) queued[tl] = 0;
    list[1 - filled].clear();
  };
  for (const auto& s : seeds) {
    words[s.voxel] = std::min(words[s.voxel], s.word);
    enqueue(0, uint32_t(t.tile_of(s.voxel)));
  }
  reset(0);

  auto load = [&](tile_mem<P>& m, uint32_t tile) {
    m.tile = tile;
    m.o = cd::origin_of(t, tile);
    for (int s = 0; s < S::halo_voxels; ++s)
      cd::load_slot(p, t, m.o, s, m.sw.data(), m.sf.data(), [&](index_t v) { return words[v]; });
  };
  auto own = [&](const tile_mem<P>& m, int i, int& lx, int& ly, int& lz, index_t& v) {
    lx = i % S::tx, ly = (i / S::tx) % S::ty, lz = i / (S::tx * S::ty);
    const index_t gx = m.o.x + lx, gy = m.o.y + ly, gz = m.o.z + lz;
    const bool mine = t.in_grid(gx, gy, gz) && cd::in_domain<P>(m.sf[cd::halo_slot<Dim>(lx, ly, lz)]);
    v = mine ? t.voxel(gx, gy, gz) : 0;
    return mine;
  };
  auto relax = [&](tile_mem<P>& m) {
    for (int i = 0; i < S::voxels; ++i) {
      int lx, ly, lz;
      index_t v;
      own(m, i, lx, ly, lz, v);
      m.loaded[i] = m.sw[cd::halo_slot<Dim>(lx, ly, lz)];
    }
    std::vector<uint64_t> best(S::voxels);
    for (bool changed = true; changed;) {
      changed = false;
      for (int i = 0; i < S::voxels; ++i) {  // read phase
        int lx, ly, lz;
        index_t v;
        const bool mine = own(m, i, lx, ly, lz, v);
        best[i] = mine ? cd::pull(p, rule, m.sw.data(), m.sf.data(), lx, ly, lz, v, bad)
                       : m.sw[cd::halo_slot<Dim>(lx, ly, lz)];
      }
      for (int i = 0; i < S::voxels; ++i) {  // write phase
        int lx, ly, lz;
        index_t v;
        own(m, i, lx, ly, lz, v);
        auto& w = m.sw[cd::halo_slot<Dim>(lx, ly, lz)];
        if (best[i] < w) w = best[i], changed = true;
      }
    }
  };
  auto write_and_push = [&](tile_mem<P>& m, int next) {
    for (int i = 0; i < S::voxels; ++i) {
      int lx, ly, lz;
      index_t v;
      const bool mine = own(m, i, lx, ly, lz, v);
      const uint64_t w = m.sw[cd::halo_slot<Dim>(lx, ly, lz)];
      if (mine && w < m.loaded[i]) words[v] = std::min(words[v], w);
    }
    for (int s = 0; s < S::halo_voxels; ++s) {
      int lx, ly, lz;
      cd::halo_coords<Dim>(s, lx, ly, lz);
      if (!cd::is_halo<Dim>(lx, ly, lz)) continue;
      const index_t hx = m.o.x + lx, hy = m.o.y + ly, hz = m.o.z + lz;
      if (!t.in_grid(hx, hy, hz) || !cd::in_domain<P>(m.sf[s])) continue;
      const index_t h = t.voxel(hx, hy, hz);
      const uint64_t c = cd::push_candidate(p, rule, m.sw.data(), m.sf.data(), lx, ly, lz, h, bad);
      if (c != cd::unreached) {
        const uint64_t before = words[h];
        words[h] = std::min(before, c);
        if (c < before) enqueue(next, uint32_t(t.tile_of(hx, hy, hz)));
      }
    }
  };

  long long it = 0;
  for (; !list[cd::current_list(it)].empty(); ++it) {
    const int cur = cd::current_list(it), next = cd::next_list(it);
    if (sched == schedule::one_by_one) {
      for (uint32_t tile : list[cur]) {
        tile_mem<P> m;
        load(m, tile);
        relax(m);
        write_and_push(m, next);
      }
    } else {
      std::vector<tile_mem<P>> ms(list[cur].size());
      for (std::size_t i = 0; i < ms.size(); ++i) load(ms[i], list[cur][i]);
      for (auto& m : ms) relax(m);
      for (auto& m : ms) write_and_push(m, next);
    }
    reset(next);
    REQUIRE(it < 100000);
  }
  return it;
}

/// backend_solve's float path in the model.
template <class P>
gv::diagram<float, P::dim> model_solve_float(const P& p, const std::vector<gv::source<float>>& src, float radius,
                                             schedule sched, bool label_pass = true) {
  const auto t = tiling_of(p);
  std::vector<uint64_t> words(static_cast<std::size_t>(t.voxels()), cd::unreached);
  std::vector<cd::seed_word> seeds;
  for (const auto& s : src)
    if (s.distance < radius) seeds.push_back({s.voxel, cd::pack(s.distance, s.label)});
  bool bad = false;
  model_engine(p, cd::rule_voronoi{radius}, t, words, seeds, sched, bad);
  if (label_pass) {
    for (auto& w : words) w = cd::clear_label(w);
    model_engine(p, cd::rule_label{}, t, words, seeds, sched, bad);
  }
  CHECK_FALSE(bad);
  gv::diagram<float, P::dim> d;
  d.distance = gv::image<float, P::dim>(p.geometry, std::numeric_limits<float>::infinity());
  d.label = gv::image<gv::label_t, P::dim>(p.geometry, gv::no_label);
  for (index_t v = 0; v < t.voxels(); ++v)
    if (words[v] != cd::unreached) d.distance[v] = cd::key_distance(words[v]), d.label[v] = cd::key_label(words[v]);
  return d;
}

/// backend_solve's double path: distance words, then the label pass (repair.cuh).
template <class P>
gv::diagram<double, P::dim> model_solve_double(const P& p, const std::vector<gv::source<double>>& src,
                                               schedule sched) {
  const auto t = tiling_of(p);
  std::vector<uint64_t> words(static_cast<std::size_t>(t.voxels()), cd::unreached);
  std::vector<cd::seed_word> seeds;
  for (const auto& s : src) seeds.push_back({s.voxel, cd::distance_word(s.distance)});
  bool bad = false;
  model_engine(p, cd::rule_distance<double>{std::numeric_limits<double>::infinity()}, t, words, seeds, sched, bad);
  CHECK_FALSE(bad);
  std::vector<uint32_t> labels(words.size(), ~uint32_t(0));
  for (const auto& s : src)
    if (words[s.voxel] == cd::distance_word(s.distance)) labels[s.voxel] = std::min(labels[s.voxel], uint32_t(s.label));
  for (bool changed = true; changed;) {
    changed = false;
    for (index_t v = 0; v < t.voxels(); ++v) {
      if (words[v] == cd::unreached) continue;
      const uint32_t best =
          cd::realising_label(p, t, words.data(), v, words[v], labels[v], [&](index_t u) { return labels[u]; });
      if (best < labels[v]) labels[v] = best, changed = true;
    }
  }
  gv::diagram<double, P::dim> d;
  d.distance = gv::image<double, P::dim>(p.geometry, std::numeric_limits<double>::infinity());
  d.label = gv::image<gv::label_t, P::dim>(p.geometry, gv::no_label);
  for (index_t v = 0; v < t.voxels(); ++v)
    if (words[v] != cd::unreached) d.distance[v] = cd::word_distance<double>(words[v]), d.label[v] = gv::label_t(labels[v]);
  return d;
}

template <class D1, class D2>
void require_same(const D1& a, const D2& b, const std::string& what) {
  INFO(what);
  REQUIRE(a.distance.size() == b.distance.size());
  index_t bad = -1;
  for (index_t v = 0; v < a.distance.size() && bad < 0; ++v)
    if (bits(a.distance[v]) != bits(b.distance[v]) || a.label[v] != b.label[v]) bad = v;
  if (bad >= 0)
    INFO("first mismatch at voxel " << bad << ": " << a.distance[bad] << "/" << a.label[bad] << " vs "
                                    << b.distance[bad] << "/" << b.label[bad]);
  CHECK(bad < 0);
}

/// @p cut: the problem also carries random cut edges (25 % or 60 % of the edges), which the kernels'
/// pull, push and label steps read through the problem's cut mask. Returns how many cut cases have an
/// answer that differs from the same problem without cuts (0 without @p cut).
template <int Dim, int N, class Metric>
int float_cases(std::mt19937_64& rng, int trials, bool cost, bool cut = false) {
  int cut_changed = 0;
  for (int trial = 0; trial < trials; ++trial) {
    // grids up to 3 tiles wide, so pushes cross tile borders in every direction
    gv::coord<Dim> e{};
    for (int a = 0; a < Dim; ++a) e[a] = 1 + index_t(rng() % (Dim == 3 ? 20 : 70));
    if (Dim == 2) e[1] = 1 + index_t(rng() % 40);
    gv::point<Dim> sp{};
    for (auto& x : sp) x = trial % 2 ? 0.5 + double(rng() % 100) / 50.0 : 1.0;
    const gv::grid<Dim> gg(e, sp, {});
    const auto f = gvtest::random_field<float>(rng, gg.size(), trial % 3 != 2, trial % 4 == 0 ? 0.0 : 0.2, cost);
    const auto p0 = gv::make_problem(gg, f, Metric{}, gv::connectivity<N>{});
    const auto seeds = gvtest::random_seeds(rng, p0, 1 + int(rng() % 6));
    if (seeds.empty()) continue;
    auto src = gvtest::as_sources(p0, seeds);
    if (trial % 5 == 1) src[0].distance = 0.75f;
    const float radius = trial % 3 == 0 ? 3.5f : std::numeric_limits<float>::infinity();
    gv::solve_options opt;
    opt.max_distance = radius;
    const std::string what = std::string(cut ? "cut " : "") + "float dim " + std::to_string(Dim) + " N " +
                             std::to_string(N) + " trial " + std::to_string(trial);
    auto check = [&](const auto& p) {
      const auto expect = gv::geodesic_solve(gv::seq, p, src, opt);
      require_same(model_solve_float(p, src, radius, schedule::one_by_one), expect, what + " one by one");
      require_same(model_solve_float(p, src, radius, schedule::all_stale), expect, what + " all stale");
      return expect;
    };
    if (!cut) {
      check(p0);
      continue;
    }
    const gv::cut_table table(gvtest::random_cuts(rng, gg, gv::connectivity<N>{}, trial % 4 == 1 ? 0.6 : 0.25));
    const auto with = check(gv::with_cuts(p0, table));
    // the cuts change the answer (else the case would not test them): some voxel differs
    const auto without = gv::geodesic_solve(gv::seq, p0, src, opt);
    for (index_t v = 0; v < gg.size(); ++v)
      if (bits(with.distance[v]) != bits(without.distance[v]) || with.label[v] != without.label[v]) {
        ++cut_changed;
        break;
      }
  }
  return cut_changed;
}

}  // namespace

TEST_CASE("cuda model: tiled relaxation equals seq, float, every connectivity and metric, both schedules") {
  std::mt19937_64 rng(4242);
  float_cases<2, 4, gv::min_stiffness>(rng, 12, false);
  float_cases<2, 8, gv::mean_cost>(rng, 12, true);
  float_cases<3, 6, gv::uniform>(rng, 10, false);
  float_cases<3, 18, gv::mean_stiffness>(rng, 10, false);
  float_cases<3, 26, gv::min_stiffness>(rng, 10, false);
  float_cases<3, 26, gv::mean_cost>(rng, 10, true);
}

TEST_CASE("cuda model: tiled relaxation with cut edges equals seq, float, both schedules") {
  std::mt19937_64 rng(1313);
  int cut_changed = float_cases<2, 4, gv::min_stiffness>(rng, 12, false, true);
  cut_changed += float_cases<2, 8, gv::mean_cost>(rng, 12, true, true);
  cut_changed += float_cases<3, 6, gv::uniform>(rng, 10, false, true);
  cut_changed += float_cases<3, 18, gv::mean_stiffness>(rng, 10, false, true);
  cut_changed += float_cases<3, 26, gv::min_stiffness>(rng, 10, false, true);
  cut_changed += float_cases<3, 26, gv::mean_cost>(rng, 10, true, true);
  CHECK(cut_changed >= 20);  // most problems' answers depend on their cuts
}

TEST_CASE("cuda model: double distances plus the label pass equal seq") {
  std::mt19937_64 rng(77);
  for (int trial = 0; trial < 12; ++trial) {
    const gv::grid<3> g({1 + index_t(rng() % 20), 1 + index_t(rng() % 20), 1 + index_t(rng() % 12)},
                        {1.0, trial % 2 ? 0.7 : 1.0, 1.3});
    const auto f = gvtest::random_field<double>(rng, g.size(), trial % 2 == 0, 0.15, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = gvtest::random_seeds(rng, p, 2 + int(rng() % 5));
    if (seeds.empty()) continue;
    const auto src = gvtest::as_sources(p, seeds);
    const auto expect = gv::geodesic_solve(gv::seq, p, src);
    require_same(model_solve_double(p, src, schedule::one_by_one), expect, "double one by one " + std::to_string(trial));
    require_same(model_solve_double(p, src, schedule::all_stale), expect, "double all stale " + std::to_string(trial));
  }
}

/// insert_box_kernel in the model: the box Jacobi, the overflow test, the cell in box order.
template <class P>
bool model_box(const P& p, const cd::tiling& t, const std::vector<float>& old, index_t q,
               std::vector<index_t>& voxel, std::vector<float>& dist) {
  const auto box = cd::box_around<P::dim>(t, q);
  const int used = box.used();
  std::vector<uint64_t> sw(static_cast<std::size_t>(used), cd::unreached), next(sw.size());
  for (int s = 0; s < used; ++s)
    if (box.voxel(t, s) == q && 0.0f < old[q]) sw[s] = cd::distance_word(0.0f);
  for (bool changed = true; changed;) {
    changed = false;
    for (int s = 0; s < used; ++s) next[s] = cd::box_pull(p, t, box, sw.data(), old.data(), s, sw[s]);
    for (int s = 0; s < used; ++s)
      if (next[s] < sw[s]) sw[s] = next[s], changed = true;
  }
  for (int s = 0; s < used; ++s)
    if (sw[s] != cd::unreached && box.open(t, s)) return false;
  for (int s = 0; s < used; ++s)
    if (sw[s] != cd::unreached) voxel.push_back(box.voxel(t, s)), dist.push_back(cd::word_distance<float>(sw[s]));
  return true;
}

template <int N>
void insert_cases(std::mt19937_64& rng, int& boxed, int& fell_back) {
  constexpr int Dim = gv::connectivity<N>::dim;
  for (int trial = 0; trial < 10; ++trial) {
    // large grids with few seeds give cells that leave the box (16^3 in 3D, 64^2 in 2D)
    const index_t n = trial % 2 ? 12 : 34;
    gv::grid<Dim> g;
    if constexpr (Dim == 3)
      g = gv::grid<3>({n, n - 3, n / 2 + 1}, {1.0, 1.0, trial % 3 ? 1.0 : 1.6});
    else
      g = gv::grid<2>({3 * n, 2 * n + 1}, {1.0, trial % 3 ? 1.0 : 1.6});
    const auto f = gvtest::random_field<float>(rng, g.size(), trial % 3 != 0, 0.1, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<N>{});
    const auto seeds = gvtest::random_seeds(rng, p, 2 + int(rng() % 3));
    if (seeds.size() < 2) continue;
    const auto d = gv::voronoi(gv::seq, p, seeds);
    std::vector<index_t> queries{g.index(seeds[0])};
    for (int i = 0; i < 6; ++i) {
      const index_t v = index_t(rng() % std::uint64_t(g.size()));
      if (p.inside(v)) queries.push_back(v);
    }
    const auto expect = gv::insert_queries(gv::seq, p, d, queries);
    const auto t = tiling_of(p);
    const std::vector<float> old(d.distance.data(), d.distance.data() + d.distance.size());
    for (std::size_t i = 0; i < queries.size(); ++i) {
      std::vector<index_t> voxel;
      std::vector<float> dist;
      if (model_box(p, t, old, queries[i], voxel, dist)) {
        ++boxed;
      } else {
        ++fell_back;
        std::vector<uint64_t> words(static_cast<std::size_t>(t.voxels()), cd::unreached);
        std::vector<cd::seed_word> seed;
        if (0.0f < old[queries[i]]) seed.push_back({queries[i], cd::distance_word(0.0f)});
        bool bad = false;
        model_engine(p, cd::rule_insert<float>{old.data()}, t, words, seed,
                     trial % 2 ? schedule::all_stale : schedule::one_by_one, bad);
        for (index_t v = 0; v < t.voxels(); ++v)
          if (words[v] != cd::unreached) voxel.push_back(v), dist.push_back(cd::word_distance<float>(words[v]));
      }
      const std::size_t b = expect.offsets[i], e = expect.offsets[i + 1];
      INFO("trial " << trial << " query " << i);
      REQUIRE(voxel.size() == e - b);
      for (std::size_t k = 0; k < voxel.size(); ++k) {
        CHECK(voxel[k] == expect.voxel[b + k]);
        CHECK(bits(dist[k]) == bits(expect.distance[b + k]));
      }
    }
  }
}

TEST_CASE("cuda model: insert-query boxes and the whole-grid fallback equal seq") {
  std::mt19937_64 rng(5);
  int boxed = 0, fell_back = 0;
  insert_cases<6>(rng, boxed, fell_back);
  insert_cases<26>(rng, boxed, fell_back);
  insert_cases<8>(rng, boxed, fell_back);
  // both paths were exercised
  CHECK(boxed > 0);
  CHECK(fell_back > 0);
}

TEST_CASE("cuda model: the float label pass gives Dijkstra's labels where relaxation alone keeps stale ones") {
  // The generator loop below (26-connected, min_stiffness, anisotropic, up to 15^3, 2 to 9 seeds) hits
  // rounding absorption, fl(d' + w) == fl(d + w) with d' > d, on a few trials; on those a plain
  // label-correcting relaxation (the tests' Bellman-Ford oracle included) can keep a label that came
  // through a stale key. Those trials are re-solved here: with the label pass the model must equal
  // seq; how many of them the first pass alone gets wrong is reported.
  std::mt19937_64 rng(11);
  int first_pass_wrong = 0, checked = 0;
  for (int t = 0; t < 4000; ++t) {
    gv::coord<3> e{};
    for (auto& x : e) x = 4 + index_t(rng() % 12);
    const gv::grid<3> g(e, {1.0, t % 2 ? 0.7 : 1.0, t % 3 ? 1.3 : 1.0}, {});
    const auto f = gvtest::random_field<float>(rng, g.size(), t % 2 == 0, 0.0, false);
    const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
    const auto seeds = gvtest::random_seeds(rng, p, 2 + int(rng() % 8));
    if (t != 3666 && t != 3710 && t != 3822 && t != 3978) continue;
    const auto src = gvtest::as_sources(p, seeds);
    const auto expect = gv::voronoi(gv::seq, p, seeds);
    const float inf = std::numeric_limits<float>::infinity();
    for (auto sched : {schedule::one_by_one, schedule::all_stale}) {
      require_same(model_solve_float(p, src, inf, sched), expect, "with label pass, trial " + std::to_string(t));
      const auto raw = model_solve_float(p, src, inf, sched, false);
      bool differs = false;
      for (index_t v = 0; v < g.size(); ++v) differs = differs || raw.label[v] != expect.label[v];
      first_pass_wrong += differs;
      ++checked;
    }
  }
  MESSAGE("first pass alone disagreed with seq on " << first_pass_wrong << " of " << checked << " solves");
  // a warning, not a failure: which trials hit absorption depends on oracle.hpp's generators
  WARN(first_pass_wrong > 0);
  CHECK(checked == 8);
}

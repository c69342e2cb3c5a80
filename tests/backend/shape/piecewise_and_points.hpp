// Part of the shape-function suite (included by suite.hpp): the fused search with the exact balls of
// constant regions (detail/shape/piecewise.hpp) against the brute-force definition on piecewise-constant
// fields with many ties, shape_functions_at rows against full rows, the memory budget, and
// to_sparse_matrix in the weight type.

namespace gvshape {

/// A field of random constant blocks: each axis is cut into runs of 1-6 voxels, each block of the
/// product gets 1, 2 or 4 (powers of two: distances tie often) or, with probability @p mask, 0 (outside).
/// With @p dominant, most blocks share the value 2, so some regions are wide enough for balls.
template <class T, int Dim>
std::vector<T> block_field(std::mt19937_64& rng, const gv::grid<Dim>& g, double mask, bool dominant) {
  std::vector<std::vector<int>> cut(Dim);
  for (int a = 0; a < Dim; ++a) {
    int b = 0;
    for (gv::index_t x = 0; x < g.extent(a);) {
      const gv::index_t run = 1 + gv::index_t(rng() % 6);
      for (gv::index_t i = 0; i < run && x < g.extent(a); ++i, ++x) cut[std::size_t(a)].push_back(b);
      ++b;
    }
  }
  std::map<std::vector<int>, T> value;
  std::uniform_real_distribution<double> u(0, 1);
  const T levels[] = {T(1), T(2), T(4)};
  std::vector<T> f(std::size_t(g.size()));
  for (gv::index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    std::vector<int> key;
    for (int a = 0; a < Dim; ++a) key.push_back(cut[std::size_t(a)][std::size_t(c[a])]);
    auto it = value.find(key);
    if (it == value.end()) {
      T x = levels[rng() % 3];
      if (dominant && u(rng) < 0.7) x = T(2);
      if (u(rng) < mask) x = T(0);
      it = value.emplace(key, x).first;
    }
    f[std::size_t(v)] = it->second;
  }
  return f;
}

inline long piecewise_engaged = 0;

template <int Dim, int N, class Metric = gv::min_stiffness>
void piecewise_case(std::mt19937_64& rng, int trial) {
  using T = float;
  gv::coord<Dim> e{};
  gv::point<Dim> sp{};
  const double extreme[] = {1.0, 0.01, 1.0 / 3.0, 1000.0, 0.7};
  for (int a = 0; a < Dim; ++a) {
    e[a] = (Dim == 2 ? 9 : 6) + gv::index_t(rng() % (Dim == 2 ? 9 : 4));
    sp[a] = trial % 3 == 1 ? 0.5 + 0.25 * double(rng() % 5) : trial % 3 == 2 ? extreme[rng() % 5] : 1.0;
  }
  const gv::grid<Dim> g(e, sp);
  const auto f = block_field<T>(rng, g, trial % 2 == 0 ? 0.1 : 0.0, trial % 4 < 2);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 2 + int(rng() % 4));
  if (seeds.size() < 2) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  if (!gv::detail::shape::piecewise_tables<decltype(p)>(gv::seq, p).empty()) ++piecewise_engaged;
  inserted_diagrams<std::decay_t<decltype(p)>> inserted(p, seeds);
  for (const bool laplace : {false, true}) {
    const int k = 8;
    const auto m = laplace ? gv::shape_method::laplace : gv::shape_method::sibson;
    const auto w = compute(p, d, m, k, 1 + rng() % 9);
    const std::string what = std::string(GEOVORONOI_SHAPE_BACKEND_NAME) + " piecewise " + method_name(m) + " dim " +
                             std::to_string(Dim) + " N " + std::to_string(N) + " trial " + std::to_string(trial);
    INFO(what);
    check_properties(w, d, what);
    gv::index_t bad = -1;
    for (gv::index_t q = 0; q < g.size() && bad < 0; ++q) {
      const auto expect = brute_force(p, d, inserted, q, laplace, k);
      const std::size_t at = std::size_t(q) * std::size_t(k);
      for (int s = 0; s < k; ++s) {
        const bool has = std::size_t(s) < expect.size();
        if (w.node[at + std::size_t(s)] != (has ? expect[std::size_t(s)].first : gv::no_label) ||
            bits(w.weight[at + std::size_t(s)]) != bits(has ? expect[std::size_t(s)].second : T(0)))
          bad = q;
      }
    }
    INFO("first mismatch with the brute-force definition at voxel " << bad);
    CHECK(bad < 0);
    compared += g.size();
    // the same bits without the balls
    gv::shape_options o;
    o.method = m;
    o.max_nodes_per_voxel = k;
    o.reuse_constant_regions = false;
    const auto w2 = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
    CHECK(w2.node == w.node);
    CHECK(std::equal(w.weight.begin(), w.weight.end(), w2.weight.begin(),
                     [](T a, T b) { return bits(a) == bits(b); }));
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: piecewise-constant fields with ties (exact balls of "
          "constant regions) equal the brute-force definition") {
  std::mt19937_64 rng(20261130);
  compared = 0;
  piecewise_engaged = 0;
  for (int trial = 0; trial < 6; ++trial) {
    piecewise_case<2, 4>(rng, trial);
    piecewise_case<2, 8>(rng, trial);
    piecewise_case<3, 6>(rng, trial);
    piecewise_case<3, 18>(rng, trial);
    piecewise_case<3, 26>(rng, trial);
    piecewise_case<3, 26, gv::mean_stiffness>(rng, trial);
    piecewise_case<2, 8, gv::mean_cost>(rng, trial);
  }
  MESSAGE("voxels compared: " << compared << "; problems with exact-ball tables: " << piecewise_engaged);
  CHECK(compared > 20000);
  CHECK(piecewise_engaged >= 20);  // the balls were really used
}

/// Rows of shape_functions_at equal the rows of the full computation, bit for bit: at scattered points,
/// or (@p clustered) at every voxel of a small block, where consecutive queries share a lane search.
template <int Dim, int N, class Metric>
void at_points_case(std::mt19937_64& rng, int trial, bool clustered = false) {
  using T = float;
  gv::coord<Dim> e{};
  gv::point<Dim> sp{}, origin{};
  for (int a = 0; a < Dim; ++a) {
    e[a] = (Dim == 2 ? 8 : 5) + gv::index_t(rng() % 6);
    sp[a] = 0.5 + 0.25 * double(rng() % 5);
    origin[a] = double(int(rng() % 7)) - 3.0;
  }
  const gv::grid<Dim> g(e, sp, origin);
  const auto f = trial % 2 ? block_field<T>(rng, g, 0.15, true)
                           : random_field<T>(rng, g.size(), true, 0.15, std::is_same_v<Metric, gv::mean_cost>);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const auto seeds = random_seeds(rng, p, 2 + int(rng() % 4));
  if (seeds.size() < 2) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  std::vector<gv::coord<Dim>> pts;
  for (int i = 0; i < (clustered ? 4 : 25); ++i) pts.push_back(g.coords(gv::index_t(rng() % std::uint64_t(g.size()))));
  if (clustered) {  // the voxels of a block of 4 (2D: 6) per side at a random corner, in a shuffled order
    const gv::index_t side = Dim == 2 ? 6 : 4;
    gv::coord<Dim> lo{};
    for (int a = 0; a < Dim; ++a) lo[a] = gv::index_t(rng() % std::uint64_t(std::max<gv::index_t>(1, e[a] - side + 1)));
    std::vector<gv::coord<Dim>> block;
    for (gv::index_t v = 0; v < g.size(); ++v) {
      const auto c = g.coords(v);
      bool in = true;
      for (int a = 0; a < Dim; ++a) in = in && c[a] >= lo[a] && c[a] < lo[a] + side;
      if (in) block.push_back(c);
    }
    std::shuffle(block.begin(), block.end(), rng);
    pts.insert(pts.end(), block.begin(), block.end());
  }
  pts.push_back(pts[3]);  // duplicates
  pts.push_back(pts[3]);
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (!p.inside(v)) {  // a masked point: an empty row
      pts.push_back(g.coords(v));
      break;
    }
  pts.push_back(seeds[0]);  // a node: its Kronecker row
  // world points: the voxel centres moved by less than half a voxel
  std::vector<gv::point<Dim>> world;
  std::uniform_real_distribution<double> jitter(-0.45, 0.45);
  for (const auto& c : pts) {
    gv::point<Dim> x{};
    for (int a = 0; a < Dim; ++a) x[a] = origin[a] + (double(c[a]) + jitter(rng)) * sp[a];
    world.push_back(x);
  }
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    INFO(GEOVORONOI_SHAPE_BACKEND_NAME << (clustered ? " at clustered points, " : " at points, ") << method_name(m)
                                       << " dim " << Dim << " N " << N << " trial " << trial);
    const int k = 1 + int(rng() % 4);
    const auto full = compute(p, d, m, k);
    gv::shape_options o;
    o.method = m;
    o.max_nodes_per_voxel = k;
    o.batch_size = 1 + rng() % 5;
    const auto at = gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, pts, o);
    const auto atw = gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, world, o);
    REQUIRE(at.points == pts.size());
    REQUIRE(at.k == k);
    REQUIRE(at.nodes == seeds.size());
    REQUIRE(at.node.size() == pts.size() * std::size_t(k));
    bool same = true, world_same = true;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const gv::index_t v = g.index(pts[i]);
      same = same && at.voxel[i] == v;
      for (int s = 0; s < k; ++s) {
        const std::size_t a = i * std::size_t(k) + std::size_t(s), b = std::size_t(v) * std::size_t(k) + std::size_t(s);
        same = same && at.node[a] == full.node[b] && bits(at.weight[a]) == bits(full.weight[b]);
        world_same = world_same && atw.node[a] == at.node[a] && bits(atw.weight[a]) == bits(at.weight[a]);
      }
    }
    CHECK(same);
    CHECK(world_same);
    // the masked point's row is empty, the node's row is its Kronecker delta
    const std::size_t node_row = (pts.size() - 1) * std::size_t(k);
    CHECK(at.node[node_row] == 0);
    CHECK(at.weight[node_row] == T(1));
    const auto sm = at.to_sparse_matrix();
    static_assert(std::is_same_v<typename std::decay_t<decltype(sm)>::Scalar, T>);
    REQUIRE(sm.rows() == gv::index_t(pts.size()));
    REQUIRE(sm.cols() == gv::index_t(seeds.size()));
    for (std::size_t i = 0; i < pts.size(); ++i)
      for (int s = 0; s < k; ++s) {
        const std::size_t a = i * std::size_t(k) + std::size_t(s);
        if (at.node[a] >= 0) CHECK(sm.coeff(gv::index_t(i), at.node[a]) == at.weight[a]);
      }
  }
  // outside the grid: an error naming the point
  auto outside = pts;
  outside[1][0] = g.extent(0);
  CHECK_THROWS_AS(gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, outside, {}), std::invalid_argument);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: shape_functions_at rows equal the full rows") {
  std::mt19937_64 rng(4242);
  for (int trial = 0; trial < 4; ++trial) {
    at_points_case<2, 4, gv::min_stiffness>(rng, trial);
    at_points_case<2, 8, gv::mean_cost>(rng, trial);
    at_points_case<3, 6, gv::uniform>(rng, trial);
    at_points_case<3, 18, gv::mean_stiffness>(rng, trial);
    at_points_case<3, 26, gv::min_stiffness>(rng, trial);
  }
  for (int trial = 0; trial < 2; ++trial) {
    at_points_case<2, 8, gv::min_stiffness>(rng, trial, true);
    at_points_case<3, 26, gv::min_stiffness>(rng, trial, true);
  }
  // an empty list of points
  const gv::grid<2> g({4, 4});
  const std::vector<float> f(16, 1.0f);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<4>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<2>>{{0, 0}, {3, 3}});
  const auto none = gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, std::vector<gv::coord<2>>{}, {});
  CHECK(none.points == 0);
  CHECK(none.to_sparse_matrix().rows() == 0);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: the query loop's memory budget is respected") {
  std::mt19937_64 rng(31);
  // (small: the case computes Laplace twice, and the test command runs it under the sanitizers at -O0)
  const gv::grid<3> g({16, 14, 10});
  const auto f = block_field<float>(rng, g, 0.05, true);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, p, 5));
  gv::shape_options o;
  o.method = gv::shape_method::laplace;
  gv::shape_stats free_stats;
  o.stats = &free_stats;
  const auto ref = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  CHECK(free_stats.workers >= 1);
  CHECK(free_stats.queries > 0);
  CHECK(free_stats.voxels_visited >= free_stats.queries);
  CHECK(free_stats.peak_scratch_bytes <= o.memory_budget);
  // a budget for one worker: one worker, within the budget, same weights
  const std::size_t one = gv::detail::shape::fused_worker_budget(p, d.seeds.size());
  const std::size_t tables = gv::detail::shape::piecewise_tables<decltype(p)>(gv::seq, p).bytes();
  gv::shape_stats tight;
  o.stats = &tight;
  o.memory_budget = one + tables + one / 2;
  const auto w = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  CHECK(tight.workers == 1);
  CHECK(tight.peak_scratch_bytes <= o.memory_budget);
  CHECK(w.node == ref.node);
  CHECK(w.weight == ref.weight);
  // below one worker: a clear error, not an overrun
  o.memory_budget = one / 2;
  CHECK_THROWS_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o), std::invalid_argument);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: to_sparse_matrix is in the weight type") {
  std::mt19937_64 rng(5);
  const gv::grid<3> g({6, 5, 4});
  const auto f = random_field<double>(rng, g.size(), false, 0.1, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, p, random_seeds(rng, p, 4));
  gv::shape_options o;
  o.method = gv::shape_method::sibson;
  o.max_nodes_per_voxel = 3;
  const auto w = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  const auto m = w.to_sparse_matrix();
  static_assert(std::is_same_v<typename std::decay_t<decltype(m)>::Scalar, double>);
  bool exact = true;
  for (gv::index_t v = 0; v < g.size(); ++v)
    for (int s = 0; s < 3; ++s) {
      const std::size_t at = std::size_t(v) * 3 + std::size_t(s);
      if (w.node[at] >= 0) exact = exact && m.coeff(v, w.node[at]) == w.weight[at];
    }
  CHECK(exact);
}

}  // namespace gvshape

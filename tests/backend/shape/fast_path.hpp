// Part of the shape-function suite (included by suite.hpp): the padded fast path of the fused search
// (detail/shape/fused_padded.hpp) against the brute-force definition on connectivities and metrics the
// other cases leave out, on grids of a few voxels per axis (most voxels lie on the border, where the
// padding stands in for the bounds checks), with a user metric (which keeps the negative-weight check)
// and with a metric that returns a negative weight; and the lane search (fused_lanes.hpp, its
// AVX-512 and SSE2 forms) against the one-query search, bit for bit.
//
// GEOVORONOI_SHAPE_SIMD_VARIANTS (default 1): whether the lane test also runs the SSE2 and 16-lane
// forms against the default. The lane search is the same host code on every host backend, so one
// suite (seq) compares the forms; the others compare the default lanes with the one-query search.

#ifndef GEOVORONOI_SHAPE_SIMD_VARIANTS
#define GEOVORONOI_SHAPE_SIMD_VARIANTS 1
#endif

namespace gvshape {

inline int lanes_engaged = 0;

/// A user metric (not one of the built-ins): harmonic mean of the two compliances.
struct harmonic_metric : gv::stiffness_domain {
  template <class T>
  T operator()(T length, T bu, T bv) const noexcept {
    return length * ((T(1) / bu + T(1) / bv) * T(0.5));
  }
};

/// A user metric that goes negative between two voxels of stiffness above 5.
struct sometimes_negative_metric : gv::stiffness_domain {
  template <class T>
  T operator()(T length, T bu, T bv) const noexcept {
    return bu > T(5) && bv > T(5) ? -length : length / (bu < bv ? bu : bv);
  }
};

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: the padded fast path equals the brute-force definition "
          "on every connectivity, the built-in metrics and a user metric") {
  std::mt19937_64 rng(20261201);
  for (int trial = 0; trial < 4; ++trial) {
    brute_force_case<2, 4, gv::mean_cost>(rng, trial);
    brute_force_case<2, 8, harmonic_metric>(rng, trial);
    brute_force_case<3, 6, gv::mean_stiffness>(rng, trial);
    brute_force_case<3, 18>(rng, trial);
    brute_force_case<3, 18, harmonic_metric>(rng, trial);
    brute_force_case<3, 26, gv::mean_cost>(rng, trial);
  }
}

/// Weights of @p p with the default budget (the lane search, where it applies) and with a budget
/// that holds one one-query worker only, compared bit for bit; whole grid and chosen points.
template <class P>
void lanes_case(std::mt19937_64& rng, const P& p, const std::string& what) {
  namespace sh = gv::detail::shape;
  using Policy = std::decay_t<decltype(GEOVORONOI_SHAPE_POLICY())>;
  const auto seeds = random_seeds(rng, p, 2 + int(rng() % 7));
  if (seeds.size() < 2) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  gv::shape_options o;
  o.max_nodes_per_voxel = 1 + int(rng() % 8);
  const std::size_t single = sh::fused_worker_budget(p, seeds.size()) +
                             sh::piecewise_tables<P>(gv::seq, p).bytes();
  // points in any order, some twice: rows of the same voxel must agree with each other and the grid;
  // a box of points (clustered: the lanes run them) and scattered ones (the one-query search does)
  std::vector<gv::coord<P::dim>> pts;
  for (gv::index_t v = 0; v < p.geometry.size(); ++v) {
    const auto c = p.geometry.coords(v);
    bool in_box = true;
    for (int a = 0; a < P::dim; ++a) in_box = in_box && c[a] >= 1 && c[a] <= 4;
    if (in_box) pts.push_back(c);
  }
  std::shuffle(pts.begin(), pts.end(), rng);
  pts.push_back(pts[3]);
  std::vector<gv::coord<P::dim>> scattered;
  for (int i = 0; i < 12; ++i) scattered.push_back(p.geometry.coords(gv::index_t(rng() % std::uint64_t(p.geometry.size()))));
  scattered.push_back(scattered[2]);
  for (const auto m : {gv::shape_method::sibson, gv::shape_method::laplace}) {
    INFO(what << " " << method_name(m));
    o.method = m;
    o.memory_budget = std::size_t(1) << 30;
    const bool lanes = sh::uses_fused_lanes<Policy>(p, seeds.size(), o.memory_budget);
    if (lanes) ++lanes_engaged;
    const auto a = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
#if defined(GEOVORONOI_FUSED_LANES) && GEOVORONOI_SHAPE_SIMD_VARIANTS
    {
      // the SSE2 lanes (the default is AVX-512 where the CPU has it)
      o.tuning.avx512 = false;
      const auto narrow = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
      o.tuning.avx512 = true;
      CHECK(a.node == narrow.node);
      CHECK(std::memcmp(a.weight.data(), narrow.weight.data(), a.weight.size() * sizeof(a.weight[0])) == 0);
    }
    // 16 lanes, AVX-512 and SSE2 (the two runs above took 32 lanes: the budget is large)
    for (const bool avx512 : {true, false}) {
      INFO("lanes 16" << (avx512 ? " AVX-512" : " SSE2"));
      o.tuning.lanes = 16;
      o.tuning.avx512 = avx512;
      const auto w = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
      o.tuning = gv::search_tuning{};
      CHECK(a.node == w.node);
      CHECK(std::memcmp(a.weight.data(), w.weight.data(), a.weight.size() * sizeof(a.weight[0])) == 0);
    }
#endif
    o.memory_budget = single;
    REQUIRE_FALSE(sh::uses_fused_lanes<Policy>(p, seeds.size(), o.memory_budget));
    const auto b = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
    CHECK(a.node == b.node);
    CHECK(std::memcmp(a.weight.data(), b.weight.data(), a.weight.size() * sizeof(a.weight[0])) == 0);
    // rows at points equal the grid's rows, with either budget
    const int k = o.max_nodes_per_voxel;
    for (const auto* set : {&pts, &scattered})
      for (const std::size_t budget : {std::size_t(1) << 30, single}) {
        o.memory_budget = budget;
        const auto at = gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, *set, o);
        for (std::size_t i = 0; i < set->size(); ++i)
          for (int s = 0; s < k; ++s) {
            const std::size_t v = std::size_t(p.geometry.index((*set)[i])) * std::size_t(k) + std::size_t(s);
            CHECK(at.node[i * std::size_t(k) + std::size_t(s)] == a.node[v]);
            CHECK(std::memcmp(&at.weight[i * std::size_t(k) + std::size_t(s)], &a.weight[v], sizeof(a.weight[0])) == 0);
          }
      }
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: 32 queries per search give the weights of "
          "one query per search, bit for bit") {
  std::mt19937_64 rng(20261202);
  lanes_engaged = 0;
  for (int trial = 0; trial < 3; ++trial) {
    // exact ties everywhere (levels 1, 2, 4), masks with NaN and 0; continuous fields
    const bool ties = trial != 1;
    {
      const gv::grid<3> g({9 + int(rng() % 6), 8 + int(rng() % 5), 5 + int(rng() % 5)}, {1.0, trial == 2 ? 0.5 : 1.0, 1.5});
      const auto f = random_field<float>(rng, g.size(), ties, 0.1, false);
      lanes_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{}), "min_stiffness 26");
      lanes_case(rng, gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<18>{}), "mean_stiffness 18");
      lanes_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<6>{}), "min_stiffness 6");
      // cut edges
      const gv::cut_table cuts(random_cuts(rng, g, gv::connectivity<26>{}, 0.2));
      lanes_case(rng, gv::with_cuts(gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{}), cuts),
                 "min_stiffness 26 cuts");
      // blocks of constant value: the exact balls seed the lanes
      const auto bf = block_field<float>(rng, g, 0.1, true);
      lanes_case(rng, gv::make_problem(g, bf, gv::min_stiffness{}, gv::connectivity<26>{}), "blocks 26");
      const auto cf = random_field<float>(rng, g.size(), ties, 0.1, true);
      lanes_case(rng, gv::make_problem(g, cf, gv::mean_cost{}, gv::connectivity<26>{}), "mean_cost 26");
    }
    {
      const gv::grid<2> g({20 + int(rng() % 9), 17 + int(rng() % 9)});
      const auto f = random_field<float>(rng, g.size(), ties, 0.1, false);
      lanes_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{}), "2D min_stiffness 8");
      lanes_case(rng, gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<4>{}), "2D mean_stiffness 4");
    }
  }
#ifdef GEOVORONOI_FUSED_LANES
  CHECK(lanes_engaged > 20);  // the comparison above did run the lanes (host backends on x86)
#endif
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: a negative edge weight met by the search is a "
          "metric_error") {
  const gv::grid<3> g({7, 6, 5});
  std::vector<float> f(std::size_t(g.size()), 1.0f);
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (g.coords(v)[0] >= 4) f[std::size_t(v)] = 6.0f + float(v % 3);  // stiff, varied: no exact ball
  const auto good = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, good, std::vector<gv::coord<3>>{{0, 0, 0}, {6, 5, 4}});
  const auto bad = gv::make_problem(g, f, sometimes_negative_metric{}, gv::connectivity<26>{});
  for (auto m : {gv::shape_method::sibson, gv::shape_method::laplace}) {
    gv::shape_options o;
    o.method = m;
    o.reuse_constant_regions = false;
    CHECK_THROWS_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), bad, d, o), gv::metric_error);
  }
}

}  // namespace gvshape

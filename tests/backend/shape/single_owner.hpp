// Part of the shape-function suite (included by suite.hpp): Sibson rows written without a search when
// the query's new cell provably holds its own node's voxels only (detail/shape/single_owner.hpp),
// against the rows every query's search gives, bit for bit: exact ties (where the short search cannot
// decide and the restricted-bounds search does), continuous fields, constant blocks, masks, cuts, zero
// weights, a user metric, float and double, 2D and 3D, the whole grid and chosen points.

namespace gvshape {

/// A cost field (mean_cost) with about a third of the voxels at cost 0: zero-weight edges.
template <class T>
std::vector<T> zero_cost_field(std::mt19937_64& rng, gv::index_t n) {
  std::vector<T> f(static_cast<std::size_t>(n), T(0));
  for (auto& x : f) x = rng() % 3 == 0 ? T(0) : T(1 + rng() % 3);
  return f;
}

struct single_owner_totals {
  std::size_t rows = 0, written = 0, restricted = 0, cases = 0;
};

/// Sibson on @p p with the filter (short searches capped at 256 pops, and at 0: every reached query
/// through the restricted search) and without it,
/// compared bit for bit, on the whole grid and on a box of points (at least 1/64 of the grid: the
/// filter runs for them too).
template <class P>
void single_owner_case(std::mt19937_64& rng, const P& p, int seeds, const std::string& what,
                       single_owner_totals& totals) {
  using T = typename P::value_type;
  const auto s = random_seeds(rng, p, seeds);
  if (s.size() < 2) return;
  const auto d = gv::voronoi(gv::seq, p, s);
  gv::shape_options o;
  o.method = gv::shape_method::sibson;
  o.max_nodes_per_voxel = 1 + int(rng() % 4);
  o.skip_single_owner_rows = false;
  const auto plain = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  std::vector<gv::coord<P::dim>> box;
  for (gv::index_t v = 0; v < p.geometry.size(); ++v) {
    const auto c = p.geometry.coords(v);
    bool in = true;
    for (int a = 0; a < P::dim; ++a) in = in && c[a] >= 1 && c[a] <= p.geometry.extent(a) / 2 + 1;
    if (in) box.push_back(c);
  }
  std::shuffle(box.begin(), box.end(), rng);
  REQUIRE(box.size() * 64 >= std::size_t(p.geometry.size()));
  const int k = o.max_nodes_per_voxel;
  o.skip_single_owner_rows = true;
  for (const std::size_t pops : {std::size_t(256), std::size_t(0)}) {
    INFO(what << ", short searches of at most " << pops << " pops, K " << k);
    o.tuning.single_owner_pops = pops;
    gv::shape_stats st;
    o.stats = &st;
    const auto w = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
    o.stats = nullptr;
    CHECK(w.node == plain.node);
    CHECK(std::memcmp(w.weight.data(), plain.weight.data(), w.weight.size() * sizeof(T)) == 0);
    totals.rows += std::size_t(p.geometry.size());
    totals.written += st.single_owner_rows;
    totals.restricted += st.single_owner_restricted;
    ++totals.cases;
    const auto at = gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, box, o);
    bool same = true;
    for (std::size_t i = 0; i < box.size(); ++i)
      for (int j = 0; j < k; ++j) {
        const std::size_t v = std::size_t(p.geometry.index(box[i])) * std::size_t(k) + std::size_t(j);
        const std::size_t r = i * std::size_t(k) + std::size_t(j);
        same = same && at.node[r] == plain.node[v] && std::memcmp(&at.weight[r], &plain.weight[v], sizeof(T)) == 0;
      }
    CHECK(same);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: Sibson rows of queries whose new cell stays in "
          "their own cell, written without a search, equal the searched rows bit for bit") {
  std::mt19937_64 rng(20261203);
  single_owner_totals totals;
  for (int trial = 0; trial < 2; ++trial) {
    const bool ties = trial == 0;  // exact ties everywhere (levels 1, 2, 4), then a continuous field
    {
      const gv::grid<3> g({10 + int(rng() % 6), 9 + int(rng() % 5), 6 + int(rng() % 4)},
                          {1.0, trial == 1 ? 0.5 : 1.0, trial == 1 ? 1.5 : 1.0});
      const auto f = random_field<float>(rng, g.size(), ties, trial == 0 ? 0.0 : 0.1, false);
      single_owner_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{}), 2 + trial,
                        "min_stiffness 26", totals);
      single_owner_case(rng, gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<18>{}), 3,
                        "mean_stiffness 18", totals);
      single_owner_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<6>{}), 2,
                        "min_stiffness 6", totals);
      single_owner_case(rng, gv::make_problem(g, f, harmonic_metric{}, gv::connectivity<26>{}), 3,
                        "harmonic (user metric) 26", totals);
      const gv::cut_table cuts(random_cuts(rng, g, gv::connectivity<26>{}, 0.15));
      single_owner_case(rng, gv::with_cuts(gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{}), cuts),
                        2, "min_stiffness 26 cuts", totals);
      const auto bf = block_field<float>(rng, g, 0.05, true);
      single_owner_case(rng, gv::make_problem(g, bf, gv::min_stiffness{}, gv::connectivity<26>{}), 3, "blocks 26",
                        totals);
      const auto zf = zero_cost_field<float>(rng, g.size());
      single_owner_case(rng, gv::make_problem(g, zf, gv::mean_cost{}, gv::connectivity<26>{}), 3,
                        "mean_cost with zero costs 26", totals);
      std::vector<double> fd(f.begin(), f.end());
      single_owner_case(rng, gv::make_problem(g, fd, gv::min_stiffness{}, gv::connectivity<26>{}), 2,
                        "double min_stiffness 26", totals);
    }
    {
      const gv::grid<2> g({24 + int(rng() % 9), 20 + int(rng() % 9)});
      const auto f = random_field<float>(rng, g.size(), ties, 0.05, false);
      single_owner_case(rng, gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<8>{}), 3,
                        "2D min_stiffness 8", totals);
      single_owner_case(rng, gv::make_problem(g, f, gv::mean_stiffness{}, gv::connectivity<4>{}), 2,
                        "2D mean_stiffness 4", totals);
    }
  }
  const std::size_t restricted = totals.restricted;
  MESSAGE("rows written without a search: " << totals.written << " of " << totals.rows << " (" << restricted
                                             << " decided on restricted bounds)");
  // the comparisons above did exercise both ways of deciding
  CHECK(totals.written * 10 > totals.rows);
  CHECK(restricted > 100);
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: the single-owner rows are not taken for "
          "Laplace, nor when an edge weighs less than 0, nor for a few points") {
  std::mt19937_64 rng(77);
  const gv::grid<3> g({12, 10, 6});
  const auto f = random_field<float>(rng, g.size(), true, 0.0, false);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d = gv::voronoi(gv::seq, p, std::vector<gv::coord<3>>{{6, 5, 3}, {0, 0, 0}});
  gv::shape_stats st;
  gv::shape_options o;
  o.stats = &st;
  o.method = gv::shape_method::sibson;
  gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  CHECK(st.single_owner_rows > 0);  // the far corner: new cells there stay in the middle node's cell
  o.method = gv::shape_method::laplace;
  gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
  CHECK(st.single_owner_rows == 0);
  o.method = gv::shape_method::sibson;
  // fewer points than 1/64 of the grid: every one is searched
  gv::shape_functions_at(GEOVORONOI_SHAPE_POLICY(), p, d, std::vector<gv::coord<3>>{{5, 5, 3}, {6, 5, 3}}, o);
  CHECK(st.single_owner_rows == 0);
  // a user metric that can go negative, the same problem otherwise: nothing filtered, and the search
  // still reports the weight when it meets it
  std::vector<float> stiff(f.size(), 1.0f);
  for (gv::index_t v = 0; v < g.size(); ++v)
    if (g.coords(v)[0] >= 8) stiff[std::size_t(v)] = 6.0f + float(v % 3);
  const auto bad = gv::make_problem(g, stiff, sometimes_negative_metric{}, gv::connectivity<26>{});
  const auto good = gv::make_problem(g, stiff, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto d2 = gv::voronoi(gv::seq, good, std::vector<gv::coord<3>>{{0, 0, 0}, {1, 9, 5}});
  o.reuse_constant_regions = false;
  CHECK_THROWS_AS(gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), bad, d2, o), gv::metric_error);
}

}  // namespace gvshape

// Part of the shape-function suite (included by suite.hpp): the padded fast path of the fused search
// (detail/shape/fused_padded.hpp) against the brute-force definition on connectivities and metrics the
// other cases leave out, on grids of a few voxels per axis (most voxels lie on the border, where the
// padding stands in for the bounds checks), with a user metric (which keeps the negative-weight check)
// and with a metric that returns a negative weight.

namespace gvshape {

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

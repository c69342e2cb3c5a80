// Shape functions of a backend compared bit for bit with those of seq (include after shape/suite.hpp).
#include <doctest/doctest.h>

namespace gvshape {

template <class P>
void versus_seq_body(std::mt19937_64& rng, int trial, const P& p);

template <int Dim, class Metric, int N>
void versus_seq_case(std::mt19937_64& rng, const gv::grid<Dim>& g, int trial, double cut = 0) {
  const auto f = random_field<float>(rng, g.size(), trial % 2 == 0, trial % 3 == 0 ? 0.0 : 0.15, false);
  const auto p0 = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
  const gv::cut_table table(cut > 0 ? random_cuts(rng, g, gv::connectivity<N>{}, cut)
                                    : gv::cut_set<Dim>(g, gv::connectivity<N>{}));
  if (cut > 0) versus_seq_body(rng, trial, gv::with_cuts(p0, table));
  else versus_seq_body(rng, trial, p0);
}

template <class P>
void versus_seq_body(std::mt19937_64& rng, int trial, const P& p) {
  constexpr int Dim = P::dim, N = P::neighbours;
  const auto seeds = random_seeds(rng, p, 3 + int(rng() % 6));
  if (seeds.empty()) return;
  const auto d = gv::voronoi(gv::seq, p, seeds);
  for (auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    gv::shape_options o;
    o.method = m;
    o.max_nodes_per_voxel = 3;
    o.batch_size = 37;
    const auto a = gv::shape_functions(gv::seq, p, d, o);
    const auto b = gv::shape_functions(GEOVORONOI_SHAPE_POLICY(), p, d, o);
    INFO(GEOVORONOI_SHAPE_BACKEND_NAME << " vs seq, " << method_name(m) << ", dim " << Dim << ", N " << N
                                       << ", trial " << trial);
    CHECK(a.node == b.node);
    bool same = a.weight.size() == b.weight.size();
    for (std::size_t i = 0; same && i < a.weight.size(); ++i) same = bits(a.weight[i]) == bits(b.weight[i]);
    CHECK(same);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: bitwise equal to seq") {
  std::mt19937_64 rng(404);
  for (int trial = 0; trial < 3; ++trial) {
    versus_seq_case<2, gv::min_stiffness, 8>(rng, gv::grid<2>({23, 17}, {1.0, 0.8}), trial);
    versus_seq_case<3, gv::min_stiffness, 26>(rng, gv::grid<3>({12, 9, 7}), trial);
    versus_seq_case<3, gv::mean_stiffness, 6>(rng, gv::grid<3>({10, 8, 6}, {1.0, 1.0, 2.0}), trial);
  }
}

TEST_CASE("shape functions [" GEOVORONOI_SHAPE_BACKEND_NAME "]: with cut edges, bitwise equal to seq") {
  std::mt19937_64 rng(505);
  for (int trial = 0; trial < 3; ++trial) {
    versus_seq_case<2, gv::min_stiffness, 8>(rng, gv::grid<2>({23, 17}, {1.0, 0.8}), trial, 0.2);
    versus_seq_case<3, gv::min_stiffness, 26>(rng, gv::grid<3>({12, 9, 7}), trial, 0.15);
    versus_seq_case<3, gv::uniform, 6>(rng, gv::grid<3>({10, 8, 6}, {1.0, 1.0, 2.0}), trial, 0.3);
  }
}

}  // namespace gvshape

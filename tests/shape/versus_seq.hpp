// Shape functions of a backend compared bit for bit with those of seq (include after shape/suite.hpp).
#include <doctest/doctest.h>

namespace gvshape {

template <int Dim, class Metric, int N>
void versus_seq_case(std::mt19937_64& rng, const gv::grid<Dim>& g, int trial) {
  const auto f = random_field<float>(rng, g.size(), trial % 2 == 0, trial % 3 == 0 ? 0.0 : 0.15, false);
  const auto p = gv::make_problem(g, f, Metric{}, gv::connectivity<N>{});
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

}  // namespace gvshape

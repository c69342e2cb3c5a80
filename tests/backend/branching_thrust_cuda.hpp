// Branching grids on the Thrust backend, CUDA system: voronoi() on the device equals the seq backend
// bit for bit (distances, labels, parents) on random images and the fingers phantom, several factors
// and connectivities. Included by thrust_cuda.cu (one nvcc unit), after its GEOVORONOI_TEST_* macros.
#pragma once

#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/cuda/execution_policy.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

namespace gvbranching {
namespace gv = geovoronoi;

inline std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

inline gv::image<float, 3> random_image(std::mt19937_64& rng, gv::coord<3> n, double empty) {
  gv::image<float, 3> f{gv::grid<3>(n)};
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (gv::index_t v = 0; v < f.size(); ++v) f[v] = u(rng) < empty ? 0.0f : float(0.5 + 4.0 * u(rng));
  return f;
}

/// Up to @p seeds of phantom::spread_seeds' fine voxels, no two in one copy.
template <class BG>
std::vector<gv::coord<3>> seeds_in_distinct_copies(const BG& bg, const gv::image<float, 3>& f, int seeds) {
  std::vector<gv::coord<3>> s;
  std::vector<gv::index_t> used;
  for (const auto& c : gv::phantom::spread_seeds(f, 4 * seeds)) {
    const gv::index_t copy = bg.fine_copy()(c);
    if (std::find(used.begin(), used.end(), copy) != used.end()) continue;
    used.push_back(copy);
    s.push_back(c);
    if (int(s.size()) == seeds) break;
  }
  return s;
}

template <int N, class Metric>
void check_equal_to_seq(const gv::image<float, 3>& f, int factor, Metric metric, int seeds, int batch) {
  const auto bg = gv::make_branching_grid(f, factor, gv::connectivity<N>{});
  const auto p = gv::make_problem(bg, metric);
  const auto s = seeds_in_distinct_copies(bg, f, seeds);
  REQUIRE(!s.empty());
  gv::solve_options opt;
  opt.with_parent = true;
  const auto want = gv::voronoi(gv::seq, p, s, opt);
  const auto got =
      gv::voronoi(gv::thrust::par_on(::thrust::cuda::par).with_batch(std::size_t(batch)), p, s, opt);
  INFO("factor " << factor << ", connectivity " << N << ", batch " << batch);
  REQUIRE(got.distance.size() == want.distance.size());
  for (std::size_t a = 0; a < want.distance.size(); ++a) {
    INFO("copy " << a);
    CHECK(bits(got.distance[a]) == bits(want.distance[a]));
    CHECK(got.label[a] == want.label[a]);
    CHECK(got.parent[a] == want.parent[a]);
  }
  CHECK(got.seeds == want.seeds);
}

/// Shape functions on copies with the CUDA system's policy (the searches run on the host, as for every
/// backend) against seq, every method, bit for bit.
inline void check_shape_equal_to_seq(const gv::image<float, 3>& f, int factor, int seeds) {
  const auto bg = gv::make_branching_grid(f, factor, gv::connectivity<26>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const auto s = seeds_in_distinct_copies(bg, f, seeds);
  REQUIRE(s.size() > 1);
  const auto policy = gv::thrust::par_on(::thrust::cuda::par);
  const auto d = gv::voronoi(gv::seq, p, s);
  for (const auto m : {gv::shape_method::distance_ratio, gv::shape_method::sibson, gv::shape_method::laplace}) {
    gv::shape_options o;
    o.method = m;
    const auto want = gv::shape_functions(gv::seq, p, d, o);
    const auto got = gv::shape_functions(policy, p, d, o);
    INFO("method " << int(m) << ", factor " << factor);
    REQUIRE(got.node == want.node);
    REQUIRE(got.weight.size() == want.weight.size());
    for (std::size_t a = 0; a < want.weight.size(); ++a) CHECK(bits(got.weight[a]) == bits(want.weight[a]));
  }
}

}  // namespace gvbranching

TEST_CASE("branching voronoi on thrust_cuda equals seq: random images") {
  if (GEOVORONOI_TEST_SKIP_IF_NO_DEVICE()) return;
  std::mt19937_64 rng(5);
  namespace gv = geovoronoi;
  for (int trial = 0; trial < 3; ++trial) {
    const auto f = gvbranching::random_image(rng, {20, 14, 11}, trial == 0 ? 0.55 : 0.3);
    for (int factor : {1, 2, 3}) {
      gvbranching::check_equal_to_seq<6>(f, factor, gv::min_stiffness{}, 5, 0);
      gvbranching::check_equal_to_seq<26>(f, factor, gv::min_stiffness{}, 5, 3);
    }
    gvbranching::check_equal_to_seq<26>(f, 2, gv::mean_stiffness{}, 7, 0);
  }
}

TEST_CASE("branching voronoi on thrust_cuda equals seq: fingers") {
  if (GEOVORONOI_TEST_SKIP_IF_NO_DEVICE()) return;
  namespace gv = geovoronoi;
  const auto f = gv::phantom::fingers(gv::grid<3>({64, 48, 16}), 6, 1);
  gvbranching::check_equal_to_seq<26>(f, 4, gv::min_stiffness{}, 10, 0);
  gvbranching::check_equal_to_seq<18>(f, 2, gv::min_stiffness{}, 10, 64);
}

TEST_CASE("branching shape functions with the thrust_cuda policy equal seq: fingers") {
  if (GEOVORONOI_TEST_SKIP_IF_NO_DEVICE()) return;
  namespace gv = geovoronoi;
  const auto f = gv::phantom::fingers(gv::grid<3>({32, 24, 8}), 4, 1);
  gvbranching::check_shape_equal_to_seq(f, 2, 6);
}

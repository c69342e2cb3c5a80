/// @file bench/voronoi/sofa_set.cpp
/// @brief SOFA's std::set Dijkstra (sofa_set.hpp) as the `sofa_set` backend of the voronoi cases,
///        plus a one-off check that its distances equal the library's sequential backend's.

#include "common.hpp"
#include "voronoi/sofa_set.hpp"

#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <type_traits>
#include <utility>
#include <vector>

namespace {

using namespace geovoronoi;

/// Compares sofa_set with seq on one case: distances must be bitwise equal; labels may differ only
/// where two seeds reach a voxel at exactly the same distance (SOFA's first-come tie rule vs the
/// library's lowest-index rule), and are then reported, not failed.
bool same_distances(const char* what, const image<float, 3>& field, const std::vector<coord<3>>& seeds) {
  const auto p = make_problem(field.geometry(), field, min_stiffness{}, connectivity<26>{});
  // the re-implementation walks the stencil in SOFA's z, y, x loop order; make sure that is the table's order
  int k = 0;
  for (int oz = -1; oz <= 1; ++oz)
    for (int oy = -1; oy <= 1; ++oy)
      for (int ox = -1; ox <= 1; ++ox) {
        if (ox == 0 && oy == 0 && oz == 0) continue;
        if (p.edges.offset[k][0] != ox || p.edges.offset[k][1] != oy || p.edges.offset[k][2] != oz) {
          std::fprintf(stderr, "sofa_set check: stencil entry %d is not in z-y-x order\n", k);
          return false;
        }
        ++k;
      }
  const auto ref = voronoi(seq, p, seeds);
  const auto got = bench::sofa::dijkstra_set(p, seeds);
  long bad_distance = 0, other_label = 0, reached = 0;
  for (index_t v = 0; v < field.size(); ++v) {
    const float a = ref.distance[v], b = got.distance[static_cast<std::size_t>(v)];
    if (std::memcmp(&a, &b, sizeof a) != 0) ++bad_distance;
    if (ref.label[v] != got.label[static_cast<std::size_t>(v)]) ++other_label;
    if (ref.label[v] != no_label) ++reached;
  }
  std::fprintf(stderr, "sofa_set check %s: %ld voxels reached, %ld distances differ, %ld labels differ (ties)\n",
               what, reached, bad_distance, other_label);
  return bad_distance == 0 && reached > 0;
}

}  // namespace

GEOVORONOI_BENCH_CHECK(sofa_set_distances_equal_seq) {
  bool ok = true;
  {  // anisotropic gradient: lengths differ per axis, few exact ties
    const grid<3> g({23, 19, 14}, {1.0, 1.3, 0.7});
    const auto f = phantom::gradient(g);
    ok = same_distances("gradient 23x19x14 aniso, 9 seeds", f, phantom::random_seeds(f, 9, 7)) && ok;
  }
  {  // steak: masked background, 6 orders of magnitude of stiffness contrast
    const auto& f = bench::bench_field("steak", 40);
    ok = same_distances("steak 40^3, 12 seeds", f, bench::bench_seeds(f, 12)) && ok;
  }
  {  // constant: many exact ties, labels may differ there, distances may not
    const auto& f = bench::bench_field("constant", 24);
    ok = same_distances("constant 24^3, 30 seeds", f, bench::bench_seeds(f, 30)) && ok;
  }
  return ok;
}

GEOVORONOI_BENCH_REGISTER(register_sofa_set_cases) {
  // queue statistics of the last iteration, shown as counters per voxel
  auto stats = std::make_shared<std::pair<double, double>>();
  auto solve = [stats](const auto& p, const std::vector<coord<3>>& s) {
    if constexpr (std::decay_t<decltype(p)>::neighbours == 26) {
      auto r = bench::sofa::dijkstra_set(p, s);
      *stats = {double(r.pops), double(r.relaxations)};
      return r;
    } else {
      throw std::logic_error("sofa_set is 26-connected only");
      return bench::sofa::solution{};
    }
  };
  auto voxel_hooks = [stats](int n) {
    bench::case_hooks h;
    h.after = [stats, n](benchmark::State& st) {
      const double voxels = double(n) * double(n) * double(n);
      st.counters["pops_per_voxel"] = stats->first / voxels;
      st.counters["relax_per_voxel"] = stats->second / voxels;
    };
    return h;
  };
  const std::vector<int> seed_counts{10, 100, 1000};
  for (int n : {64, 128})
    bench::register_solver_cases("sofa_set", solve, {n}, seed_counts, {26}, bench::field_names(), false,
                                 voxel_hooks(n), n <= 64 ? 2 : 1);
  bench::register_solver_cases("sofa_set", solve, {256}, {10}, {26}, {"gradient"}, false, voxel_hooks(256), 1);
}

#ifndef GEOVORONOI_BENCH_COMBINED
GEOVORONOI_BENCH_MAIN()
#endif

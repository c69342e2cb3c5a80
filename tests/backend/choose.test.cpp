// Tests of geovoronoi/backend/choose.hpp: the default-backend rule (docs/backends.md, "Choosing a
// backend") on problems on either side of each threshold.

#include <doctest/doctest.h>

#include <geovoronoi.hpp>  // with geovoronoi::seq in scope: the enumerators must not shadow it
#include <geovoronoi/backend/choose.hpp>
#include <geovoronoi/phantom.hpp>
#include <geovoronoi/problem.hpp>

#include <cstring>
#include <vector>

namespace {
namespace gv = geovoronoi;

TEST_CASE("choose: names") {
  CHECK(std::strcmp(gv::to_string(gv::backend_kind::sequential), "seq") == 0);
  CHECK(std::strcmp(gv::to_string(gv::backend_kind::thrust), "thrust") == 0);
  CHECK(std::strcmp(gv::to_string(gv::backend_kind::cuda), "cuda") == 0);
}

TEST_CASE("choose: a large domain goes to thrust with two threads or more, to seq with one") {
  const gv::grid<3> g({80, 80, 64});  // 409600 voxels, all inside
  const auto f = gv::phantom::gradient(g);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  CHECK(gv::recommended_backend(p, 2) == gv::backend_kind::thrust);
  CHECK(gv::recommended_backend(p, 16) == gv::backend_kind::thrust);
  CHECK(gv::recommended_backend(p, 1) == gv::backend_kind::sequential);
  CHECK(gv::recommended_backend(p, 0) == gv::backend_kind::sequential);  // unknown: one thread
  const auto c = gv::recommended_backend_explained(p, 2);
  CHECK(c.facts.voxels == g.size());
  CHECK(c.facts.domain == g.size());
  CHECK(c.facts.threads == 2u);
  CHECK(std::strlen(c.reason) > 0);
  // a CUDA device wins whatever the size
  CHECK(gv::recommended_backend(p, 1, true) == gv::backend_kind::cuda);
}

TEST_CASE("choose: small domains go to seq") {
  const gv::grid<3> g({48, 48, 48});  // 110592 voxels < 2^18
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<6>{});
  CHECK(gv::recommended_backend(p, 2) == gv::backend_kind::sequential);
  CHECK(gv::recommended_backend(p, 64) == gv::backend_kind::sequential);
  // the threshold counts domain voxels, not grid voxels: a big grid that is mostly masked
  const gv::grid<3> big({80, 80, 64});
  std::vector<float> masked(static_cast<std::size_t>(big.size()), 0.0f);
  for (gv::index_t v = 0; v < big.size() / 2; ++v) masked[static_cast<std::size_t>(v)] = 1.0f;  // 204800 inside
  const auto q = gv::make_problem(big, masked, gv::min_stiffness{}, gv::connectivity<26>{});
  const auto c = gv::recommended_backend_explained(q, 2);
  CHECK(c.facts.domain == big.size() / 2);
  CHECK(c.kind == gv::backend_kind::sequential);
  // with the domain above the threshold it is thrust again
  for (gv::index_t v = 0; v < big.size() * 3 / 4; ++v) masked[static_cast<std::size_t>(v)] = 1.0f;
  CHECK(gv::recommended_backend(q, 2) == gv::backend_kind::thrust);
}

TEST_CASE("choose: a domain that is a small part of the grid goes to seq") {
  const gv::grid<3> g({40, 40, 40});  // 64000 voxels
  std::vector<float> f(static_cast<std::size_t>(g.size()), 0.0f);
  for (gv::index_t v = 0; v < 3000; ++v) f[static_cast<std::size_t>(v * 20)] = 2.0f;  // 4.7 % inside
  const auto p = gv::make_problem(g, f, gv::uniform{}, gv::connectivity<6>{});
  gv::backend_rule rule;
  rule.min_domain = 1000;  // let the fraction decide
  CHECK(gv::recommended_backend(p, 2, false, rule) == gv::backend_kind::sequential);
  rule.min_domain_fraction = 0.04;
  CHECK(gv::recommended_backend(p, 2, false, rule) == gv::backend_kind::thrust);
  rule.min_threads = 4;
  CHECK(gv::recommended_backend(p, 2, false, rule) == gv::backend_kind::sequential);
  CHECK(gv::recommended_backend(p, 4, false, rule) == gv::backend_kind::thrust);
}

TEST_CASE("choose: shape functions go to thrust with two threads or more at any size, to seq with one") {
  const gv::grid<3> g({12, 10, 8});  // 960 voxels: a Voronoi solve of it would stay on seq
  const auto f = gv::phantom::constant(g);
  const auto p = gv::make_problem(g, f, gv::min_stiffness{}, gv::connectivity<26>{});
  CHECK(gv::recommended_backend(p, 2) == gv::backend_kind::sequential);
  CHECK(gv::recommended_shape_backend(p, 2) == gv::backend_kind::thrust);
  CHECK(gv::recommended_shape_backend(p, 8) == gv::backend_kind::thrust);
  CHECK(gv::recommended_shape_backend(p, 1) == gv::backend_kind::sequential);
  CHECK(gv::recommended_shape_backend(p, 0) == gv::backend_kind::sequential);
  CHECK(gv::recommended_shape_backend(p, 1, true) == gv::backend_kind::cuda);
  const auto c = gv::recommended_shape_backend_explained(p, 2);
  CHECK(c.facts.domain == g.size());
  CHECK(c.facts.threads == 2u);
  CHECK(std::strstr(c.reason, "shape functions") != nullptr);
  gv::backend_rule rule;
  rule.min_threads = 4;
  CHECK(gv::recommended_shape_backend(p, 2, false, rule) == gv::backend_kind::sequential);
  CHECK(gv::recommended_shape_backend(p, 4, false, rule) == gv::backend_kind::thrust);
  // a large problem: the same answer as for a solve
  const gv::grid<3> big({80, 80, 64});
  const auto fb = gv::phantom::gradient(big);
  const auto q = gv::make_problem(big, fb, gv::min_stiffness{}, gv::connectivity<26>{});
  CHECK(gv::recommended_shape_backend(q, 2) == gv::backend_kind::thrust);
  CHECK(gv::recommended_shape_backend(q, 1) == gv::backend_kind::sequential);
}

}  // namespace

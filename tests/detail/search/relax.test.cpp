// The relaxation step (detail/search/relax.hpp): its SIMD forms give the scalar step's bits lane by
// lane, the domain rules agree, and a bad weight is one error naming the weight.
#include <geovoronoi/detail/search/relax.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/metric.hpp>

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace gv = geovoronoi;
namespace gs = geovoronoi::detail::search;

namespace {

std::uint32_t bits(float x) {
  std::uint32_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

/// The same bits, or both NaN (a NaN's payload may depend on the order of an operation's operands).
bool same(float a, float b) { return bits(a) == bits(b) || (std::isnan(a) && std::isnan(b)); }

/// Values that stress every rule: zeros, subnormals, the extremes, infinities, NaN, and random ones.
std::vector<float> values(std::mt19937& rng) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> v = {0.0f,  -0.0f, std::numeric_limits<float>::denorm_min(), std::numeric_limits<float>::min(),
                          1.0f,  0.5f,  3.0f, std::numeric_limits<float>::max(), inf, -inf,
                          std::numeric_limits<float>::quiet_NaN(), -1.0f, 1e-30f, 1e30f};
  std::uniform_real_distribution<float> u(0.0f, 100.0f);
  std::uniform_int_distribution<int> e(-40, 40);
  for (int i = 0; i < 40; ++i) v.push_back(std::ldexp(u(rng), e(rng)));
  return v;
}

struct negative_metric {
  template <class T>
  T operator()(T length, T, T) const noexcept {
    return -length;
  }
};

template <class M>
void check_simd_step(std::mt19937& rng) {
#if defined(__SSE2__)
  const auto v = values(rng);
  std::uniform_int_distribution<std::size_t> pick(0, v.size() - 1);
  const M m{};
  std::size_t compared = 0;
  for (int trial = 0; trial < 4000; ++trial) {
    float len[4], dv[4], fv[4], fu[4];
    for (int j = 0; j < 4; ++j) {
      len[j] = std::abs(v[pick(rng)]);
      dv[j] = std::abs(v[pick(rng)]);
      fv[j] = v[pick(rng)];
      fu[j] = v[pick(rng)];
    }
    // the searches broadcast one dv and fv to four neighbours
    for (int j = 1; j < 4; ++j) dv[j] = dv[0], fv[j] = fv[0];
    alignas(16) float got[4], w4[4], in4[4];
    _mm_store_ps(got, gs::sse_relax<M>(_mm_loadu_ps(len), _mm_loadu_ps(dv), _mm_loadu_ps(fv), _mm_loadu_ps(fu)));
    _mm_store_ps(w4, gs::sse_weight<M>::apply(_mm_loadu_ps(len), _mm_loadu_ps(fv), _mm_loadu_ps(fu)));
    _mm_store_ps(in4, gs::sse_inside<M>::apply(_mm_loadu_ps(fu)));
    for (int j = 0; j < 4; ++j) {
      const float w = gs::edge_weight(m, len[j], fv[j], fu[j]);
      CHECK(same(w4[j], w));
      CHECK(same(got[j], gs::extend(dv[j], w)));
      CHECK((bits(in4[j]) != 0) == gv::detail::inside<M>(fu[j]));
      ++compared;
    }
  }
  CHECK(compared == 16000);
#else
  (void)rng;
#endif
}

}  // namespace

TEST_CASE("relax: the SSE2 step of every built-in metric gives the scalar step's bits, lane by lane") {
  std::mt19937 rng(2027);
  check_simd_step<gv::uniform>(rng);
  check_simd_step<gv::min_stiffness>(rng);
  check_simd_step<gv::mean_stiffness>(rng);
  check_simd_step<gv::mean_cost>(rng);
}

#ifdef GEOVORONOI_SIMD_AVX512
namespace {
__attribute__((target("avx512f"))) void avx512_extend(const float* d, const float* w, float* out) {
  _mm512_storeu_ps(out, gs::extend(_mm512_loadu_ps(d), _mm512_loadu_ps(w)));
}
}  // namespace
TEST_CASE("relax: the AVX-512 addition gives the scalar addition's bits") {
  if (!__builtin_cpu_supports("avx512f")) {
    MESSAGE("no AVX-512 on this CPU: nothing to compare");
    return;
  }
  std::mt19937 rng(7);
  const auto v = values(rng);
  float d[16], w[16], got[16];
  for (std::size_t s = 0; s + 16 <= v.size(); ++s) {
    for (int j = 0; j < 16; ++j) d[j] = std::abs(v[s + std::size_t(j)]), w[j] = std::abs(v[v.size() - 1 - s - std::size_t(j)]);
    avx512_extend(d, w, got);
    for (int j = 0; j < 16; ++j) CHECK(same(got[j], gs::extend(d[j], w[j])));
  }
}
#endif

TEST_CASE("relax: a negative or NaN weight is the metric's error, naming the weight") {
  CHECK(gs::relax(gv::min_stiffness{}, 1.0f, 2.0f, 4.0f, 2.0f) == 2.5f);
  CHECK(gs::relax(gv::uniform{}, 0.5, 1.0, 1.0, 1.0) == 1.5);
  try {
    (void)gs::relax(negative_metric{}, 1.5f, 0.0f, 1.0f, 1.0f);
    FAIL("no error");
  } catch (const gv::metric_error& e) {
    CHECK(std::string(e.what()).find("-1.5") != std::string::npos);
    CHECK(std::string(e.what()).find("weights must be >= 0") != std::string::npos);
  }
  CHECK_THROWS_AS(gs::check_weight(std::numeric_limits<double>::quiet_NaN()), gv::metric_error);
  CHECK_NOTHROW(gs::check_weight(0.0f));
  CHECK_THROWS_WITH_AS(gs::bad_weight(), doctest::Contains("negative or NaN edge weight"), gv::metric_error);
}

TEST_CASE("relax: the built-in metrics never weigh less than 0 between domain voxels; other metrics are checked") {
  static_assert(gs::never_negative_v<gv::uniform> && gs::never_negative_v<gv::min_stiffness> &&
                gs::never_negative_v<gv::mean_stiffness> && gs::never_negative_v<gv::mean_cost>);
  static_assert(!gs::never_negative_v<negative_metric>);
  std::mt19937 rng(11);
  const auto v = values(rng);
  auto check = [&](auto m) {
    using M = decltype(m);
    for (const float a : v)
      for (const float b : v) {
        if (!gv::detail::inside<M>(a) || !gv::detail::inside<M>(b)) continue;
        const float w = gs::edge_weight(m, 1.0f, a, b);
        CHECK((w >= 0.0f || std::isnan(w)));
      }
  };
  check(gv::uniform{});
  check(gv::min_stiffness{});
  check(gv::mean_stiffness{});
  check(gv::mean_cost{});
}

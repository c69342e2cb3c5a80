// Tests of geovoronoi/detail/search/key.hpp: packed (distance, label) keys order exactly like the pair for
// non-negative distances (float and double), round-trip their parts, and the radix-heap bucket of two
// keys is 1 + the highest differing bit.

#include <doctest/doctest.h>

#include <geovoronoi/detail/search/key.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace gd = geovoronoi::detail::search;

template <class T>
std::vector<T> sample_distances(std::mt19937_64& rng) {
  std::vector<T> d{T(0), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(), T(1),
                   std::nextafter(T(1), T(2)), T(1e-20), T(3.5), std::numeric_limits<T>::max(),
                   std::numeric_limits<T>::infinity()};
  std::uniform_real_distribution<double> u(0, 50);
  for (int i = 0; i < 40; ++i) d.push_back(T(u(rng)));
  return d;
}

template <class T>
void order_and_round_trip() {
  using kt = gd::key_traits<T>;
  std::mt19937_64 rng(sizeof(T));
  const auto ds = sample_distances<T>(rng);
  const std::vector<gv::label_t> ls{0, 1, 2, 7, 1000, std::numeric_limits<gv::label_t>::max()};
  for (T d1 : ds)
    for (gv::label_t l1 : ls) {
      const auto k1 = kt::make(d1, l1);
      CHECK(kt::label(k1) == l1);
      CHECK(kt::distance(k1) == d1);
      CHECK(k1 < kt::unreached);
      for (T d2 : ds)
        for (gv::label_t l2 : ls) {
          const auto k2 = kt::make(d2, l2);
          const bool pair_less = d1 < d2 || (d1 == d2 && l1 < l2);
          if ((k1 < k2) != pair_less) {
            INFO(d1 << "/" << l1 << " vs " << d2 << "/" << l2);
            CHECK((k1 < k2) == pair_less);
          }
          CHECK((k1 == k2) == (d1 == d2 && l1 == l2));
        }
    }
}

TEST_CASE("key: packed keys order like (distance, label) and round-trip, float and double") {
  order_and_round_trip<float>();
  order_and_round_trip<double>();
}

TEST_CASE("key: radix bucket is 1 + the highest differing bit") {
  using kf = gd::key_traits<float>;
  CHECK(kf::bucket(5, 5) == 0);
  CHECK(kf::bucket(4, 5) == 1);
  CHECK(kf::bucket(0, std::uint64_t(1) << 63) == 64);
  CHECK(kf::bucket(kf::make(1.0f, 0), kf::make(1.0f, 1)) == 1);
  CHECK(kf::bucket(kf::make(1.0f, 0), kf::make(1.0f, 2)) == 2);
  CHECK(kf::bucket(kf::make(1.0f, 0), kf::make(std::nextafter(1.0f, 2.0f), 0)) == 33);
  using kd = gd::key_traits<double>;
  CHECK(kd::bucket(kd::make(1.0, 4), kd::make(1.0, 4)) == 0);
  CHECK(kd::bucket(kd::make(1.0, 0), kd::make(1.0, 1)) == 1);
  CHECK(kd::bucket(kd::make(1.0, 0), kd::make(1.0, 1 << 30)) == 31);
  CHECK(kd::bucket(kd::make(1.0, 0), kd::make(std::nextafter(1.0, 2.0), 0)) == 33);
  CHECK(kd::bucket(kd::make(0.0, 0), kd::make(std::numeric_limits<double>::infinity(), 0)) == 96 - 1);
  // random pairs: the bucket equals the position of the highest differing bit of the 96-bit key
  std::mt19937_64 rng(9);
  for (int t = 0; t < 10000; ++t) {
    const gd::wide_key a{rng() >> 1, std::uint32_t(rng())}, b{rng() >> (rng() % 64), std::uint32_t(rng() % 4)};
    int expect = 0;
    for (int bit = 95; bit >= 0; --bit) {
      const bool xa = bit >= 32 ? (a.d >> (bit - 32)) & 1 : (a.l >> bit) & 1;
      const bool xb = bit >= 32 ? (b.d >> (bit - 32)) & 1 : (b.l >> bit) & 1;
      if (xa != xb) {
        expect = bit + 1;
        break;
      }
    }
    CHECK(kd::bucket(a, b) == expect);
  }
}

}  // namespace

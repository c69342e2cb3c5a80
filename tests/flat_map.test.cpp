// Tests of geovoronoi/detail/flat_map.hpp against std::unordered_map: random inserts, look-ups,
// updates through the returned reference, growth, reset and enumeration.

#include <doctest/doctest.h>

#include <geovoronoi/detail/flat_map.hpp>

#include <random>
#include <unordered_map>

namespace {
namespace gv = geovoronoi;

void random_ops(std::uint64_t seed, gv::index_t key_range, std::size_t expected, int ops) {
  std::mt19937_64 rng(seed);
  gv::detail::flat_map<std::uint64_t> m(expected);
  std::unordered_map<gv::index_t, std::uint64_t> ref;
  auto random_key = [&] {
    // mostly from a small range (repeats), sometimes huge or structured (strided keys collide in
    // the low bits)
    switch (rng() % 4) {
      case 0: return gv::index_t(rng() % std::uint64_t(key_range));
      case 1: return gv::index_t(rng() >> 2);
      case 2: return gv::index_t(rng() % 64) << 20;
      default: return gv::index_t(rng() % std::uint64_t(key_range)) * 1024;
    }
  };
  for (int op = 0; op < ops; ++op) {
    const gv::index_t k = random_key();
    const int what = int(rng() % 3);
    if (what == 0) {
      auto* got = m.find(k);
      auto it = ref.find(k);
      REQUIRE((got != nullptr) == (it != ref.end()));
      if (got) CHECK(*got == it->second);
    } else {
      const std::uint64_t init = rng();
      std::uint64_t& got = m.get_or_insert(k, init);
      auto [it, inserted] = ref.try_emplace(k, init);
      CHECK(got == it->second);
      if (what == 2) {  // update through the reference
        got = rng();
        it->second = got;
      }
      (void)inserted;
    }
    CHECK(m.size() == ref.size());
  }
  // enumeration visits exactly the entries, once each
  std::unordered_map<gv::index_t, std::uint64_t> seen;
  m.for_each([&](gv::index_t k, const std::uint64_t& v) { CHECK(seen.emplace(k, v).second); });
  CHECK(seen == ref);
  // reset empties the map
  m.reset(3);
  CHECK(m.size() == 0);
  for (const auto& [k, v] : ref) CHECK(m.find(k) == nullptr);
  int visited = 0;
  m.for_each([&](gv::index_t, const std::uint64_t&) { ++visited; });
  CHECK(visited == 0);
}

TEST_CASE("flat_map: equals std::unordered_map on random operations") {
  random_ops(1, 100, 1, 20000);
  random_ops(2, 100000, 64, 20000);
  random_ops(3, 5, 1000, 2000);
}

TEST_CASE("flat_map: keys 0 and large keys, values default-initialised by init") {
  gv::detail::flat_map<int> m;
  CHECK(m.find(0) == nullptr);
  m.get_or_insert(0, 5) += 1;
  CHECK(*m.find(0) == 6);
  CHECK(m.get_or_insert(0, 100) == 6);  // present: init ignored
  const gv::index_t big = std::numeric_limits<gv::index_t>::max();
  m.get_or_insert(big, 9);
  CHECK(*m.find(big) == 9);
  CHECK(m.size() == 2);
  // grow well past the initial capacity; earlier entries survive
  for (gv::index_t k = 1; k < 5000; ++k) m.get_or_insert(k * 16, int(k));
  CHECK(m.size() == 5001);
  CHECK(*m.find(0) == 6);
  CHECK(*m.find(big) == 9);
  CHECK(*m.find(16 * 4999) == 4999);
  CHECK(m.find(17) == nullptr);
}

}  // namespace

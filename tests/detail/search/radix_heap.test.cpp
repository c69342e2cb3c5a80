// Tests of geovoronoi/detail/search/radix_heap.hpp: randomized monotone push/pop sequences against
// std::priority_queue, with float and double keys, exact ties (equal keys) and near ties (equal
// distances, different labels; distances one ulp apart).

#include <doctest/doctest.h>

#include <geovoronoi/detail/search/radix_heap.hpp>

#include <cmath>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <random>
#include <vector>

namespace {
namespace gv = geovoronoi;
namespace gd = geovoronoi::detail::search;

template <class T>
T next_distance(std::mt19937_64& rng, T last) {
  switch (rng() % 8) {
    case 0:
    case 1: return last;                                                    // exact tie in distance
    case 2: return std::nextafter(last, std::numeric_limits<T>::infinity());  // one ulp more
    case 3: return last + std::numeric_limits<T>::denorm_min();
    case 4: return last + T(0.5);
    case 5: return last + T(double(rng() % 1000) / 7.0);
    case 6: return last * T(1.5) + T(1e-3);
    default: return last + T(1e6);
  }
}

template <class T>
void random_sequence(std::uint64_t seed, int ops, int label_range) {
  using kt = gd::key_traits<T>;
  using key = typename kt::key_type;
  struct entry {
    key k;
    gv::index_t v;
  };
  auto greater = [](const entry& a, const entry& b) { return b.k < a.k; };
  std::priority_queue<entry, std::vector<entry>, decltype(greater)> ref(greater);
  std::map<std::pair<std::uint64_t, gv::index_t>, int> pending;  // (key hash, voxel) -> count
  auto id = [](key k) {
    if constexpr (std::is_same_v<key, std::uint64_t>)
      return k;
    else
      return k.d * 0x100000001ull ^ k.l;
  };
  gd::radix_heap<T> heap;
  std::mt19937_64 rng(seed);
  T last_d = T(0);
  key last_key = kt::make(T(0), 0);
  gv::index_t next_voxel = 0;
  int mismatches = 0;
  for (int op = 0; op < ops && mismatches < 5; ++op) {
    const bool push = ref.empty() || rng() % 5 < 3;
    if (push) {
      // a key not below the last popped one: a larger distance, or the same distance and a label
      // not below the last popped label
      T d = next_distance(rng, last_d);
      gv::label_t l = gv::label_t(rng() % std::uint64_t(label_range));
      if (d == last_d && l < kt::label(last_key)) l = kt::label(last_key);
      const key k = kt::make(d, l);
      REQUIRE_FALSE(k < last_key);
      const gv::index_t v = (rng() % 4 == 0 && next_voxel > 0) ? gv::index_t(rng() % next_voxel) : next_voxel++;
      heap.push(k, v);
      ref.push({k, v});
      pending[{id(k), v}]++;
    } else {
      REQUIRE_FALSE(heap.empty());
      const auto got = heap.pop();
      const entry want = ref.top();
      ref.pop();
      const bool same_key = !(got.key < want.k) && !(want.k < got.key);
      if (!same_key) ++mismatches;
      CHECK(same_key);
      // among equal keys any order is fine, but the item must be one that was pushed and not popped
      auto it = pending.find({id(got.key), got.voxel});
      const bool known = it != pending.end() && it->second > 0;
      CHECK(known);
      if (known && --it->second == 0) pending.erase(it);
      last_key = got.key;
      last_d = kt::distance(got.key);
    }
    CHECK(heap.size() == ref.size());
    CHECK(heap.empty() == ref.empty());
  }
  // drain
  while (!ref.empty()) {
    REQUIRE_FALSE(heap.empty());
    const auto got = heap.pop();
    CHECK(!(got.key < ref.top().k));
    CHECK(!(ref.top().k < got.key));
    ref.pop();
  }
  CHECK(heap.empty());
  CHECK(mismatches == 0);
}

TEST_CASE("radix_heap: random monotone sequences equal std::priority_queue, float keys") {
  random_sequence<float>(1, 20000, 4);
  random_sequence<float>(2, 20000, 1);          // only distance ties
  random_sequence<float>(3, 5000, 1 << 30);     // large labels
}

TEST_CASE("radix_heap: random monotone sequences equal std::priority_queue, double keys") {
  random_sequence<double>(4, 20000, 4);
  random_sequence<double>(5, 20000, 1);
  random_sequence<double>(6, 5000, 1 << 30);
}

template <class T>
void ties_and_reuse() {
  using kt = gd::key_traits<T>;
  gd::radix_heap<T> heap;
  // many equal keys, then the same distance with growing labels, then +inf
  for (gv::index_t v = 0; v < 100; ++v) heap.push(kt::make(T(2), 3), v);
  for (gv::label_t l = 0; l < 10; ++l) heap.push(kt::make(T(2), l), 1000 + l);
  heap.push(kt::make(std::numeric_limits<T>::infinity(), 0), 5000);
  heap.push(kt::make(T(0), 7), 6000);
  CHECK(heap.size() == 112);
  CHECK(heap.pop().voxel == 6000);
  for (gv::label_t l = 0; l < 3; ++l) CHECK(heap.pop().voxel == 1000 + l);  // labels 0, 1, 2 first
  int threes = 0;
  for (int i = 0; i < 101; ++i) threes += kt::label(heap.pop().key) == 3;  // 100 + voxel 1003
  CHECK(threes == 101);
  for (gv::label_t l = 4; l < 10; ++l) CHECK(heap.pop().voxel == 1000 + l);
  CHECK(kt::distance(heap.pop().key) == std::numeric_limits<T>::infinity());
  CHECK(heap.empty());
  // clear() resets the monotone bound: smaller keys may be pushed again
  heap.push(kt::make(T(5), 0), 1);
  heap.push(kt::make(T(9), 0), 2);
  CHECK(heap.pop().voxel == 1);
  heap.clear();
  CHECK(heap.empty());
  CHECK(heap.size() == 0);
  heap.push(kt::make(T(1), 0), 3);
  heap.push(kt::make(T(0.5), 0), 4);
  CHECK(heap.pop().voxel == 4);
  CHECK(heap.pop().voxel == 3);
}

TEST_CASE("radix_heap: ties, infinity and clear") {
  ties_and_reuse<float>();
  ties_and_reuse<double>();
}

}  // namespace

// Tests of geovoronoi/detail/search/paged_scratch.hpp against a std::map model: random touches and writes
// over grids whose size is and is not a multiple of the page, fills, look-ups, sorted page walks
// (the grid's last, partial page included), clear() between searches and prepare() for other sizes.

#include <doctest/doctest.h>

#include <geovoronoi/detail/search/paged_scratch.hpp>

#include <algorithm>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <vector>

namespace {
namespace gv = geovoronoi;

/// A fill that tags each value with its voxel and the search it was filled in.
std::uint64_t filled(gv::index_t v, std::uint64_t search) { return std::uint64_t(v) * 1000003u + search; }

template <int Bits>
void random_searches(std::uint64_t seed) {
  using scratch_t = gv::detail::search::paged_scratch<std::uint64_t, Bits>;
  constexpr gv::index_t page = scratch_t::page_size;
  std::mt19937_64 rng(seed);
  scratch_t s;
  const gv::index_t sizes[] = {1, std::max<gv::index_t>(1, page - 1), page, page + 1, 7 * page + 3, 1000, 4099};
  std::uint64_t search = 0;
  for (int round = 0; round < 60; ++round) {
    const gv::index_t n = sizes[rng() % 7];
    // one series of searches on this grid; the table is reused while n stays the same
    s.prepare(n);
    REQUIRE(s.voxels() == n);
    CHECK(s.empty());
    const int searches = 1 + int(rng() % 4);
    for (int k = 0; k < searches; ++k, ++search) {
      std::map<gv::index_t, std::uint64_t> model;  // every value of every page handed out
      std::set<gv::index_t> pages;
      int fills = 0;
      auto fill = [&](gv::index_t first, std::uint64_t* values, gv::index_t count) {
        ++fills;
        CHECK(first % page == 0);
        CHECK(count == std::min(page, n - first));
        CHECK(pages.insert(first / page).second);  // a page is filled once per search
        for (gv::index_t i = 0; i < count; ++i) {
          values[i] = filled(first + i, search);
          model[first + i] = values[i];
        }
      };
      // nothing is left from the previous search
      for (gv::index_t v = 0; v < n; v += 1 + gv::index_t(rng() % 5)) CHECK(s.find(v) == nullptr);
      const int ops = 1 + int(rng() % 300);
      for (int op = 0; op < ops; ++op) {
        // clustered voxels, as a search visits them
        const gv::index_t v = gv::index_t(rng() % std::uint64_t(n));
        if (rng() % 3 == 0) {
          const auto* got = s.find(v);
          const auto it = model.find(v);
          REQUIRE((got != nullptr) == (it != model.end()));
          if (got) CHECK(*got == it->second);
        } else {
          std::uint64_t& x = s.touch(v, fill);
          CHECK(x == model.at(v));
          if (rng() % 2) {
            x = rng();
            model[v] = x;
          }
        }
      }
      CHECK(s.pages() == pages.size());
      CHECK(fills == int(pages.size()));
      // the sorted walk visits every page handed out, once, in increasing order, with its values
      gv::index_t last = -1;
      std::size_t walked = 0;
      s.for_each_page_sorted([&](gv::index_t first, const std::uint64_t* values, gv::index_t count) {
        CHECK(first > last);
        last = first;
        ++walked;
        CHECK(count == std::min(page, n - first));
        for (gv::index_t i = 0; i < count; ++i) CHECK(values[i] == model.at(first + i));
      });
      CHECK(walked == pages.size());
      s.clear();
      CHECK(s.empty());
      for (const auto& [v, x] : model) CHECK(s.find(v) == nullptr);
    }
  }
}

TEST_CASE("paged_scratch: equals a map model over random searches, pages of 1, 4 and 64 values") {
  random_searches<0>(1);
  random_searches<2>(2);
  random_searches<6>(3);
}

TEST_CASE("paged_scratch: a page is filled again in the next search, not reused stale") {
  gv::detail::search::paged_scratch<int, 3> s;
  s.prepare(20);
  int fills = 0;
  auto fill = [&](gv::index_t first, int* values, gv::index_t count) {
    ++fills;
    for (gv::index_t i = 0; i < count; ++i) values[i] = -int(first + i);
  };
  s.touch(9, fill) = 99;
  s.touch(10, fill) = 100;  // same page (8..15)
  s.touch(17, fill) = 170;  // last page, 4 voxels (16..19)
  CHECK(fills == 2);
  CHECK(*s.find(8) == -8);
  CHECK(*s.find(9) == 99);
  CHECK(s.find(3) == nullptr);
  std::vector<gv::index_t> counts;
  s.for_each_page_sorted([&](gv::index_t, const int*, gv::index_t count) { counts.push_back(count); });
  CHECK(counts == std::vector<gv::index_t>{8, 4});
  s.clear();
  CHECK(s.find(9) == nullptr);
  CHECK(s.touch(9, fill) == -9);  // refilled
  CHECK(fills == 3);
  // prepare() forgets an unfinished search too (a search that threw)
  s.prepare(20);
  CHECK(s.find(9) == nullptr);
  CHECK(s.pages() == 0);
  // another size: a new table, the old entries gone
  s.touch(2, fill);
  s.prepare(5);
  CHECK(s.find(2) == nullptr);
  CHECK(s.touch(4, fill) == -4);
  std::vector<gv::index_t> firsts;
  s.for_each_page_sorted([&](gv::index_t first, const int*, gv::index_t count) {
    firsts.push_back(first);
    CHECK(count == 5);
  });
  CHECK(firsts == std::vector<gv::index_t>{0});
}

TEST_CASE("paged_scratch: memory held follows the pages handed out, not the grid") {
  gv::detail::search::paged_scratch<std::uint64_t, 6> s;
  const gv::index_t n = gv::index_t(1) << 24;  // 16 Mi voxels: 2 MiB of table
  s.prepare(n);
  auto fill = [](gv::index_t, std::uint64_t* values, gv::index_t count) {
    for (gv::index_t i = 0; i < count; ++i) values[i] = 0;
  };
  for (gv::index_t v = 0; v < 1000; ++v) s.touch(n / 2 + v * 4096, fill);  // 1000 pages
  CHECK(s.pages() == 1000);
  const std::size_t table = std::size_t(n / 64) * sizeof(void*);
  CHECK(s.bytes() >= table + 1000 * 64 * 8);
  CHECK(s.bytes() <= table + 2 * 1024 * 64 * 8);  // the pool grows by 64 pages, plus the page list
  // later searches of the same size reuse the pool: nothing accumulates between searches
  const std::size_t held = s.bytes();
  for (int search = 0; search < 20; ++search) {
    s.clear();
    for (gv::index_t v = 0; v < 1000; ++v) s.touch(n / 3 + v * 4096 + search, fill);
    CHECK(s.pages() == 1000);
  }
  CHECK(s.bytes() == held);
}

TEST_CASE("paged_scratch: sorted walks of clustered and of scattered pages") {
  // clustered pages are walked through the table, scattered ones sorted: both give increasing order
  gv::detail::search::paged_scratch<gv::index_t, 2> s;
  s.prepare(100000);
  auto fill = [](gv::index_t first, gv::index_t* values, gv::index_t count) {
    for (gv::index_t i = 0; i < count; ++i) values[i] = first + i;
  };
  for (const auto& pages : {std::vector<gv::index_t>{7, 3, 5, 4, 9}, std::vector<gv::index_t>{24000, 3, 900, 12},
                            std::vector<gv::index_t>{0, 24999}, std::vector<gv::index_t>{24999, 24998, 0}}) {
    for (const auto page : pages) s.touch(page * 4 + 1, fill);
    std::vector<gv::index_t> walked;
    s.for_each_page_sorted([&](gv::index_t first, const gv::index_t* values, gv::index_t count) {
      CHECK(values[0] == first);
      CHECK(count == 4);
      walked.push_back(first / 4);
    });
    auto expect = pages;
    std::sort(expect.begin(), expect.end());
    CHECK(walked == expect);
    s.clear();
  }
}

TEST_CASE("paged_scratch: a negative size is rejected") {
  gv::detail::search::paged_scratch<int> s;
  CHECK_THROWS_AS(s.prepare(-1), std::invalid_argument);
}

}  // namespace

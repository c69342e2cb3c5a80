// Host-side tests of the CUDA backend's host-device arithmetic (geovoronoi/backend/cuda/detail/
// tiling.hpp): tiles, halo slots, packed keys, worklist bookkeeping and insert-query boxes. They run
// with g++ on every machine; the kernels that use these pieces need a GPU and are tested there.
#include <doctest/doctest.h>

#include <geovoronoi/backend/cuda/detail/tiling.hpp>
#include <geovoronoi/detail/search/key.hpp>
#include <geovoronoi/grid.hpp>

#include <limits>
#include <random>
#include <set>
#include <type_traits>
#include <vector>

namespace cd = geovoronoi::cuda::detail;
namespace gv = geovoronoi;
using gv::index_t;

static_assert(std::is_trivially_copyable_v<cd::tiling>, "tiling is passed to kernels by value");
static_assert(std::is_trivially_copyable_v<cd::box_axis>, "box_axis lives in kernels");
static_assert(cd::tile_shape<3>::voxels == 512 && cd::tile_shape<2>::voxels == 512,
              "one tile = one 512-thread block in 2D and 3D");

TEST_CASE("cuda tiling: every voxel lies in exactly one tile, partial tiles at the far borders") {
  for (const auto& e : std::vector<std::array<index_t, 3>>{{1, 1, 1}, {8, 8, 8}, {9, 17, 3}, {40, 33, 27}}) {
    const auto t = cd::make_tiling<3>(e[0], e[1], e[2]);
    CHECK(t.tnx == (e[0] + 7) / 8);
    CHECK(t.tiles() == t.tnx * t.tny * t.tnz);
    std::vector<int> per_tile(static_cast<std::size_t>(t.tiles()), 0);
    for (index_t z = 0; z < e[2]; ++z)
      for (index_t y = 0; y < e[1]; ++y)
        for (index_t x = 0; x < e[0]; ++x) {
          const index_t v = t.voxel(x, y, z);
          CHECK(v == x + e[0] * (y + e[1] * z));
          const index_t tile = t.tile_of(v);
          REQUIRE(tile >= 0);
          REQUIRE(tile < t.tiles());
          CHECK(tile == t.tile_of(x, y, z));
          index_t a, b, c;
          t.tile_coords(tile, a, b, c);
          CHECK(x / 8 == a);
          CHECK(y / 8 == b);
          CHECK(z / 8 == c);
          CHECK(t.tile_id(a, b, c) == tile);
          ++per_tile[static_cast<std::size_t>(tile)];
        }
    for (int n : per_tile) {
      CHECK(n >= 1);
      CHECK(n <= 512);
    }
  }
  const auto t2 = cd::make_tiling<2>(70, 20, 1);
  CHECK(t2.tnx == 3);
  CHECK(t2.tny == 2);
  CHECK(t2.tnz == 1);
  CHECK(t2.tile_of(69, 19, 0) == 5);
}

template <int Dim>
void halo_roundtrip() {
  using S = cd::tile_shape<Dim>;
  std::set<int> seen;
  int inner = 0;
  for (int lz = -S::hz; lz < S::tz + S::hz; ++lz)
    for (int ly = -1; ly <= S::ty; ++ly)
      for (int lx = -1; lx <= S::tx; ++lx) {
        const int s = cd::halo_slot<Dim>(lx, ly, lz);
        REQUIRE(s >= 0);
        REQUIRE(s < S::halo_voxels);
        CHECK(seen.insert(s).second);
        int x, y, z;
        cd::halo_coords<Dim>(s, x, y, z);
        CHECK(x == lx);
        CHECK(y == ly);
        CHECK(z == lz);
        inner += !cd::is_halo<Dim>(lx, ly, lz);
      }
  CHECK(int(seen.size()) == S::halo_voxels);
  CHECK(inner == S::voxels);
  // a neighbour step inside the box moves the slot by the box strides
  CHECK(cd::halo_slot<Dim>(1, 0, 0) - cd::halo_slot<Dim>(0, 0, 0) == 1);
  CHECK(cd::halo_slot<Dim>(0, 1, 0) - cd::halo_slot<Dim>(0, 0, 0) == S::sx);
}

TEST_CASE("cuda tiling: halo slots are a bijection onto the haloed box") {
  halo_roundtrip<3>();
  halo_roundtrip<2>();
  CHECK(cd::tile_shape<3>::halo_voxels == 1000);
  CHECK(cd::tile_shape<2>::halo_voxels == 34 * 18);
}

TEST_CASE("cuda keys: packed keys match the core's key layout and order like (distance, label)") {
  using kt = gv::detail::search::key_traits<float>;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> dist(0.0f, 100.0f);
  std::vector<std::pair<float, gv::label_t>> vals{{0.0f, 0}, {0.0f, 7}, {1.0f, 0}, {1.0f, 3},
                                                   {std::numeric_limits<float>::infinity(), 2}};
  for (int i = 0; i < 200; ++i) vals.push_back({dist(rng), gv::label_t(rng() % 1000)});
  for (const auto& [d, l] : vals) {
    const auto k = cd::pack(d, l);
    CHECK(k == kt::make(d, l));
    CHECK(cd::key_distance(k) == d);
    CHECK(cd::key_label(k) == l);
    CHECK(k != cd::unreached);
  }
  for (const auto& a : vals)
    for (const auto& b : vals) {
      const bool lex = a.first < b.first || (a.first == b.first && a.second < b.second);
      CHECK((cd::pack(a.first, a.second) < cd::pack(b.first, b.second)) == lex);
    }
  // distance-only words: float bits zero-extended, double bits as they are; order like the value
  for (int i = 0; i < 200; ++i) {
    const float a = dist(rng), b = dist(rng);
    CHECK((cd::distance_word(a) < cd::distance_word(b)) == (a < b));
    CHECK(cd::word_distance<float>(cd::distance_word(a)) == a);
    const double da = double(a) / 3.0, db = double(b) / 7.0;
    CHECK((cd::distance_word(da) < cd::distance_word(db)) == (da < db));
    CHECK(cd::word_distance<double>(cd::distance_word(da)) == da);
  }
  CHECK(cd::distance_word(std::numeric_limits<double>::infinity()) < cd::unreached);
  CHECK(cd::distance_word(std::numeric_limits<float>::infinity()) < cd::unreached);
}

TEST_CASE("cuda worklist: lists alternate and the grid never exceeds the tiles") {
  for (long long it = 0; it < 10; ++it) {
    CHECK(cd::current_list(it) != cd::next_list(it));
    CHECK(cd::next_list(it) == cd::current_list(it + 1));
  }
  CHECK(cd::blocks_for(5, 132, 4) == 5);
  CHECK(cd::blocks_for(100000, 132, 4) == 528);
  CHECK(cd::blocks_for(0, 132, 4) == 1);
  CHECK(cd::blocks_for(7, 0, 0) == 1);
  // memory model: float solve = 12 B/voxel + 12 B/tile (+ counters), within the 16 B/voxel budget
  const auto t = cd::make_tiling<3>(256, 256, 256);
  const double per_voxel = double(cd::solve_device_bytes<float>(t.voxels(), t.tiles())) / double(t.voxels());
  CHECK(per_voxel <= 16.0);
  CHECK(per_voxel >= 12.0);
  CHECK(cd::solve_device_bytes<double>(t.voxels(), t.tiles()) > cd::solve_device_bytes<float>(t.voxels(), t.tiles()));
}

TEST_CASE("cuda query boxes: placed inside the grid, around the query, open faces only where the grid goes on") {
  for (index_t n : {1, 5, 16, 17, 40, 100})
    for (index_t q = 0; q < n; ++q) {
      const auto a = cd::place_box(q, n, 16);
      CHECK(a.len == (n < 16 ? n : 16));
      CHECK(a.lo >= 0);
      CHECK(a.lo + a.len <= n);
      CHECK(q >= a.lo);
      CHECK(q < a.lo + a.len);
      CHECK(cd::open_face(a, 0, n) == (a.lo > 0));
      CHECK(cd::open_face(a, a.len - 1, n) == (a.lo + a.len < n));
      if (a.len > 2) CHECK_FALSE(cd::open_face(a, 1, n));
    }
  CHECK(cd::query_box_shape<3>::voxels == 4096);
  CHECK(cd::query_box_shape<2>::voxels == 4096);
}

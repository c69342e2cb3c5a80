// Tests of geovoronoi/config.hpp: the index and label types and their sentinels.

#include <doctest/doctest.h>

#include <geovoronoi/config.hpp>

#include <cstdint>
#include <type_traits>

namespace {
namespace gv = geovoronoi;

static_assert(std::is_same_v<gv::index_t, std::int64_t>, "linear indices are 64-bit signed");
static_assert(std::is_same_v<gv::label_t, std::int32_t>, "labels are 32-bit signed");
static_assert(gv::no_label == -1 && gv::no_index == -1);
static_assert(GEOVORONOI_VERSION_MAJOR >= 0 && GEOVORONOI_VERSION_MINOR >= 0 && GEOVORONOI_VERSION_PATCH >= 0);

// GEOVORONOI_HOST_DEVICE expands to nothing for a plain C++ compiler
GEOVORONOI_HOST_DEVICE constexpr int twice(int x) { return 2 * x; }
static_assert(twice(21) == 42);

TEST_CASE("config: sentinels are distinct from valid indices and labels") {
  CHECK(gv::no_index < 0);
  CHECK(gv::no_label < 0);
  // a 2048^3 volume has more voxels than a 32-bit index can hold
  const gv::index_t big = gv::index_t(2048) * 2048 * 2048;
  CHECK(big > gv::index_t(INT32_MAX));
  CHECK(twice(3) == 6);
}

}  // namespace

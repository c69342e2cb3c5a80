// The RGB canvas: set/get, fill and paste clip to the picture, crop and hstack keep pixels in place.
#include <geovoronoi/io/rgb_image.hpp>

#include <doctest/doctest.h>

namespace gio = geovoronoi::io;

TEST_CASE("rgb_image: drawing clips to the picture; crop and hstack keep pixels in place") {
  gio::rgb_image a(4, 3, {1, 2, 3});
  a.set(-1, 0, {9, 9, 9});  // outside: ignored
  a.set(4, 2, {9, 9, 9});
  a.fill(2, 1, 10, 10, {200, 0, 0});  // runs over the edge
  CHECK(a.get(0, 0) == gio::rgb{1, 2, 3});
  CHECK(a.get(3, 2) == gio::rgb{200, 0, 0});
  CHECK(a.get(1, 1) == gio::rgb{1, 2, 3});
  const auto c = gio::crop(a, 2, 1, 5, 5);  // clipped to 2 x 2
  CHECK(c.width == 2);
  CHECK(c.height == 2);
  CHECK(c.get(0, 0) == gio::rgb{200, 0, 0});
  const gio::rgb_image b(2, 5, {0, 0, 255});
  const auto h = gio::hstack(a, b, {7, 7, 7});
  CHECK(h.width == 6);
  CHECK(h.height == 5);
  CHECK(h.get(3, 2) == gio::rgb{200, 0, 0});
  CHECK(h.get(4, 4) == gio::rgb{0, 0, 255});
  CHECK(h.get(0, 4) == gio::rgb{7, 7, 7});  // below the shorter picture
}

// A user's program: compute a small diagram and check one value, exiting non-zero on failure.
// With CONSUMER_EXPECT_ZLIB defined (the consumer's CMake found zlib, so geovoronoi's configure did
// too), it also writes and reads back a compressed MetaImage without linking zlib itself: that part
// comes with the geovoronoi::geovoronoi target.
#include <geovoronoi.hpp>
#include <geovoronoi/io/metaimage.hpp>

#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <unistd.h>

#ifndef CONSUMER_EXPECT_ZLIB
#define CONSUMER_EXPECT_ZLIB 0
#endif

int main() {
  namespace gv = geovoronoi;
  const gv::grid<3> g({8, 8, 8});
  const std::vector<float> stiffness(static_cast<std::size_t>(g.size()), 1.0f);
  const auto d = gv::voronoi(gv::seq, g, stiffness, std::vector<gv::coord<3>>{{0, 0, 0}, {7, 7, 7}},
                             gv::uniform{}, gv::connectivity<6>{});
  bool ok = d.distance({3, 0, 0}) == 3.0f && d.label({1, 1, 1}) == 0 && d.label({6, 6, 6}) == 1;
  std::printf("consumer: diagram %s\n", ok ? "ok" : "WRONG");

  const bool zlib = gv::io::metaimage_has_zlib;
  if (zlib != bool(CONSUMER_EXPECT_ZLIB)) {
    std::printf("consumer: compressed MetaImage support is %s, expected %s\n", zlib ? "on" : "off",
                CONSUMER_EXPECT_ZLIB ? "on" : "off");
    ok = false;
  }
  if (zlib) {
    const auto path = (std::filesystem::temp_directory_path() /
                       ("geovoronoi-consumer-" + std::to_string(::getpid()) + ".mha")).string();
    gv::io::metaimage_write_options z;
    z.compress = true;
    gv::io::write_metaimage(path, d.label, z);
    const auto back = gv::io::read_metaimage_image<gv::label_t, 3>(path);
    std::filesystem::remove(path);
    const bool same = back.values() == d.label.values();
    std::printf("consumer: compressed MetaImage round trip %s\n", same ? "ok" : "WRONG");
    ok = ok && same;
  }
  return ok ? 0 : 1;
}

// A user's program on the core target: compute a small diagram and check it, exiting non-zero on
// failure. CONSUMER_EXPECT_ZLIB / CONSUMER_EXPECT_PNG (1 when geovoronoi was configured with zlib /
// libpng) say what geovoronoi::geovoronoi must bring by itself: compressed MetaImage support and a
// working io::write_png, without this program finding or linking zlib or libpng.
#include <geovoronoi.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/png.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <unistd.h>

#ifndef CONSUMER_EXPECT_ZLIB
#error "CONSUMER_EXPECT_ZLIB must be defined to 0 or 1"
#endif
#ifndef CONSUMER_EXPECT_PNG
#error "CONSUMER_EXPECT_PNG must be defined to 0 or 1"
#endif

namespace {
std::string temp_file(const char* ext) {
  return (std::filesystem::temp_directory_path() / ("geovoronoi-consumer-" + std::to_string(::getpid()) + ext))
      .string();
}
}  // namespace

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
    const auto path = temp_file(".mha");
    gv::io::metaimage_write_options z;
    z.compress = true;
    gv::io::write_metaimage(path, d.label, z);
    const auto back = gv::io::read_metaimage_image<gv::label_t, 3>(path);
    std::filesystem::remove(path);
    const bool same = back.values() == d.label.values();
    std::printf("consumer: compressed MetaImage round trip %s\n", same ? "ok" : "WRONG");
    ok = ok && same;
  }

  // write_png works exactly when libpng came with the target (else it throws io_error).
  const auto png = temp_file(".png");
  bool wrote = false;
  try {
    gv::io::write_png(png, gv::io::rgb_image(4, 3, {200, 100, 50}));
    std::ifstream f(png, std::ios::binary);
    char sig[8] = {};
    f.read(sig, 8);
    wrote = f.gcount() == 8 && std::string(sig + 1, 3) == "PNG";
  } catch (const gv::io::io_error& e) {
    std::printf("consumer: write_png: %s\n", e.what());
  }
  std::filesystem::remove(png);
  std::printf("consumer: write_png %s (expected %s)\n", wrote ? "works" : "unavailable",
              CONSUMER_EXPECT_PNG ? "to work" : "unavailable");
  ok = ok && wrote == bool(CONSUMER_EXPECT_PNG);
  return ok ? 0 : 1;
}

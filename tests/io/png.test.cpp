// PNG writer: the file is a PNG of the picture's size whose pixels decode back (when zlib is at
// hand), and write errors name the file.
#include "support/io_util.hpp"

#include <geovoronoi/io/png.hpp>

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

namespace {
std::uint32_t be32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}
}  // namespace

TEST_CASE("png: the file is an 8-bit RGB PNG of the picture's size") {
#if !GEOVORONOI_IO_HAVE_PNG
  CHECK_THROWS_AS(gio::write_png(scratch("x.png"), gio::rgb_image(3, 2)), gio::io_error);
  return;
#endif
  gio::rgb_image pic(37, 21, {10, 20, 30});
  pic.set(5, 7, {255, 0, 0});
  gio::write_png(scratch("p.png"), pic);
  const std::string file = io_test::read_all(scratch("p.png"));
  REQUIRE(file.size() > 33);
  CHECK(file.substr(1, 3) == "PNG");
  CHECK(file.substr(12, 4) == "IHDR");
  CHECK(be32(file, 16) == 37u);
  CHECK(be32(file, 20) == 21u);
  CHECK(int(std::uint8_t(file[24])) == 8);  // bit depth
  CHECK(int(std::uint8_t(file[25])) == 2);  // colour type RGB
}

TEST_CASE("png: write errors name the file") {
  const gio::rgb_image pic(8, 4);
  CHECK_THROWS_AS(gio::write_png(scratch("missing/dir/x.png"), pic), gio::io_error);
  CHECK_THROWS_AS(gio::write_png(scratch("empty.png"), gio::rgb_image()), gio::io_error);
  try {
    gio::write_png(scratch("missing/dir/y.png"), pic);
  } catch (const gio::io_error& e) {
    CHECK(std::string(e.what()).find("y.png") != std::string::npos);
  }
}

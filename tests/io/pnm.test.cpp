// PGM/PPM import: P2, P3, P5, P6 (8 and 16 bit), comments, channel choice, extrusion, bad files.
#include "support/io_util.hpp"

#include <geovoronoi/io/pnm.hpp>
#include <geovoronoi/io/read.hpp>

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

TEST_CASE("pnm: ASCII and binary PGM read the same picture, row 0 at y = 0") {
  io_test::write_text(scratch("a.pgm"), "P2\n# a comment\n3 2 # inline\n255\n0 10 20\n30 40 255\n");
  io_test::write_text(scratch("b.pgm"), std::string("P5\n3 2\n255\n") + std::string("\0\x0a\x14\x1e\x28\xff", 6));
  for (const char* name : {"a.pgm", "b.pgm"}) {
    const auto v = gio::read_pnm<float>(scratch(name));
    CHECK(v.dims == 2);
    CHECK(v.extents == std::array<index_t, 3>{3, 2, 1});
    CHECK(v.data == std::vector<float>{0, 10, 20, 30, 40, 255});
  }
  // 16-bit binary samples are big-endian
  io_test::write_text(scratch("c.pgm"), std::string("P5 2 1 65535\n") + std::string("\x01\x00\xff\xfe", 4));
  CHECK(gio::read_pnm<int>(scratch("c.pgm")).data == std::vector<int>{256, 65534});
}

TEST_CASE("pnm: PPM channel choice and extrusion to n slices") {
  io_test::write_text(scratch("c.ppm"), "P3\n2 1\n255\n10 20 30  40 50 60\n");
  io_test::write_text(scratch("d.ppm"), std::string("P6\n2 1\n255\n") + "\x0a\x14\x1e\x28\x32\x3c");
  for (const char* name : {"c.ppm", "d.ppm"}) {
    gio::pnm_options o;
    CHECK(gio::read_pnm<float>(scratch(name), o).data == std::vector<float>{10, 40});
    o.channel = 2;
    CHECK(gio::read_pnm<float>(scratch(name), o).data == std::vector<float>{30, 60});
    o.channel = -1;
    CHECK(gio::read_pnm<float>(scratch(name), o).data == std::vector<float>{20, 50});
  }
  gio::pnm_options o;
  o.extrude = 3;
  o.spacing = {0.15, 0.15, 0.5};
  const auto v = gio::read_pnm<float>(scratch("c.ppm"), o);
  CHECK(v.dims == 3);
  CHECK(v.extents == std::array<index_t, 3>{2, 1, 3});
  CHECK(v.data == std::vector<float>{10, 40, 10, 40, 10, 40});
  CHECK(v.geometry<3>().spacing(2) == 0.5);
  gio::read_options r;
  r.extrude = 2;
  CHECK(gio::read_volume<float>(scratch("c.ppm"), r).extents[2] == 2);
}

TEST_CASE("pnm: a written PGM reads back") {
  const std::vector<double> values{0, 12.4, 300, -5, 128, 255};
  gio::write_pgm(scratch("w.pgm"), values.data(), 3, 2);
  CHECK(gio::read_pnm<int>(scratch("w.pgm")).data == std::vector<int>{0, 12, 255, 0, 128, 255});
}

TEST_CASE("pnm: bad files throw io_error naming the file and the problem") {
  using io_test::expect_io_error;
  auto read = [](const std::string& name, const std::string& text, index_t extrude = 1) {
    io_test::write_text(scratch(name), text);
    return [name, extrude] {
      gio::pnm_options o;
      o.extrude = extrude;
      gio::read_pnm<float>(scratch(name), o);
    };
  };
  expect_io_error(read("m.pgm", "P7\n1 1\n255\n\0"), "m.pgm", "magic");
  expect_io_error(read("e.pgm", ""), "e.pgm", "magic");
  expect_io_error(read("w.pgm", "P5\nx 1\n255\n"), "w.pgm", "width");
  expect_io_error(read("z.pgm", "P5\n0 1\n255\n"), "z.pgm", "empty");
  expect_io_error(read("mv.pgm", "P5\n1 1\n70000\n\0\0"), "mv.pgm", "maxval");
  expect_io_error(read("t.pgm", "P5\n4 4\n255\nabc"), "t.pgm", "truncated");
  expect_io_error(read("h.pgm", "P5\n100000000 100000000\n255\nabc"), "h.pgm", "absurd");
  expect_io_error(read("big.pgm", "P2\n1000 1000\n255\n1 2 3\n"), "big.pgm", "samples");
  expect_io_error(read("a.pgm", "P2\n2 1\n255\n1 x\n"), "a.pgm", "pixel value");
  expect_io_error(read("over.pgm", "P2\n2 1\n15\n1 16\n"), "over.pgm", "exceeds maxval");
  expect_io_error(read("x.pgm", "P2\n2 1\n255\n1 2\n", 0), "x.pgm", "extrusion");
  expect_io_error(read("x2.pgm", "P2\n2 1\n255\n1 2\n", 2000000), "x2.pgm", "extrusion");
  expect_io_error([] { gio::read_volume<float>(scratch("x.tiff")); }, "x.tiff", "unknown volume format");
}

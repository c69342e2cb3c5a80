// NumPy .npy: round trips of every element type and shape order, hand-written headers (Fortran
// order, big-endian, bool, version 2.0), and bad files.
#include "support/io_util.hpp"

#include <geovoronoi/io/npy.hpp>

#include <cstdint>
#include <limits>

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

namespace {

std::string npy_header(const std::string& dict, int major = 1) {
  std::string h = "\x93NUMPY";
  h += char(major);
  h += '\0';
  std::string d = dict;
  const std::size_t pre = major == 1 ? 10 : 12;
  while ((pre + d.size() + 1) % 64) d += ' ';
  d += '\n';
  const std::size_t n = d.size();
  h += char(n & 0xff);
  h += char((n >> 8) & 0xff);
  if (major != 1) h += std::string(2, '\0');
  return h + d;
}

template <class T>
void round_trip(const std::string& name) {
  std::vector<T> values;
  for (int i = 0; i < 24; ++i) values.push_back(static_cast<T>(std::is_signed_v<T> ? i * 5 - 50 : i * 9));
  gio::write_npy(scratch(name), values.data(), {2, 3, 4});
  const auto a = gio::read_npy<T>(scratch(name));
  CHECK(a.shape == std::vector<index_t>{2, 3, 4});
  CHECK(!a.fortran_order);
  CHECK(a.stored == gio::element_type_of<T>());
  CHECK(a.data == values);
  const auto d = gio::read_npy<double>(scratch(name));
  for (std::size_t i = 0; i < values.size(); ++i) CHECK(d.data[i] == double(values[i]));
  // the header is padded so the data start on a 64-byte boundary, as numpy writes it
  const std::string text = io_test::read_all(scratch(name));
  CHECK((text.size() - values.size() * sizeof(T)) % 64 == 0);
}

}  // namespace

TEST_CASE("npy: round trip of every element type") {
  round_trip<std::int8_t>("i1.npy");
  round_trip<std::uint8_t>("u1.npy");
  round_trip<std::int16_t>("i2.npy");
  round_trip<std::uint16_t>("u2.npy");
  round_trip<std::int32_t>("i4.npy");
  round_trip<std::uint32_t>("u4.npy");
  round_trip<std::int64_t>("i8.npy");
  round_trip<std::uint64_t>("u8.npy");
  round_trip<float>("f4.npy");
  round_trip<double>("f8.npy");
}

TEST_CASE("npy: images are written as [z, y, x] in C order, which is the x-fastest layout") {
  const geovoronoi::grid<3> g({4, 3, 2});
  geovoronoi::image<float, 3> img(g);
  for (index_t v = 0; v < img.size(); ++v) img[v] = float(v);
  gio::write_npy(scratch("img.npy"), img);
  const auto a = gio::read_npy<float>(scratch("img.npy"));
  CHECK(a.shape == std::vector<index_t>{2, 3, 4});
  CHECK(io_test::read_all(scratch("img.npy")).find("'shape': (2, 3, 4)") != std::string::npos);
  const auto back = gio::read_npy_image<float, 3>(scratch("img.npy"));
  CHECK(back.geometry().extents() == g.extents());
  CHECK(back({3, 1, 1}) == img({3, 1, 1}));
  CHECK(back.values() == img.values());
  // 1D arrays carry numpy's one-element tuple
  gio::write_npy(scratch("one.npy"), std::vector<std::int64_t>{1, 2, 3});
  CHECK(io_test::read_all(scratch("one.npy")).find("'shape': (3,)") != std::string::npos);
  CHECK(gio::read_npy<std::int64_t>(scratch("one.npy")).data == std::vector<std::int64_t>{1, 2, 3});
  // 2D images: (ny, nx)
  geovoronoi::image<std::int32_t, 2> flat(geovoronoi::grid<2>({5, 2}));
  for (index_t v = 0; v < flat.size(); ++v) flat[v] = std::int32_t(v);
  gio::write_npy(scratch("flat.npy"), flat);
  CHECK(gio::read_npy<int>(scratch("flat.npy")).shape == std::vector<index_t>{2, 5});
  CHECK(gio::read_npy_image<int, 2>(scratch("flat.npy")).values() == flat.values());
}

TEST_CASE("npy: hand-written headers: Fortran order, big-endian, bool, version 2.0, double quotes") {
  const float le[6] = {1, 2, 3, 4, 5, 6};
  io_test::write_bytes(scratch("fortran.npy"), npy_header("{'descr': '<f4', 'fortran_order': True, 'shape': (3, 2), }"), le, sizeof le);
  const auto f = gio::read_npy_volume<float>(scratch("fortran.npy"));
  CHECK(f.extents == std::array<index_t, 3>{3, 2, 1});  // Fortran (nx, ny): first index fastest
  CHECK(f.data == std::vector<float>{1, 2, 3, 4, 5, 6});
  const auto c = gio::read_npy_volume<float>(scratch("fortran.npy"));
  (void)c;
  // big-endian int32 1, 256, -2
  const unsigned char be[12] = {0, 0, 0, 1, 0, 0, 1, 0, 0xff, 0xff, 0xff, 0xfe};
  io_test::write_bytes(scratch("be.npy"), npy_header("{'descr': '>i4', 'fortran_order': False, 'shape': (3,), }"), be, sizeof be);
  CHECK(gio::read_npy<std::int64_t>(scratch("be.npy")).data == std::vector<std::int64_t>{1, 256, -2});
  const unsigned char bools[3] = {0, 1, 7};
  io_test::write_bytes(scratch("b.npy"), npy_header("{'descr': '|b1', 'fortran_order': False, 'shape': (3,), }"), bools, 3);
  CHECK(gio::read_npy<int>(scratch("b.npy")).data == std::vector<int>{0, 1, 1});
  const double d[2] = {0.5, -0.25};
  io_test::write_bytes(scratch("v2.npy"), npy_header("{\"descr\": \"<f8\", \"fortran_order\": False, \"shape\": (2,)}", 2), d, sizeof d);
  CHECK(gio::read_npy<double>(scratch("v2.npy")).data == std::vector<double>{0.5, -0.25});
}

TEST_CASE("npy: bad files throw io_error naming the file and the problem") {
  using io_test::expect_io_error;
  auto read = [](const std::string& p) { return [p] { gio::read_npy_volume<float>(p); }; };
  const float data[4] = {1, 2, 3, 4};
  auto file = [&](const std::string& name, const std::string& dict, std::size_t bytes = sizeof data) {
    io_test::write_bytes(scratch(name), npy_header(dict), data, bytes);
    return scratch(name);
  };
  io_test::write_text(scratch("magic.npy"), "PK\3\4 this is a zip");
  expect_io_error(read(scratch("magic.npy")), "magic.npy", "magic");
  expect_io_error(read(file("short.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 3), }")), "short.npy", "truncated");
  expect_io_error(read(file("long.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (3,), }")), "long.npy", "more than the shape");
  expect_io_error(read(file("huge.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (100000, 100000, 100000), }")), "huge.npy", "2^40");
  expect_io_error(read(file("big.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (100000, 100000), }")), "big.npy", "truncated");
  expect_io_error(read(file("cplx.npy", "{'descr': '<c8', 'fortran_order': False, 'shape': (2,), }")), "cplx.npy", "dtype");
  expect_io_error(read(file("obj.npy", "{'descr': '|O', 'fortran_order': False, 'shape': (2,), }")), "obj.npy", "dtype");
  expect_io_error(read(file("nodescr.npy", "{'fortran_order': False, 'shape': (4,), }")), "nodescr.npy", "descr");
  expect_io_error(read(file("noshape.npy", "{'descr': '<f4', 'fortran_order': False, }")), "noshape.npy", "shape");
  expect_io_error(read(file("badshape.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (2, x), }")), "badshape.npy", "dimension");
  expect_io_error(read(file("fo.npy", "{'descr': '<f4', 'fortran_order': Maybe, 'shape': (4,), }")), "fo.npy", "fortran_order");
  // exactly True or False, as NumPy's own reader (ast.literal_eval, then a bool check) requires: a
  // value such as 'NotTrue' read as True would silently reverse the axes
  for (const char* bad : {"NotTrue", "Falsey", "TrueFalse", "'True'", "1", "true"}) {
    INFO(bad);
    expect_io_error(read(file("fo2.npy", std::string("{'descr': '<f4', 'fortran_order': ") + bad + ", 'shape': (4,), }")),
                    "fo2.npy", "fortran_order");
  }
  CHECK(gio::read_npy<float>(file("fo3.npy", "{'descr': '<f4', 'fortran_order':True, 'shape': (4,), }")).fortran_order);
  CHECK_FALSE(gio::read_npy<float>(file("fo4.npy", "{'descr': '<f4', 'fortran_order':  False , 'shape': (4,)}")).fortran_order);
  expect_io_error(read(file("4d.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (1, 1, 2, 2), }")), "4d.npy", "dimensions");
  expect_io_error(read(file("zero.npy", "{'descr': '<f4', 'fortran_order': False, 'shape': (0, 4), }", 0)), "zero.npy", "empty");
  std::string h = npy_header("{'descr': '<f4', 'fortran_order': False, 'shape': (4,), }");
  h[8] = char(0xff);
  h[9] = char(0x7f);
  io_test::write_text(scratch("hlen.npy"), h);
  expect_io_error(read(scratch("hlen.npy")), "hlen.npy", "past the end");
  std::string v9 = h;
  v9[6] = 9;
  io_test::write_text(scratch("v9.npy"), v9);
  expect_io_error(read(scratch("v9.npy")), "v9.npy", "version");
  // every truncation of a valid file
  gio::write_npy(scratch("ok.npy"), data, {2, 2});
  const std::string text = io_test::read_all(scratch("ok.npy"));
  for (std::size_t cut = 0; cut < text.size(); ++cut) {
    io_test::write_text(scratch("cut.npy"), text.substr(0, cut));
    CHECK_THROWS_AS(gio::read_npy<float>(scratch("cut.npy")), gio::io_error);
  }
}

TEST_CASE("npy: float values an integer type cannot hold are an error naming the value, on read and write") {
  const float data[3] = {1.0f, std::numeric_limits<float>::infinity(), 2.0f};
  io_test::write_bytes(scratch("finf.npy"), npy_header("{'descr': '<f4', 'fortran_order': False, 'shape': (3,), }"), data,
                       sizeof data);
  io_test::expect_io_error([] { gio::read_npy<std::int16_t>(scratch("finf.npy")); }, "finf.npy", "element 1 is +inf");
  CHECK(gio::read_npy<double>(scratch("finf.npy")).data[1] == std::numeric_limits<double>::infinity());
  const double big[2] = {0.0, 1e20};
  io_test::expect_io_error([&] { gio::write_npy(scratch("wbig.npy"), big, {2}, gio::element_type::int64); }, "wbig.npy",
                           "element 1 is 1e+20");
}

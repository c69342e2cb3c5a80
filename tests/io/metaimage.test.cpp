// MetaImage: round trips of every element type (.mhd and .mha, both byte orders, compressed),
// channels interleaved and planar, hand-written SOFA and ITK style headers, and bad files.
#include "support/io_util.hpp"

#include <geovoronoi/io/metaimage.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <new>

// GCC flags the free() below as mismatched with operator new, which these replacements define
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif

// This test binary counts the largest single allocation and can make big ones fail, to check that
// readers bound their allocations by what a file really holds and name sizes when memory runs out.
namespace alloc_probe {
std::atomic<std::size_t> largest{0};
std::atomic<std::size_t> fail_from{0};  // 0: never fail
}  // namespace alloc_probe

void* operator new(std::size_t n) {
  std::size_t seen = alloc_probe::largest.load();
  while (n > seen && !alloc_probe::largest.compare_exchange_weak(seen, n)) {
  }
  const std::size_t limit = alloc_probe::fail_from.load();
  if (limit != 0 && n >= limit) throw std::bad_alloc();
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

namespace {

template <class T>
gio::volume<T> sample_volume(int channels = 1) {
  gio::volume<T> v;
  v.extents = {5, 4, 3};
  v.spacing = {0.5, 0.25, 2.0};
  v.origin = {-1.5, 3.0, 0.125};
  v.channels = channels;
  v.data.resize(std::size_t(v.voxels() * channels));
  for (std::size_t i = 0; i < v.data.size(); ++i) {
    // values that exercise the type's range: negatives for signed types, large ones for wide types
    double x = double(i % 97) - (std::is_signed_v<T> ? 40.0 : 0.0);
    if (sizeof(T) >= 4 && i % 7 == 0) x *= 1000003.0;
    if (std::is_floating_point_v<T>) x += 0.25;
    v.data[i] = static_cast<T>(x);
  }
  return v;
}

template <class T>
void round_trip(const std::string& name, const gio::metaimage_write_options& opt = {}) {
  const auto v = sample_volume<T>();
  gio::write_metaimage(scratch(name), v, opt);
  const auto back = gio::read_metaimage<T>(scratch(name));
  CHECK(back.extents == v.extents);
  CHECK(back.spacing == v.spacing);
  CHECK(back.origin == v.origin);
  CHECK(back.channels == 1);
  CHECK(back.stored == gio::element_type_of<T>());
  CHECK(back.data == v.data);
  // conversion on read: every element type reads as double with the same values
  const auto as_double = gio::read_metaimage<double>(scratch(name));
  REQUIRE(as_double.data.size() == v.data.size());
  for (std::size_t i = 0; i < v.data.size(); ++i) CHECK(as_double.data[i] == double(v.data[i]));
}

template <class T>
void round_trips(const std::string& tag) {
  round_trip<T>(tag + ".mhd");
  round_trip<T>(tag + ".mha");
  gio::metaimage_write_options msb;
  msb.msb = true;
  round_trip<T>(tag + "-msb.mha", msb);
  if (gio::metaimage_has_zlib) {
    gio::metaimage_write_options z;
    z.compress = true;
    round_trip<T>(tag + "-z.mhd", z);
    round_trip<T>(tag + "-z.mha", z);
  }
}

}  // namespace

TEST_CASE("metaimage: round trip of every element type, .mhd and .mha, both byte orders, compressed") {
  round_trips<std::int8_t>("i8");
  round_trips<std::uint8_t>("u8");
  round_trips<std::int16_t>("i16");
  round_trips<std::uint16_t>("u16");
  round_trips<std::int32_t>("i32");
  round_trips<std::uint32_t>("u32");
  round_trips<std::int64_t>("i64");
  round_trips<std::uint64_t>("u64");
  round_trips<float>("f32");
  round_trips<double>("f64");
}

TEST_CASE("metaimage: conversion on write, e.g. float data stored as MET_USHORT") {
  auto v = sample_volume<float>();
  for (auto& x : v.data) x = std::fmod(std::abs(std::round(x)), 65536.0f);  // values uint16 can hold
  gio::metaimage_write_options opt;
  opt.type = gio::element_type::uint16;
  gio::write_metaimage(scratch("conv.mha"), v, opt);
  CHECK(io_test::read_all(scratch("conv.mha")).find("ElementType = MET_USHORT") != std::string::npos);
  const auto back = gio::read_metaimage<float>(scratch("conv.mha"));
  CHECK(back.stored == gio::element_type::uint16);
  for (std::size_t i = 0; i < v.data.size(); ++i) CHECK(back.data[i] == float(std::uint16_t(v.data[i])));
}

TEST_CASE("metaimage: images (2D and 3D) round trip with their grids") {
  const geovoronoi::grid<2> g2({7, 3}, {0.5, 2.0}, {1.0, -1.0});
  geovoronoi::image<std::int32_t, 2> a(g2);
  for (index_t v = 0; v < a.size(); ++v) a[v] = std::int32_t(v * 3 - 10);
  gio::write_metaimage(scratch("img2.mhd"), a);
  const auto b = gio::read_metaimage_image<std::int32_t, 2>(scratch("img2.mhd"));
  CHECK(b.geometry() == g2);
  CHECK(b.values() == a.values());
  CHECK(io_test::read_all(scratch("img2.mhd")).find("NDims = 2") != std::string::npos);
  // a 3-slice volume is not a 2D image
  gio::write_metaimage(scratch("vol3.mha"), sample_volume<float>());
  io_test::expect_io_error([] { gio::read_metaimage_image<float, 2>(scratch("vol3.mha")); }, "vol3.mha", "2D");
}

TEST_CASE("metaimage: several channels, interleaved (ITK) and planar (SOFA) on disk, planar in memory") {
  const auto v = sample_volume<float>(3);
  const std::size_t n = std::size_t(v.voxels());
  for (auto layout : {gio::channel_layout::interleaved, gio::channel_layout::planar}) {
    gio::metaimage_write_options opt;
    opt.layout = layout;
    const std::string name = layout == gio::channel_layout::planar ? "ch-planar.mhd" : "ch-inter.mhd";
    gio::write_metaimage(scratch(name), v, opt);
    const auto back = gio::read_metaimage<float>(scratch(name), layout);
    CHECK(back.channels == 3);
    CHECK(back.data == v.data);
    // the raw bytes are in the promised order
    const std::string raw = io_test::read_all(scratch(layout == gio::channel_layout::planar ? "ch-planar.raw" : "ch-inter.raw"));
    REQUIRE(raw.size() == v.data.size() * 4);
    const std::size_t voxel = 7, channel = 2;
    const std::size_t at = layout == gio::channel_layout::planar ? channel * n + voxel : voxel * 3 + channel;
    float x;
    std::memcpy(&x, raw.data() + at * 4, 4);
    CHECK(x == v.data[channel * n + voxel]);
    CHECK(back.channel<3>(2)[index_t(voxel)] == v.data[channel * n + voxel]);
  }
}

TEST_CASE("metaimage: SOFA style header (HeaderSize = -1, Position, Orientation, planar channels, MET_DOUBLE)") {
  // 3 x 2 x 1 voxels, 2 channels stored one whole volume after the other, after 16 bytes of junk
  std::vector<double> planar(12);
  for (std::size_t i = 0; i < 12; ++i) planar[i] = double(i) * 1.5 - 4.0;
  std::string raw(16, 'J');
  raw.append(reinterpret_cast<const char*>(planar.data()), planar.size() * sizeof(double));
  io_test::write_text(scratch("sofa.raw"), raw);
  io_test::write_text(scratch("sofa.mhd"),
                      "ObjectType = Image\n"
                      "NDims = 3\n"
                      "ElementNumberOfChannels = 2\n"
                      "DimSize = 3 2 1\n"
                      "ElementType = MET_DOUBLE\n"
                      "HeaderSize = -1\n"
                      "ElementSpacing = 0.15 0.15 0.15\n"
                      "Position = 1 2 3\n"
                      "Orientation = 1 0 0 0 1 0 0 0 1\n"
                      "isPerpective = 0\n"
                      "ElementDataFile = sofa.raw\n");
  const auto v = gio::read_metaimage<double>(scratch("sofa.mhd"), gio::channel_layout::planar);
  CHECK(v.extents == std::array<index_t, 3>{3, 2, 1});
  CHECK(v.channels == 2);
  CHECK(v.spacing[0] == 0.15);
  CHECK(v.origin == std::array<double, 3>{1, 2, 3});
  CHECK(v.data == planar);
  // SOFA's older spellings: scale3d / translation, and a 4th dimension as planar channels
  io_test::write_bytes(scratch("sofa4.mha"),
                       "ObjectType = Image\nNDims = 4\nDimSize = 3 2 1 2\nElementType = MET_DOUBLE\n"
                       "scale3d = 2 2 2\ntranslation = 0 0 5\nElementDataFile = LOCAL\n",
                       planar.data(), planar.size() * sizeof(double));
  const auto w = gio::read_metaimage<double>(scratch("sofa4.mha"));
  CHECK(w.channels == 2);
  CHECK(w.spacing[2] == 2.0);
  CHECK(w.origin[2] == 5.0);
  CHECK(w.data == planar);
}

TEST_CASE("metaimage: ITK style header (.mha, interleaved vector pixels, MSB short, ElementSize)") {
  // 2 x 2 x 1 voxels of 3-component big-endian shorts, interleaved per voxel
  std::string data;
  for (int v = 0; v < 4; ++v)
    for (int c = 0; c < 3; ++c) {
      const std::int16_t x = std::int16_t(100 * c - v);
      data += char((std::uint16_t(x) >> 8) & 0xff);
      data += char(std::uint16_t(x) & 0xff);
    }
  io_test::write_text(scratch("itk.mha"),
                      "ObjectType = Image\nNDims = 3\nBinaryData = True\nBinaryDataByteOrderMSB = True\n"
                      "CompressedData = False\nTransformMatrix = 1 0 0 0 1 0 0 0 1\nOffset = 0 0 -7.5\n"
                      "CenterOfRotation = 0 0 0\nAnatomicalOrientation = RAI\nElementSize = 0.3 0.3 1.2\n"
                      "DimSize = 2 2 1\nElementNumberOfChannels = 3\nElementType = MET_SHORT_ARRAY\n"
                      "ElementDataFile = LOCAL\n" + data);
  const auto v = gio::read_metaimage<int>(scratch("itk.mha"));
  CHECK(v.channels == 3);
  CHECK(v.spacing[2] == 1.2);
  CHECK(v.origin[2] == -7.5);
  for (int vox = 0; vox < 4; ++vox)
    for (int c = 0; c < 3; ++c) CHECK(v.data[std::size_t(c * 4 + vox)] == 100 * c - vox);
}

TEST_CASE("metaimage: HeaderSize > 0 skips bytes before the data") {
  const std::uint8_t bytes[] = {9, 9, 9, 1, 2, 3, 4};
  io_test::write_bytes(scratch("skip.raw"), "", bytes, sizeof bytes);
  io_test::write_text(scratch("skip.mhd"), "NDims = 2\nDimSize = 2 2\nHeaderSize = 3\nElementType = MET_UCHAR\nElementDataFile = skip.raw\n");
  const auto v = gio::read_metaimage<int>(scratch("skip.mhd"));
  CHECK(v.data == std::vector<int>{1, 2, 3, 4});
}

TEST_CASE("metaimage: malformed, truncated, inconsistent and lying files throw io_error naming the file") {
  using io_test::expect_io_error;
  const std::string base = "ObjectType = Image\nNDims = 3\nElementType = MET_FLOAT\n";
  auto mha = [&](const std::string& name, const std::string& header, std::size_t data_bytes = 0) {
    io_test::write_text(scratch(name), header + std::string(data_bytes, '\0'));
    return scratch(name);
  };
  auto read = [](const std::string& p) { return [p] { gio::read_metaimage<float>(p); }; };
  expect_io_error(read(scratch("does-not-exist.mha")), "does-not-exist.mha", "cannot open");
  expect_io_error(read(mha("trunc.mha", base + "DimSize = 4 4 4\nElementDataFile = LOCAL\n", 100)), "trunc.mha", "truncated");
  expect_io_error(read(mha("peta.mha", base + "DimSize = 1000000 1000000 1000000\nElementDataFile = LOCAL\n", 8)), "peta.mha", "2^40");
  expect_io_error(read(mha("tera.mha", base + "DimSize = 100000 100000 10\nElementDataFile = LOCAL\n", 8)), "tera.mha", "bytes");
  expect_io_error(read(mha("nodata.mha", base + "DimSize = 2 2 2\n")), "nodata.mha", "ElementDataFile");
  expect_io_error(read(mha("nodims.mha", "NDims = 3\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n")), "nodims.mha", "DimSize");
  expect_io_error(read(mha("notype.mha", "NDims = 1\nDimSize = 2\nElementDataFile = LOCAL\n", 8)), "notype.mha", "ElementType");
  expect_io_error(read(mha("badtype.mha", "NDims = 1\nDimSize = 2\nElementType = MET_QUATERNION\nElementDataFile = LOCAL\n", 8)), "badtype.mha", "MET_QUATERNION");
  expect_io_error(read(mha("count.mha", base + "DimSize = 2 2\nElementDataFile = LOCAL\n", 32)), "count.mha", "NDims");
  expect_io_error(read(mha("neg.mha", base + "DimSize = 2 -2 2\nElementDataFile = LOCAL\n", 32)), "neg.mha", "not positive");
  expect_io_error(read(mha("ndims.mha", "NDims = 9\nDimSize = 1\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n")), "ndims.mha", "NDims");
  expect_io_error(read(mha("junk.mha", "this is not a header\n")), "junk.mha", "Key = Value");
  expect_io_error(read(mha("spacing.mha", base + "DimSize = 1 1 1\nElementSpacing = 1 0 1\nElementDataFile = LOCAL\n", 4)), "spacing.mha", "not positive");
  expect_io_error(read(mha("nan.mha", base + "DimSize = 1 1 1\nOffset = 0 nan 0\nElementDataFile = LOCAL\n", 4)), "nan.mha", "finite");
  expect_io_error(read(mha("hs.mha", base + "DimSize = 1 1 1\nHeaderSize = 1000\nElementDataFile = LOCAL\n", 4)), "hs.mha", "HeaderSize");
  expect_io_error(read(mha("hsm.mha", base + "DimSize = 1 1 1\nHeaderSize = -2\nElementDataFile = LOCAL\n", 4)), "hsm.mha", "HeaderSize");
  expect_io_error(read(mha("hs1.mha", base + "DimSize = 100 1 1\nHeaderSize = -1\nElementDataFile = LOCAL\n", 4)), "hs1.mha", "bytes");
  expect_io_error(read(mha("list.mha", base + "DimSize = 1 1 1\nElementDataFile = LIST\n")), "list.mha", "not supported");
  expect_io_error(read(mha("missingraw.mhd", base + "DimSize = 1 1 1\nElementDataFile = missing.raw\n")), "missing.raw", "cannot open");
  expect_io_error(read(mha("ascii.mha", base + "DimSize = 1 1 1\nBinaryData = False\nElementDataFile = LOCAL\n1.0\n")), "ascii.mha", "ASCII");
  expect_io_error(read(mha("obj.mha", "ObjectType = Mesh\n" + base + "DimSize = 1 1 1\nElementDataFile = LOCAL\n", 4)), "obj.mha", "Mesh");
  std::string binary = "NDims = 3\n";
  binary += std::string("\0\1\2", 3);
  expect_io_error(read(mha("binary.mha", binary)), "binary.mha", "binary data");
  // compressed: lying sizes, corrupt streams
  expect_io_error(read(mha("zlie.mha", base + "DimSize = 1000 1000 1000\nCompressedData = True\nElementDataFile = LOCAL\n", 64)), "zlie.mha", "compressed");
  expect_io_error(read(mha("zsize.mha", base + "DimSize = 2 2 2\nCompressedData = True\nCompressedDataSize = 5000\nElementDataFile = LOCAL\n", 64)), "zsize.mha", "CompressedDataSize");
  if (gio::metaimage_has_zlib) {
    expect_io_error(read(mha("zbad.mha", base + "DimSize = 2 2 2\nCompressedData = True\nElementDataFile = LOCAL\n", 64)), "zbad.mha", "corrupt");
    // a valid stream that holds fewer, or more, bytes than the header says
    gio::metaimage_write_options z;
    z.compress = true;
    gio::write_metaimage(scratch("zok.mha"), sample_volume<float>(), z);
    std::string text = io_test::read_all(scratch("zok.mha"));
    const auto at = text.find("DimSize = 5 4 3");
    REQUIRE(at != std::string::npos);
    std::string more = text, fewer = text;
    more.replace(at, 15, "DimSize = 5 4 4");
    fewer.replace(at, 15, "DimSize = 5 4 2");
    io_test::write_text(scratch("zmore.mha"), more);
    io_test::write_text(scratch("zfewer.mha"), fewer);
    expect_io_error(read(scratch("zmore.mha")), "zmore.mha", "compressed data hold");
    expect_io_error(read(scratch("zfewer.mha")), "zfewer.mha", "more bytes than");
    // truncated compressed stream
    io_test::write_text(scratch("ztrunc.mha"), text.substr(0, text.size() - 20));
    expect_io_error(read(scratch("ztrunc.mha")), "ztrunc.mha", "CompressedDataSize");
  } else {
    expect_io_error(read(mha("zno.mha", base + "DimSize = 2 2 2\nCompressedData = True\nElementDataFile = LOCAL\n", 64)), "zno.mha", "zlib");
  }
}

TEST_CASE("metaimage: every truncation of a valid file is rejected cleanly") {
  gio::write_metaimage(scratch("full.mha"), sample_volume<std::int16_t>());
  const std::string text = io_test::read_all(scratch("full.mha"));
  for (std::size_t cut = 0; cut < text.size(); cut += 7) {
    io_test::write_text(scratch("cut.mha"), text.substr(0, cut));
    CHECK_THROWS_AS(gio::read_metaimage<float>(scratch("cut.mha")), gio::io_error);
  }
}

TEST_CASE("metaimage: a data file that is a directory is an error, not a huge allocation (fuzzer find)") {
  // ElementDataFile = / once made read_file() size a directory as a file and ask for exabytes
  std::filesystem::create_directories(scratch("a-directory"));
  io_test::write_text(scratch("dirdata.mhd"),
                      "ObjectType = Image\nNDims = 2\nDimSize = 2 1\nElementType = MET_UCHAR\n"
                      "ElementDataFile = a-directory\n");
  io_test::expect_io_error([] { gio::read_metaimage<float>(scratch("dirdata.mhd")); }, "a-directory",
                           "not a regular file");
  io_test::expect_io_error([] { gio::read_metaimage<float>(scratch("no-such-file.mha")); }, "no-such-file.mha",
                           "does not exist");
}

// ---- orientation ---------------------------------------------------------------------------------

TEST_CASE("metaimage: TransformMatrix lists the direction of each index axis (ITK), read into a row-major D") {
  // index axis x points along world +y, index axis y along world -x
  const std::uint8_t bytes[6] = {0, 1, 2, 3, 4, 5};
  io_test::write_bytes(scratch("rot.mha"),
                       "ObjectType = Image\nNDims = 3\nTransformMatrix = 0 1 0 -1 0 0 0 0 1\nOffset = 10 20 30\n"
                       "ElementSpacing = 0.5 2 3\nDimSize = 3 2 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                       bytes, sizeof bytes);
  const auto v = gio::read_metaimage<float>(scratch("rot.mha"));
  CHECK(v.orientation == std::array<double, 9>{0, -1, 0, 1, 0, 0, 0, 0, 1});
  const auto g = v.geometry<3>();
  CHECK(g.world({2, 0, 0}) == geovoronoi::point<3>{10.0, 21.0, 30.0});
  CHECK(g.world({0, 1, 0}) == geovoronoi::point<3>{8.0, 20.0, 30.0});
  CHECK(g.nearest_voxel({8.0, 21.0, 30.0}) == geovoronoi::coord<3>{2, 1, 0});
  // read back through the image reader: the grid carries the direction
  CHECK(gio::read_metaimage_image<float>(scratch("rot.mha")).geometry() == g);
  // the 2D spelling, and Orientation / Rotation as synonyms
  io_test::write_bytes(scratch("rot2.mha"),
                       "NDims = 2\nOrientation = 0 1 -1 0\nDimSize = 3 2\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                       bytes, sizeof bytes);
  CHECK(gio::read_metaimage<float>(scratch("rot2.mha")).geometry<2>().direction() == geovoronoi::direction_matrix<2>{0, -1, 1, 0});
  io_test::write_bytes(scratch("rot3.mha"),
                       "NDims = 3\nRotation = 0 0 1 1 0 0 0 1 0\nDimSize = 3 2 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                       bytes, sizeof bytes);
  CHECK(gio::read_metaimage<float>(scratch("rot3.mha")).orientation == std::array<double, 9>{0, 1, 0, 0, 0, 1, 1, 0, 0});
}

TEST_CASE("metaimage: a rotated TransformMatrix survives read -> write -> read bit for bit") {
  const double c = std::cos(0.7), s = std::sin(0.7);
  const double cb = std::cos(-1.1), sb = std::sin(-1.1);
  // a rotation about z times one about x: awkward doubles in every entry but one
  const std::array<double, 9> d = {c, -s * cb, s * sb, s, c * cb, -c * sb, 0, sb, cb};
  auto v = sample_volume<float>();
  v.orientation = d;
  for (const char* name : {"orient.mhd", "orient.mha", "orient-z.mha"}) {
    gio::metaimage_write_options opt;
    opt.compress = std::string(name) == "orient-z.mha" && gio::metaimage_has_zlib;
    gio::write_metaimage(scratch(name), v, opt);
    const auto back = gio::read_metaimage<float>(scratch(name));
    CHECK(back.orientation == d);
    CHECK(back.data == v.data);
    gio::write_metaimage(scratch(std::string("again-") + name), back, opt);
    CHECK(gio::read_metaimage<float>(scratch(std::string("again-") + name)).orientation == d);
  }
  // an image written from a rotated grid reads back on the same grid
  const geovoronoi::grid<3> g({4, 3, 2}, {0.5, 1.5, 2.5}, {1.0, -2.0, 3.0}, d);
  geovoronoi::image<std::int16_t, 3> img(g, std::int16_t(7));
  gio::write_metaimage(scratch("orient-img.mha"), img);
  CHECK(gio::read_metaimage_image<std::int16_t>(scratch("orient-img.mha")).geometry() == g);
  // and in 2D
  const geovoronoi::grid<2> h({4, 3}, {0.5, 1.5}, {1.0, -2.0}, {c, -s, s, c});
  gio::write_metaimage(scratch("orient-2d.mhd"), geovoronoi::image<float, 2>(h, 1.0f));
  CHECK(gio::read_metaimage_image<float, 2>(scratch("orient-2d.mhd")).geometry() == h);
}

TEST_CASE("metaimage: singular or non-orthonormal TransformMatrix is rejected, on read and on write") {
  using io_test::expect_io_error;
  const std::uint8_t bytes[2] = {1, 2};
  auto with = [&](const std::string& name, const std::string& m) {
    io_test::write_bytes(scratch(name), "NDims = 2\nTransformMatrix = " + m +
                                            "\nDimSize = 2 1\nElementType = MET_UCHAR\nElementDataFile = LOCAL\n",
                         bytes, sizeof bytes);
    return [p = scratch(name)] { gio::read_metaimage<float>(p); };
  };
  expect_io_error(with("sing.mha", "1 0 0 0"), "sing.mha", "TransformMatrix: the direction matrix [1 0; 0 0] is singular");
  expect_io_error(with("scaled.mha", "2 0 0 2"), "scaled.mha", "not orthonormal");
  expect_io_error(with("skew.mha", "1 0 0.5 1"), "skew.mha", "not orthonormal");
  CHECK_NOTHROW(with("flip.mha", "-1 0 0 1")());
  auto v = sample_volume<float>();
  v.orientation = {1, 0, 0, 0, 1, 0, 0, 0, 0};
  CHECK_THROWS_WITH_AS(gio::write_metaimage(scratch("wsing.mha"), v),
                       doctest::Contains("singular"), std::invalid_argument);
  CHECK_FALSE(std::filesystem::exists(scratch("wsing.mha")));
  CHECK_THROWS_WITH_AS(v.geometry<3>(), doctest::Contains("direction matrix"), std::invalid_argument);
}

// ---- element conversions -------------------------------------------------------------------------

TEST_CASE("metaimage: values an integer type cannot hold are an error naming the value, never UB") {
  using io_test::expect_io_error;
  auto floats = [](const std::string& name, float x) {
    const float data[4] = {1.0f, 2.0f, 3.0f, x};
    io_test::write_bytes(scratch(name), "NDims = 1\nDimSize = 4\nElementType = MET_FLOAT\nElementDataFile = LOCAL\n",
                         data, sizeof data);
    return scratch(name);
  };
  const float inf = std::numeric_limits<float>::infinity();
  expect_io_error([p = floats("cnan.mha", std::nanf(""))] { gio::read_metaimage<int>(p); }, "cnan.mha", "element 3 is NaN");
  expect_io_error([p = floats("cinf.mha", inf)] { gio::read_metaimage<int>(p); }, "cinf.mha", "element 3 is +inf");
  expect_io_error([p = floats("cminf.mha", -inf)] { gio::read_metaimage<std::uint8_t>(p); }, "cminf.mha", "-inf");
  expect_io_error([p = floats("cbig.mha", 3e9f)] { gio::read_metaimage<std::int32_t>(p); }, "cbig.mha", "int32 cannot hold");
  expect_io_error([p = floats("c2p31.mha", 2147483648.0f)] { gio::read_metaimage<std::int32_t>(p); }, "c2p31.mha", "2147483648");
  expect_io_error([p = floats("cneg.mha", -1.0f)] { gio::read_metaimage<std::uint16_t>(p); }, "cneg.mha", "out of range");
  expect_io_error([p = floats("c300.mha", 300.0f)] { gio::read_metaimage<std::uint8_t>(p); }, "c300.mha", "300");
  CHECK(gio::read_metaimage<std::int32_t>(floats("cok.mha", 2147483520.0f)).data[3] == 2147483520);
  CHECK(gio::read_metaimage<std::uint8_t>(floats("cfrac.mha", -0.75f)).data[3] == 0);  // truncated toward 0
  CHECK(gio::read_metaimage<std::int64_t>(floats("c64.mha", -9.2e18f)).data[3] == std::int64_t(-9.2e18f));
  // integer to a narrower integer
  const std::int16_t shorts[2] = {5, -3};
  io_test::write_bytes(scratch("cshort.mha"), "NDims = 1\nDimSize = 2\nElementType = MET_SHORT\nElementDataFile = LOCAL\n",
                       shorts, sizeof shorts);
  expect_io_error([] { gio::read_metaimage<std::uint32_t>(scratch("cshort.mha")); }, "cshort.mha", "element 1 is -3");
  CHECK(gio::read_metaimage<std::int8_t>(scratch("cshort.mha")).data == std::vector<std::int8_t>{5, -3});
  // on write: NaN or 1e10 stored as MET_UCHAR / MET_INT
  auto v = sample_volume<float>();
  std::fill(v.data.begin(), v.data.end(), 1.5f);
  v.data[7] = std::nanf("");
  gio::metaimage_write_options as_uchar;
  as_uchar.type = gio::element_type::uint8;
  expect_io_error([&] { gio::write_metaimage(scratch("wnan.mha"), v, as_uchar); }, "wnan.mha", "element 7 is NaN");
  v.data[7] = 1e10f;
  as_uchar.type = gio::element_type::int32;
  expect_io_error([&] { gio::write_metaimage(scratch("wbig.mha"), v, as_uchar); }, "wbig.mha", "int32 cannot hold");
  // make_volume converting an image
  geovoronoi::image<double, 2> img(geovoronoi::grid<2>({2, 2}), 1.0);
  img[3] = -1.0;
  CHECK_THROWS_WITH_AS(gio::make_volume<std::uint8_t>(img), doctest::Contains("element 3 is -1"), std::invalid_argument);
}

TEST_CASE("volume::channel checks that data holds channels * voxels values") {
  gio::volume<float> v;
  v.extents = {4, 4, 4};
  v.channels = 2;
  v.data.assign(64 + 10, 1.0f);  // one channel and a bit
  CHECK_THROWS_WITH_AS(v.channel<3>(1), doctest::Contains("74 values"), std::invalid_argument);
  CHECK_THROWS_WITH_AS(v.channel<3>(0), doctest::Contains("need 128"), std::invalid_argument);
  v.data.assign(128, 2.0f);
  CHECK(v.channel<3>(1).size() == 64);
  v.data.assign(200, 2.0f);
  CHECK_THROWS_AS(v.channel<3>(0), std::invalid_argument);
}

// ---- memory ------------------------------------------------------------------------------------

TEST_CASE("metaimage: a corrupt compressed stream that declares a huge size fails before allocating it") {
  if (!gio::metaimage_has_zlib) return;
  // 256 KiB of garbage after a zlib header, declaring 256 MiB of floats (within deflate's ratio)
  std::string junk(std::size_t(256) << 10, '\0');
  std::uint32_t x = 12345;
  for (auto& ch : junk) {
    x = x * 1664525u + 1013904223u;
    ch = char(x >> 24);
  }
  junk[0] = char(0x78);
  junk[1] = char(0x9c);
  io_test::write_text(scratch("zhuge.mha"),
                      "NDims = 3\nDimSize = 256 256 1024\nElementType = MET_FLOAT\nCompressedData = True\n"
                      "CompressedDataSize = " + std::to_string(junk.size()) + "\nElementDataFile = LOCAL\n" + junk);
  alloc_probe::largest = 0;
  io_test::expect_io_error([] { gio::read_metaimage<float>(scratch("zhuge.mha")); }, "zhuge.mha", "compressed data");
  INFO("largest allocation: " << alloc_probe::largest.load());
  CHECK(alloc_probe::largest.load() < (std::size_t(16) << 20));
}

TEST_CASE("metaimage: a valid compressed stream grows its buffer to exactly the declared size") {
  if (!gio::metaimage_has_zlib) return;
  gio::volume<float> v;
  v.extents = {64, 64, 64};  // 1 MiB of floats that compress well, but not to almost nothing
  v.data.resize(std::size_t(v.voxels()));
  for (std::size_t i = 0; i < v.data.size(); ++i) v.data[i] = float((i * 7919) % 251) / 4.0f;
  gio::metaimage_write_options z;
  z.compress = true;
  gio::write_metaimage(scratch("zgrow.mha"), v, z);
  CHECK(io_test::read_all(scratch("zgrow.mha")).size() < 600000);
  CHECK(gio::read_metaimage<float>(scratch("zgrow.mha")).data == v.data);
  // the same stream cut short, without CompressedDataSize to catch it first
  std::string text = io_test::read_all(scratch("zgrow.mha"));
  const auto line = text.find("CompressedDataSize");
  REQUIRE(line != std::string::npos);
  text.erase(line, text.find('\n', line) + 1 - line);
  io_test::write_text(scratch("zcut.mha"), text.substr(0, text.size() - 200));
  io_test::expect_io_error([] { gio::read_metaimage<float>(scratch("zcut.mha")); }, "zcut.mha", "truncated");
}

TEST_CASE("metaimage: running out of memory names the size and the file") {
  gio::volume<std::uint8_t> v;
  v.extents = {64, 32, 16};  // 32 KiB on disk, 256 KiB as double
  v.data.assign(std::size_t(v.voxels()), std::uint8_t(3));
  gio::write_metaimage(scratch("oom.mha"), v);
  alloc_probe::fail_from = 100000;
  bool thrown = false;
  try {
    gio::read_metaimage<double>(scratch("oom.mha"));
  } catch (const gio::io_error& e) {
    thrown = true;
    const std::string what = e.what();
    INFO(what);
    CHECK(what.find("oom.mha") != std::string::npos);
    CHECK(what.find("out of memory") != std::string::npos);
    CHECK(what.find("262144 bytes") != std::string::npos);
  }
  alloc_probe::fail_from = 0;
  CHECK(thrown);
  // the error is io::out_of_memory (an io_error), so that a program tells it from a bad file
  alloc_probe::fail_from = 100000;
  CHECK_THROWS_AS(gio::read_metaimage<double>(scratch("oom.mha")), gio::out_of_memory);
  alloc_probe::fail_from = 0;
}

TEST_CASE("metaimage: headers with CR-only line endings (classic Mac) are read like LF and CRLF ones") {
  const std::uint8_t bytes[] = {1, 2, 3, 4, 5, 6};
  io_test::write_bytes(scratch("cr.raw"), "", bytes, sizeof bytes);
  const std::string lines[] = {"ObjectType = Image", "NDims = 2", "DimSize = 3 2", "ElementSpacing = 0.5 2",
                               "ElementType = MET_UCHAR", "ElementDataFile = cr.raw"};
  for (const char* eol : {"\n", "\r\n", "\r"}) {
    std::string h;
    for (const auto& l : lines) h += l + eol;
    io_test::write_text(scratch("cr.mhd"), h);
    INFO("line ending " << (eol[0] == '\r' ? (eol[1] ? "CRLF" : "CR") : "LF"));
    const auto v = gio::read_metaimage<int>(scratch("cr.mhd"));
    CHECK(v.data == std::vector<int>{1, 2, 3, 4, 5, 6});
    CHECK(v.extents == std::array<index_t, 3>{3, 2, 1});
    CHECK(v.spacing[1] == 2.0);
    // LOCAL data right after the ElementDataFile line's CR (its first byte may be a LF: data, not a line end)
    std::string local;
    for (std::size_t i = 0; i + 1 < std::size(lines); ++i) local += lines[i] + eol;
    local += std::string("ElementDataFile = LOCAL") + eol;
    const std::uint8_t data[] = {10, 13, 10, 7, 8, 9};
    io_test::write_bytes(scratch("cr.mha"), local, data, sizeof data);
    const auto w = gio::read_metaimage<int>(scratch("cr.mha"));
    CHECK(w.data == std::vector<int>{10, 13, 10, 7, 8, 9});
  }
}

TEST_CASE("io::read_log: every file a reader opens is recorded, the data file a header names included") {
  const std::uint8_t bytes[] = {1, 2};
  std::filesystem::create_directories(scratch("logged"));
  io_test::write_bytes(scratch("logged/field.raw"), "", bytes, sizeof bytes);
  io_test::write_text(scratch("logged.mhd"),
                      "NDims = 2\nDimSize = 2 1\nElementType = MET_UCHAR\nElementDataFile = logged/field.raw\n");
  gio::read_log outer;
  {
    gio::read_log log;
    (void)gio::read_metaimage<float>(scratch("logged.mhd"));
    CHECK(log.paths() == std::vector<std::string>{scratch("logged.mhd"), scratch("logged/field.raw")});
    CHECK_THROWS_AS(gio::read_metaimage<float>(scratch("no-such.mhd")), gio::io_error);  // tried: recorded too
    CHECK(log.paths().size() == 3);
    (void)gio::read_file(scratch("logged/field.raw"));
    CHECK(log.paths().back() == scratch("logged/field.raw"));
  }
  // every live log of the thread sees the reads made while it lives
  CHECK(outer.paths().size() == 4);
  (void)gio::read_metaimage_header(scratch("logged.mhd"));
  CHECK(outer.paths().size() == 5);
}

TEST_CASE("metaimage: a header value echoed in a message is cut to a readable length and escaped") {
  const std::string huge(100000, 'X');
  io_test::write_text(scratch("longtype.mha"), "NDims = 1\nDimSize = 2\nElementType = MET_" + huge +
                                                   "\nElementDataFile = LOCAL\n");
  std::string what;
  try {
    gio::read_metaimage<float>(scratch("longtype.mha"));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  INFO(what);
  CHECK(what.find("unknown ElementType") != std::string::npos);
  CHECK(what.find("100004 bytes") != std::string::npos);
  CHECK(what.size() < 400);
  io_test::write_text(scratch("c1.mha"), "NDims = 1\nDimSize = 2\nElementType = MET_\x9b" "31m\xff\nElementDataFile = LOCAL\n");
  what.clear();
  try {
    gio::read_metaimage<float>(scratch("c1.mha"));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  INFO(what);
  CHECK(what.find("MET_\\x9b31m\\xff") != std::string::npos);
}

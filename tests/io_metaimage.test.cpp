// MetaImage: round trips of every element type (.mhd and .mha, both byte orders, compressed),
// channels interleaved and planar, hand-written SOFA and ITK style headers, and bad files.
#include "io_test_util.hpp"

#include <geovoronoi/io/metaimage.hpp>

#include <cmath>
#include <cstdint>

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
  for (auto& x : v.data) x = std::abs(std::round(x));
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

// VTK XML ImageData writer: the XML says what ParaView needs, and the bytes of every array can be
// found again (appended raw and inline base64).
#include "support/io_util.hpp"

#include <geovoronoi/io/vti.hpp>

#include <cstdint>

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

namespace {

std::string attribute(const std::string& xml, const std::string& tag_start, const std::string& name) {
  const auto t = xml.find(tag_start);
  REQUIRE(t != std::string::npos);
  const auto open = xml.rfind('<', t);
  const auto a = xml.find(" " + name + "=\"", open) + 1;
  REQUIRE(a != std::string::npos);
  const auto b = xml.find('"', a + name.size() + 2);
  return xml.substr(a + name.size() + 2, b - a - name.size() - 2);
}

std::string unbase64(const std::string& s) {
  std::string out;
  unsigned buf = 0;
  int bits = 0;
  for (char c : s) {
    int v;
    if (c >= 'A' && c <= 'Z') v = c - 'A';
    else if (c >= 'a' && c <= 'z') v = c - 'a' + 26;
    else if (c >= '0' && c <= '9') v = c - '0' + 52;
    else if (c == '+') v = 62;
    else if (c == '/') v = 63;
    else continue;
    buf = (buf << 6) | unsigned(v);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out += char((buf >> bits) & 0xff);
    }
  }
  return out;
}

}  // namespace

TEST_CASE("vti: appended raw arrays with the grid's extent, origin and spacing") {
  const geovoronoi::grid<3> g({4, 3, 2}, {0.5, 1.0, 2.0}, {1.0, -2.0, 0.25});
  geovoronoi::image<float, 3> d(g);
  geovoronoi::image<std::int32_t, 3> l(g);
  for (index_t v = 0; v < g.size(); ++v) d[v] = float(v) * 0.5f, l[v] = std::int32_t(v % 5) - 1;
  std::vector<float> planar(std::size_t(g.size()) * 2);
  for (std::size_t i = 0; i < planar.size(); ++i) planar[i] = float(i);
  gio::vti_writer<3> w(g);
  w.add("distance", d).add("label", l).add_planar("w", planar, 2);
  w.write(scratch("a.vti"));
  const std::string x = io_test::read_all(scratch("a.vti"));
  CHECK(attribute(x, "<ImageData", "WholeExtent") == "0 3 0 2 0 1");
  CHECK(attribute(x, "<ImageData", "Origin") == "1 -2 0.25");
  CHECK(attribute(x, "<ImageData", "Spacing") == "0.5 1 2");
  CHECK(attribute(x, "Name=\"label\"", "type") == "Int32");
  CHECK(attribute(x, "Name=\"w\"", "NumberOfComponents") == "2");
  // the label array's block: 8-byte size, then the values
  const std::size_t offset = std::stoul(attribute(x, "Name=\"label\"", "offset"));
  const auto start = x.find("encoding=\"raw\">");
  REQUIRE(start != std::string::npos);
  const std::size_t base = x.find('_', start) + 1;
  std::uint64_t n;
  std::memcpy(&n, x.data() + base + offset, 8);
  CHECK(n == std::uint64_t(g.size()) * 4);
  std::vector<std::int32_t> back(std::size_t(g.size()));
  std::memcpy(back.data(), x.data() + base + offset + 8, back.size() * 4);
  CHECK(back == l.values());
  // the planar channels are interleaved in the file
  const std::size_t woff = std::stoul(attribute(x, "Name=\"w\"", "offset"));
  float second;
  std::memcpy(&second, x.data() + base + woff + 8 + 4, 4);
  CHECK(second == planar[std::size_t(g.size())]);  // voxel 0, component 1
  CHECK(x.rfind("</VTKFile>") != std::string::npos);
}

TEST_CASE("vti: inline base64 and 2D grids") {
  const geovoronoi::grid<2> g({3, 2});
  geovoronoi::image<double, 2> f(g);
  for (index_t v = 0; v < g.size(); ++v) f[v] = double(v) - 2.5;
  gio::vti_writer<2> w(g, gio::vti_encoding::inline_base64);
  w.add("f", f);
  w.write(scratch("b.vti"));
  const std::string x = io_test::read_all(scratch("b.vti"));
  CHECK(attribute(x, "<ImageData", "WholeExtent") == "0 2 0 1 0 0");
  CHECK(x.find("AppendedData") == std::string::npos);
  const auto a = x.find("format=\"binary\">");
  REQUIRE(a != std::string::npos);
  const auto b = x.find("</DataArray>", a);
  const std::string raw = unbase64(x.substr(a + 16, b - a - 16));
  REQUIRE(raw.size() == 8 + 6 * 8);
  std::vector<double> back(6);
  std::memcpy(back.data(), raw.data() + 8, 48);
  CHECK(back == f.values());
}

TEST_CASE("vti: arrays of the wrong size or grid are rejected") {
  const geovoronoi::grid<3> g({2, 2, 2});
  gio::vti_writer<3> w(g);
  std::vector<float> v(7);
  CHECK_THROWS_AS(w.add("bad", v.data(), v.size()), std::invalid_argument);
  CHECK_THROWS_AS(w.add("other", geovoronoi::image<float, 3>(geovoronoi::grid<3>({3, 2, 2}))), std::invalid_argument);
  CHECK_THROWS_AS(w.write(scratch("no/such/dir/x.vti")), gio::io_error);
}

TEST_CASE("vti: K-component weights and node indices (shape functions) read back voxel by voxel") {
  const geovoronoi::grid<3> g({5, 4, 3}, {1.0, 1.0, 3.0});
  const int k = 3;
  const std::size_t n = std::size_t(g.size());
  std::vector<float> weights(n * k);
  std::vector<std::int32_t> nodes(n * k);
  for (std::size_t v = 0; v < n; ++v)
    for (int s = 0; s < k; ++s) {
      weights[v * k + std::size_t(s)] = float(v) + 0.25f * float(s);
      nodes[v * k + std::size_t(s)] = s == 2 && v % 2 ? -1 : std::int32_t(v % 7 + std::size_t(s));
    }
  for (auto enc : {gio::vti_encoding::appended_raw, gio::vti_encoding::inline_base64}) {
    gio::vti_writer<3> w(g, enc);
    w.add("weights", weights.data(), weights.size(), k).add("nodes", nodes.data(), nodes.size(), k);
    w.write(scratch("k.vti"));
    const std::string x = io_test::read_all(scratch("k.vti"));
    CHECK(attribute(x, "Name=\"weights\"", "NumberOfComponents") == "3");
    CHECK(attribute(x, "Name=\"nodes\"", "NumberOfComponents") == "3");
    CHECK(attribute(x, "Name=\"nodes\"", "type") == "Int32");
    std::string wb, nb;  // the two blocks: 8-byte size, then the values
    if (enc == gio::vti_encoding::appended_raw) {
      const std::size_t base = x.find('_', x.find("encoding=\"raw\">")) + 1;
      const std::size_t wo = std::stoul(attribute(x, "Name=\"weights\"", "offset"));
      const std::size_t no = std::stoul(attribute(x, "Name=\"nodes\"", "offset"));
      wb = x.substr(base + wo, 8 + n * k * 4), nb = x.substr(base + no, 8 + n * k * 4);
    } else {
      auto block = [&](const std::string& name) {
        const auto a = x.find(">", x.find("Name=\"" + name + "\"")) + 1;
        return unbase64(x.substr(a, x.find("</DataArray>", a) - a));
      };
      wb = block("weights"), nb = block("nodes");
    }
    REQUIRE(wb.size() == 8 + n * k * 4);
    REQUIRE(nb.size() == 8 + n * k * 4);
    std::vector<float> wback(n * k);
    std::vector<std::int32_t> nback(n * k);
    std::memcpy(wback.data(), wb.data() + 8, n * k * 4);
    std::memcpy(nback.data(), nb.data() + 8, n * k * 4);
    CHECK(wback == weights);
    CHECK(nback == nodes);
  }
}

TEST_CASE("vti: Direction is the grid's direction matrix, row by row (VTK's order)") {
  const geovoronoi::grid<3> g({3, 2, 2}, {1.0, 2.0, 3.0}, {5.0, 6.0, 7.0}, {0, -1, 0, 1, 0, 0, 0, 0, 1});
  gio::vti_writer<3> w(g);
  w.add("f", geovoronoi::image<float, 3>(g, 1.0f));
  w.write(scratch("dir.vti"));
  CHECK(attribute(io_test::read_all(scratch("dir.vti")), "<ImageData", "Direction") == "0 -1 0 1 0 0 0 0 1");
  // 2D: the 2 x 2 block, z the identity
  const geovoronoi::grid<2> h({3, 2}, {1.0, 1.0}, {0.0, 0.0}, {0, 1, -1, 0});
  gio::vti_writer<2> w2(h);
  w2.add("f", geovoronoi::image<float, 2>(h, 1.0f));
  w2.write(scratch("dir2.vti"));
  CHECK(attribute(io_test::read_all(scratch("dir2.vti")), "<ImageData", "Direction") == "0 1 0 -1 0 0 0 0 1");
  // the identity stays as before
  gio::vti_writer<2> w3(geovoronoi::grid<2>({3, 2}));
  w3.add("f", geovoronoi::image<float, 2>(geovoronoi::grid<2>({3, 2}), 1.0f));
  w3.write(scratch("dir3.vti"));
  CHECK(attribute(io_test::read_all(scratch("dir3.vti")), "<ImageData", "Direction") == "1 0 0 0 1 0 0 0 1");
}

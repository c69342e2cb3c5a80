// io/stl.hpp, io/obj.hpp, io/mesh.hpp: ASCII and binary STL, OBJ, and their errors.
#include <geovoronoi/io/mesh.hpp>

#include "support/io_util.hpp"

#include <cmath>
#include <cstring>
#include <limits>

namespace gv = geovoronoi;
namespace gio = geovoronoi::io;

namespace {

std::vector<unsigned char> bytes_of(const std::string& s) { return std::vector<unsigned char>(s.begin(), s.end()); }

/// A binary STL: 80-byte header, count, then 50 bytes per triangle (little-endian floats).
std::vector<unsigned char> binary_stl(const std::string& header, const std::vector<std::array<float, 9>>& tris,
                                      std::uint32_t count_override = 0xFFFFFFFFu) {
  std::vector<unsigned char> b(80, ' ');
  std::memcpy(b.data(), header.data(), std::min<std::size_t>(80, header.size()));
  const std::uint32_t n = count_override == 0xFFFFFFFFu ? std::uint32_t(tris.size()) : count_override;
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<unsigned char>(n >> (8 * i)));
  for (const auto& t : tris) {
    float rec[12] = {0, 0, 1};
    for (int k = 0; k < 9; ++k) rec[3 + k] = t[std::size_t(k)];
    const auto* p = reinterpret_cast<const unsigned char*>(rec);
    b.insert(b.end(), p, p + 48);  // the test machines are little-endian
    b.push_back(0);
    b.push_back(0);
  }
  return b;
}

const char* ascii_stl = R"(solid cube_corner
  facet normal 0 0 -1
    outer loop
      vertex 0 0 0
      vertex 1 0 0
      vertex 0 1.5e0 0
    endloop
  endfacet
  facet normal 0 0 0
    outer loop
      vertex 0 0 1
      vertex -2 0 1
      vertex 0 -3 1
    endloop
  endfacet
endsolid cube_corner
)";

}  // namespace

TEST_CASE("STL: ASCII") {
  const auto m = gio::parse_stl("a.stl", bytes_of(ascii_stl));
  REQUIRE(m.triangles.size() == 2);
  CHECK(m.vertices.size() == 6);
  CHECK(m.vertices[m.triangles[0][2]] == std::array<double, 3>{0, 1.5, 0});
  CHECK(m.vertices[m.triangles[1][2]] == std::array<double, 3>{0, -3, 1});
  CHECK(m.degenerate == 0);

  SUBCASE("errors name the file and the line") {
    std::string s = ascii_stl;
    s.replace(s.find("1.5e0"), 5, "nan");
    io_test::expect_io_error([&] { gio::parse_stl("n.stl", bytes_of(s)); }, "n.stl", "line 6");
    s = ascii_stl;
    s.replace(s.find("-2 0 1"), 6, "-2 inf 1");
    io_test::expect_io_error([&] { gio::parse_stl("i.stl", bytes_of(s)); }, "i.stl", "not a finite number");
    s = ascii_stl;
    s = s.substr(0, s.find("endloop"));
    io_test::expect_io_error([&] { gio::parse_stl("t.stl", bytes_of(s)); }, "t.stl", "end of the file");
    io_test::expect_io_error([&] { gio::parse_stl("e.stl", bytes_of("solid empty\nendsolid empty\n")); }, "e.stl",
                             "no facets");
    io_test::expect_io_error([&] { gio::parse_stl("z.stl", {}); }, "z.stl", "empty");
    s = ascii_stl;
    s.replace(s.find("      vertex 0 0 1\n"), 19, "");
    io_test::expect_io_error([&] { gio::parse_stl("two.stl", bytes_of(s)); }, "two.stl", "2 vertices");
  }
  SUBCASE("degenerate facets are dropped and counted, polygons fanned") {
    std::string s = ascii_stl;
    s.replace(s.find("vertex 0 1.5e0 0"), 16, "vertex 2 0 0");  // collinear: zero area
    const auto d = gio::parse_stl("d.stl", bytes_of(s));
    CHECK(d.triangles.size() == 1);
    CHECK(d.degenerate == 1);
    s = ascii_stl;
    s.replace(s.find("vertex 0 1.5e0 0"), 16, "vertex 1 1 0\n vertex 0 1 0");  // a quad
    CHECK(gio::parse_stl("q.stl", bytes_of(s)).triangles.size() == 3);
  }
  SUBCASE("two solids in one file") {
    const std::string two = std::string(ascii_stl) + ascii_stl;
    CHECK(gio::parse_stl("2.stl", bytes_of(two)).triangles.size() == 4);
  }
}

TEST_CASE("STL: binary, and telling it from ASCII") {
  const std::vector<std::array<float, 9>> tris{{0, 0, 0, 1, 0, 0, 0, 1, 0}, {0, 0, 2, 1, 0, 2, 0, 0.25f, 2}};
  const auto m = gio::parse_stl("b.stl", binary_stl("binary", tris));
  REQUIRE(m.triangles.size() == 2);
  CHECK(m.vertices[m.triangles[1][2]] == std::array<double, 3>{0, 0.25, 2});

  SUBCASE("a binary file whose header starts with \"solid\" is still binary") {
    const auto s = gio::parse_stl("s.stl", binary_stl("solid exported by some CAD tool", tris));
    CHECK(s.triangles.size() == 2);
  }
  SUBCASE("truncated or padded files name the triangle count and the sizes") {
    auto b = binary_stl("binary", tris);
    b.resize(b.size() - 7);
    io_test::expect_io_error([&] { gio::parse_stl("t.stl", b); }, "t.stl", "truncated");
    io_test::expect_io_error([&] { gio::parse_stl("t.stl", b); }, "t.stl", "2 triangles (184 bytes)");
    b = binary_stl("solid but binary", tris);
    b.resize(b.size() - 1);
    io_test::expect_io_error([&] { gio::parse_stl("s.stl", b); }, "s.stl", "truncated");
    b = binary_stl("binary", tris);
    b.push_back(0);
    io_test::expect_io_error([&] { gio::parse_stl("p.stl", b); }, "p.stl", "trailing bytes");
    io_test::expect_io_error([&] { gio::parse_stl("h.stl", binary_stl("binary", tris, 1000000)); }, "h.stl",
                             "1000000 triangles");
    io_test::expect_io_error([&] { gio::parse_stl("x.stl", bytes_of("garbage")); }, "x.stl", "too few");
    io_test::expect_io_error([&] { gio::parse_stl("0.stl", binary_stl("binary", {})); }, "0.stl", "no triangles");
  }
  SUBCASE("NaN and infinite coordinates name the triangle and the byte") {
    auto t2 = tris;
    t2[1][4] = std::numeric_limits<float>::quiet_NaN();
    io_test::expect_io_error([&] { gio::parse_stl("n.stl", binary_stl("binary", t2)); }, "n.stl",
                             "triangle 1 (byte " + std::to_string(84 + 50 + 12 + 16) + ")");
    t2 = tris;
    t2[0][0] = std::numeric_limits<float>::infinity();
    io_test::expect_io_error([&] { gio::parse_stl("i.stl", binary_stl("binary", t2)); }, "i.stl", "infinite");
  }
  SUBCASE("zero-area triangles are dropped and counted") {
    auto t2 = tris;
    t2.push_back({1, 1, 1, 1, 1, 1, 2, 2, 2});
    const auto d = gio::parse_stl("d.stl", binary_stl("binary", t2));
    CHECK(d.triangles.size() == 2);
    CHECK(d.degenerate == 1);
  }
}

TEST_CASE("STL: an ASCII file with a NUL byte that is not binary either fails as ASCII, naming the line") {
  // read as binary, the text would be a truncated file of hundreds of millions of triangles
  std::string s = ascii_stl;
  s.replace(s.find("vertex 1 0 0"), 12, std::string("vertex 1 0\0 0", 13));
  std::string what;
  try {
    gio::parse_stl("nul.stl", bytes_of(s));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  INFO(what);
  CHECK(what.find("nul.stl: ASCII STL line 5") != std::string::npos);
  CHECK(what.find("NUL") != std::string::npos);
  CHECK(what.find("not binary STL either") != std::string::npos);
  CHECK(what.find("million") == std::string::npos);
  CHECK(what.find("truncated") == std::string::npos);
  // a binary file whose header starts with "solid" and whose size matches its count stays binary
  const std::vector<std::array<float, 9>> tris{{0, 0, 0, 1, 0, 0, 0, 1, 0}};
  auto b = binary_stl("solid x", tris);
  CHECK(gio::parse_stl("b.stl", b).triangles.size() == 1);
}

TEST_CASE("STL, OBJ: a huge token is echoed cut to a readable length") {
  const std::string token(1 << 20, '9');
  std::string s = ascii_stl;
  s.replace(s.find("1.5e0"), 5, token + "x");
  std::string what;
  try {
    gio::parse_stl("long.stl", bytes_of(s));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  INFO(what.substr(0, 300));
  CHECK(what.find("line 6") != std::string::npos);
  CHECK(what.find("(1048577 bytes)") != std::string::npos);
  CHECK(what.size() < 300);
  what.clear();
  try {
    gio::parse_obj("long.obj", bytes_of("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 " + token + "\n"));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  INFO(what.substr(0, 300));
  CHECK(what.find("line 4") != std::string::npos);
  CHECK(what.find("(1048576 bytes)") != std::string::npos);
  CHECK(what.size() < 300);
  // bytes that are not UTF-8 are escaped
  what.clear();
  try {
    gio::parse_obj("c1.obj", bytes_of("v 0 \x9b" "31m 0\n"));
  } catch (const gio::io_error& e) {
    what = e.what();
  }
  CHECK(what.find("\\x9b31m") != std::string::npos);
}

TEST_CASE("OBJ: vertices, faces of every corner form, negative indices, fans") {
  const std::string obj =
      "# a comment\n"
      "mtllib x.mtl\n"
      "o thing\n"
      "v 0 0 0\n"
      "v 1 0 0 1.0\n"
      "v 1 1 0\n"
      "v 0 1 0\r\n"
      "vt 0 0\n"
      "vn 0 0 1\n"
      "g group\n"
      "usemtl m\n"
      "s off\n"
      "f 1 2 3   # trailing comment\n"
      "f 1/1 3/1 4/1\n"
      "f 1/1/1 2/1/1 3/1/1\n"
      "f 1//1 3//1 4//1\n"
      "f -4 -3 -2 -1\n"
      "l 1 2\n";
  const auto m = gio::parse_obj("m.obj", bytes_of(obj));
  CHECK(m.vertices.size() == 4);
  REQUIRE(m.triangles.size() == 6);
  CHECK(m.triangles[0] == std::array<std::uint32_t, 3>{0, 1, 2});
  CHECK(m.triangles[1] == std::array<std::uint32_t, 3>{0, 2, 3});
  CHECK(m.triangles[4] == std::array<std::uint32_t, 3>{0, 1, 2});  // the quad, fanned from its first corner
  CHECK(m.triangles[5] == std::array<std::uint32_t, 3>{0, 2, 3});

  SUBCASE("errors name the file and the line") {
    const std::string head = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    io_test::expect_io_error([&] { gio::parse_obj("r.obj", bytes_of(head + "f 1 2 4\n")); }, "r.obj", "line 4");
    io_test::expect_io_error([&] { gio::parse_obj("r.obj", bytes_of(head + "f 1 2 4\n")); }, "r.obj",
                             "3 vertices are defined so far");
    io_test::expect_io_error([&] { gio::parse_obj("n.obj", bytes_of(head + "f -1 -2 -4\n")); }, "n.obj", "vertex -4");
    io_test::expect_io_error([&] { gio::parse_obj("0.obj", bytes_of(head + "f 0 1 2\n")); }, "0.obj", "index 0");
    io_test::expect_io_error([&] { gio::parse_obj("2.obj", bytes_of(head + "f 1 2\n")); }, "2.obj", "at least three");
    io_test::expect_io_error([&] { gio::parse_obj("x.obj", bytes_of(head + "f 1 2 x\n")); }, "x.obj", "not an integer");
    io_test::expect_io_error([&] { gio::parse_obj("s.obj", bytes_of(head + "f 1 2 /3\n")); }, "s.obj", "no vertex index");
    io_test::expect_io_error([&] { gio::parse_obj("nan.obj", bytes_of("v 0 nan 0\n")); }, "nan.obj", "line 1");
    io_test::expect_io_error([&] { gio::parse_obj("inf.obj", bytes_of("v 0 0 0\nv 1e999 0 0\n")); }, "inf.obj", "line 2");
    io_test::expect_io_error([&] { gio::parse_obj("v.obj", bytes_of("v 0 0\n")); }, "v.obj", "three coordinates");
    io_test::expect_io_error([&] { gio::parse_obj("f.obj", bytes_of(head)); }, "f.obj", "no faces");
    io_test::expect_io_error([&] { gio::parse_obj("e.obj", {}); }, "e.obj", "empty");
    io_test::expect_io_error([&] { gio::parse_obj("b.obj", bytes_of(head + "f 1 2 99999999999999999999\n")); }, "b.obj",
                             "not an integer");
  }
  SUBCASE("degenerate faces are dropped and counted") {
    const auto d = gio::parse_obj("d.obj", bytes_of("v 0 0 0\nv 1 0 0\nv 2 0 0\nv 0 1 0\nf 1 2 3\nf 1 1 4\nf 1 2 4\n"));
    CHECK(d.triangles.size() == 1);
    CHECK(d.degenerate == 2);
  }
}

TEST_CASE("read_mesh: by extension, from files") {
  const std::string stl = io_test::scratch("mesh.STL"), obj = io_test::scratch("mesh.obj"),
                    other = io_test::scratch("mesh.ply");
  io_test::write_text(stl, ascii_stl);
  io_test::write_text(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
  io_test::write_text(other, "ply\n");
  CHECK(gio::read_mesh(stl).triangles.size() == 2);
  CHECK(gio::read_mesh(obj).triangles.size() == 1);
  io_test::expect_io_error([&] { gio::read_mesh(other); }, other, "unknown mesh format");
  io_test::expect_io_error([&] { gio::read_mesh(io_test::scratch("missing.obj")); }, "missing.obj", "does not exist");
}

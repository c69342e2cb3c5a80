#pragma once
/// @file io/obj.hpp
/// @brief Wavefront OBJ reader (geometry only) into a triangle_mesh; OBJ writer.
///
/// Reads `v x y z [w]` (w ignored) and `f` records; every other record (vt, vn, g, o, s, l, p,
/// usemtl, mtllib, ...) and `#` comments are skipped. A face vertex may be written `v`, `v/vt`,
/// `v/vt/vn` or `v//vn`; only v is used. Positive indices count from 1; negative ones count back
/// from the last vertex defined so far (-1 is the latest), and an index must refer to a vertex
/// already defined. Faces with more than three vertices are fanned from their first vertex.
/// Coordinates must be finite. Zero-area triangles are dropped and counted in
/// triangle_mesh::degenerate. A file without any face is an error.

#include <geovoronoi/io/common.hpp>
#include <geovoronoi/io/stl.hpp>
#include <geovoronoi/mesh.hpp>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace geovoronoi::io {

namespace detail {

/// Splits one line into whitespace-separated tokens.
inline std::vector<std::string> split_words(const unsigned char* p, std::size_t n) {
  std::vector<std::string> out;
  std::size_t i = 0;
  while (i < n) {
    while (i < n && (p[i] == ' ' || p[i] == '\t' || p[i] == '\r' || p[i] == '\f' || p[i] == '\v')) ++i;
    std::size_t b = i;
    while (i < n && !(p[i] == ' ' || p[i] == '\t' || p[i] == '\r' || p[i] == '\f' || p[i] == '\v')) ++i;
    if (i > b) out.emplace_back(reinterpret_cast<const char*>(p + b), i - b);
  }
  return out;
}

/// The vertex index of face corner @p t ("7", "7/2", "7/2/3", "7//3", "-1"), resolved against the
/// @p count vertices defined so far (0-based). Throws through @p fail.
template <class Fail>
std::uint32_t obj_corner(const std::string& t, std::size_t count, Fail&& fail) {
  const std::string v = t.substr(0, t.find('/'));
  if (v.empty()) fail("face corner " + quote_token(t) + " has no vertex index");
  char* end = nullptr;
  errno = 0;
  const long long i = std::strtoll(v.c_str(), &end, 10);
  if (end != v.c_str() + v.size() || errno == ERANGE) fail("face corner " + quote_token(t) + " is not an integer index");
  if (i == 0) fail("face corner " + quote_token(t) + ": index 0 is invalid (OBJ counts vertices from 1)");
  const long long n = static_cast<long long>(count);
  const long long r = i > 0 ? i - 1 : n + i;
  if (r < 0 || r >= n)
    fail("face corner " + quote_token(t) + " refers to vertex " + std::to_string(i) + ", but " + std::to_string(count) +
         " vertices are defined so far");
  return static_cast<std::uint32_t>(r);
}

}  // namespace detail

/**
 * @brief Parses OBJ bytes (see this file's notes).
 * @param path the name used in error messages.
 * @throws io_error naming @p path and the line: an empty file, a non-finite or missing coordinate,
 *         an index that is 0, malformed or out of range, a face with fewer than three corners, no
 *         face at all.
 */
inline triangle_mesh parse_obj(const std::string& path, const std::vector<unsigned char>& bytes) {
  if (bytes.empty()) throw io_error(path, "is empty (0 bytes); an OBJ file needs vertices and faces");
  triangle_mesh m;
  std::size_t line = 0, faces = 0, i = 0;
  while (i < bytes.size()) {
    ++line;
    std::size_t e = i;
    while (e < bytes.size() && bytes[e] != '\n') ++e;
    const std::size_t b = i;
    i = e + 1;
    std::size_t len = e - b;
    for (std::size_t k = 0; k < len; ++k)
      if (bytes[b + k] == '#') len = k;  // a comment runs to the end of the line
    if (len == 0) continue;
    const auto w = detail::split_words(bytes.data() + b, len);
    if (w.empty()) continue;
    auto fail = [&](const std::string& what) { throw io_error(path, "OBJ " + detail::at_line(line) + what); };
    if (w[0] == "v") {
      if (w.size() < 4) fail("a vertex needs three coordinates (\"v x y z\")");
      std::array<double, 3> p;
      for (std::size_t a = 0; a < 3; ++a)
        if (!detail::parse_finite(w[a + 1], p[a])) fail("vertex coordinate " + detail::quote_token(w[a + 1]) + " is not a finite number");
      if (m.vertices.size() >= 0xFFFFFFFFu) fail("too many vertices (more than 2^32 - 1)");
      m.vertices.push_back(p);
    } else if (w[0] == "f") {
      if (w.size() < 4) fail("a face needs at least three corners, this one has " + std::to_string(w.size() - 1));
      const std::size_t n = m.vertices.size();
      const std::uint32_t first = detail::obj_corner(w[1], n, fail);
      std::uint32_t prev = detail::obj_corner(w[2], n, fail);
      for (std::size_t k = 3; k < w.size(); ++k) {
        const std::uint32_t cur = detail::obj_corner(w[k], n, fail);
        detail::add_triangle(m, first, prev, cur);
        prev = cur;
      }
      ++faces;
    }
  }
  if (faces == 0) throw io_error(path, "OBJ holds no faces (\"f\" records)");
  return m;
}

/// Reads an OBJ file (see parse_obj()).
inline triangle_mesh read_obj(const std::string& path) { return parse_obj(path, read_file(path)); }

/**
 * @brief Writes @p mesh as OBJ text: one `v x y z` record per vertex (17 significant digits, so it
 *        reads back exactly) and one `f a b c` record (1-based) per triangle.
 * @throws io_error naming @p path when a triangle refers to a missing vertex or the file cannot be
 *         written.
 */
inline void write_obj(const std::string& path, const triangle_mesh& mesh) {
  detail::check_vertex_indices(path, mesh);
  std::string text = "# written by geovoronoi\n";
  char buf[128];
  for (const auto& v : mesh.vertices) {
    std::snprintf(buf, sizeof buf, "v %.17g %.17g %.17g\n", v[0], v[1], v[2]);
    text += buf;
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    std::snprintf(buf, sizeof buf, "f %lu %lu %lu\n", static_cast<unsigned long>(tri[0]) + 1,
                  static_cast<unsigned long>(tri[1]) + 1, static_cast<unsigned long>(tri[2]) + 1);
    text += buf;
  }
  detail::write_file(path, text.data(), text.size());
}

}  // namespace geovoronoi::io

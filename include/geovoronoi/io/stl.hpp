#pragma once
/// @file io/stl.hpp
/// @brief STL reader, ASCII and binary, into a triangle_mesh; binary STL writer.
///
/// Binary or ASCII is decided by content, not by the first word: a file of at least 84 bytes whose
/// size is exactly 84 + 50 * (the triangle count at byte 80) is binary, even when its header starts
/// with "solid" (many exporters write that); otherwise a file that starts with "solid" is ASCII, except
/// that one holding a NUL byte which the ASCII reading refuses is read as binary when its triangle
/// count is plausible (84 + 50 x count within a factor of 2 of the size: a truncated or padded binary
/// file), else the ASCII error names the line and the NUL byte and says it is not binary STL either;
/// anything else is read as binary and its size must match its count.
/// Coordinates must be finite. Zero-area triangles are dropped and counted in
/// triangle_mesh::degenerate. A file without any facet is an error. Normals and attribute bytes are
/// ignored. ASCII facets with more than three vertices are fanned into triangles.

#include <geovoronoi/io/common.hpp>
#include <geovoronoi/mesh.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace geovoronoi::io {

namespace detail {

/// Whitespace tokenizer over a byte buffer that knows its line number.
class text_tokens {
 public:
  text_tokens(const unsigned char* p, std::size_t n) : p_(p), n_(n) {}

  /// The next token (empty at the end); sets line() to its line.
  std::string next() {
    while (i_ < n_ && is_space(p_[i_])) {
      if (p_[i_] == '\n') ++line_;
      ++i_;
    }
    std::size_t b = i_;
    while (i_ < n_ && !is_space(p_[i_])) ++i_;
    return std::string(reinterpret_cast<const char*>(p_ + b), i_ - b);
  }
  /// Skips the rest of the current line.
  void skip_line() {
    while (i_ < n_ && p_[i_] != '\n') ++i_;
  }
  std::size_t line() const noexcept { return line_; }

 private:
  static bool is_space(unsigned char c) noexcept { return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v'; }
  const unsigned char* p_;
  std::size_t n_;
  std::size_t i_ = 0;
  std::size_t line_ = 1;
};

/// Parses a whole token as a finite double, or returns false.
inline bool parse_finite(const std::string& t, double& out) {
  if (t.empty()) return false;
  char* end = nullptr;
  out = std::strtod(t.c_str(), &end);
  return end == t.c_str() + t.size() && std::isfinite(out);
}

/// A token as a message quotes it: in double quotes, cut and escaped (geovoronoi::printable), and a
/// NUL byte in it named.
inline std::string quote_token(const std::string& t) {
  return "\"" + geovoronoi::printable(t) + "\"" +
         (t.find('\0') != std::string::npos ? " (it holds a NUL byte: binary data in a text file?)" : "");
}

/// "line N: " prefix for messages.
inline std::string at_line(std::size_t line) { return "line " + std::to_string(line) + ": "; }

/// Adds triangle (a, b, c) of vertex indices, or counts it when its area is zero.
inline void add_triangle(triangle_mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
  if (geovoronoi::detail::zero_area(m.vertices[a], m.vertices[b], m.vertices[c])) ++m.degenerate;
  else m.triangles.push_back({a, b, c});
}

/// The little-endian 32-bit word at byte @p at (0 past the end; callers check sizes first).
// GCC 12 reports out-of-bounds reads here on paths that the size checks rule out, once a small
// constant buffer is inlined into a caller: the pragma silences that false positive only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Warray-bounds"
#endif
inline std::uint32_t le32(const std::vector<unsigned char>& bytes, std::size_t at) noexcept {
  std::uint32_t w = 0;
  if (bytes.size() < 4 || at > bytes.size() - 4) return 0;
  for (std::size_t k = 0; k < 4; ++k) w |= std::uint32_t(bytes[at + k]) << (8 * k);
  return w;
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

/// Whether the size is exactly that of a binary STL of the triangle count at byte 80.
inline bool stl_binary_size(const std::vector<unsigned char>& bytes) {
  return bytes.size() >= 84 && 84 + 50 * std::uint64_t(le32(bytes, 80)) == bytes.size();
}

/// Whether the text starts with "solid" (after white space).
inline bool stl_starts_solid(const std::vector<unsigned char>& bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && bytes[i] != 0 && std::strchr(" \t\r\n\f\v", bytes[i]) != nullptr) ++i;
  return bytes.size() - i >= 5 && std::memcmp(bytes.data() + i, "solid", 5) == 0;
}

/// Throws io_error naming @p path and the first triangle of @p mesh that refers to a missing vertex
/// (the mesh writers' check).
inline void check_vertex_indices(const std::string& path, const triangle_mesh& mesh) {
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int k = 0; k < 3; ++k)
      if (tri[k] >= mesh.vertices.size())
        throw io_error(path, "triangle " + std::to_string(t) + " refers to vertex " + std::to_string(tri[k]) + " of " +
                                 std::to_string(mesh.vertices.size()));
  }
}

inline triangle_mesh parse_stl_binary(const std::string& path, const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 84)
    throw io_error(path, "is not an STL file: " + std::to_string(bytes.size()) +
                             " bytes are too few for a binary STL (84-byte header) and it is not ASCII STL (starting with \"solid\")");
  const std::uint32_t count = le32(bytes, 80);
  const std::uint64_t want = 84 + 50 * std::uint64_t(count);
  if (want != bytes.size())
    throw io_error(path, "binary STL " + std::string(want > bytes.size() ? "is truncated" : "has trailing bytes") +
                             ": its header announces " + std::to_string(count) + " triangles (" +
                             std::to_string(want) + " bytes) but the file holds " + std::to_string(bytes.size()) +
                             " bytes");
  if (count == 0) throw io_error(path, "binary STL holds no triangles");
  triangle_mesh m;
  m.vertices.reserve(std::size_t(count) * 3);
  m.triangles.reserve(count);
  for (std::uint32_t t = 0; t < count; ++t) {
    const std::size_t base = 84 + 50 * std::size_t(t) + 12;  // skip the normal
    for (int v = 0; v < 3; ++v) {
      std::array<double, 3> p;
      for (int a = 0; a < 3; ++a) {
        const std::size_t at = base + 12 * std::size_t(v) + 4 * std::size_t(a);
        const std::uint32_t w = le32(bytes, at);
        float f;
        std::memcpy(&f, &w, 4);
        if (!std::isfinite(f))
          throw io_error(path, "binary STL triangle " + std::to_string(t) + " (byte " + std::to_string(at) +
                                   "): coordinate is " + (f != f ? "NaN" : "infinite"));
        p[std::size_t(a)] = f;
      }
      m.vertices.push_back(p);
    }
    add_triangle(m, 3 * t, 3 * t + 1, 3 * t + 2);
  }
  return m;
}

inline triangle_mesh parse_stl_ascii(const std::string& path, const std::vector<unsigned char>& bytes) {
  triangle_mesh m;
  text_tokens in(bytes.data(), bytes.size());
  auto fail = [&](const std::string& what) { throw io_error(path, "ASCII STL " + at_line(in.line()) + what); };
  auto expect = [&](const char* word) {
    const std::string t = in.next();
    if (t != word) fail("expected \"" + std::string(word) + "\", found " + (t.empty() ? "the end of the file" : quote_token(t)));
  };
  std::string t = in.next();
  if (t != "solid") fail("expected \"solid\"");
  in.skip_line();  // the solid's name
  std::size_t facets = 0;
  for (;;) {
    t = in.next();
    if (t == "endsolid") {
      in.skip_line();
      t = in.next();
      if (t.empty()) break;
      if (t != "solid") fail("expected \"solid\" or the end of the file after \"endsolid\", found " + quote_token(t));
      in.skip_line();
      continue;
    }
    if (t.empty()) fail("the file ends without \"endsolid\"");
    if (t != "facet") fail("expected \"facet\" or \"endsolid\", found " + quote_token(t));
    expect("normal");
    for (int a = 0; a < 3; ++a) {  // the normal is not used, but it must be a number
      const std::string n = in.next();
      char* end = nullptr;
      (void)std::strtod(n.c_str(), &end);
      if (n.empty() || end != n.c_str() + n.size()) fail("the facet normal has a component that is not a number: " + quote_token(n));
    }
    expect("outer");
    expect("loop");
    const std::size_t first = m.vertices.size();
    for (;;) {
      t = in.next();
      if (t == "endloop") break;
      if (t != "vertex") fail("expected \"vertex\" or \"endloop\", found " + (t.empty() ? std::string("the end of the file") : quote_token(t)));
      std::array<double, 3> p;
      for (int a = 0; a < 3; ++a) {
        const std::string c = in.next();
        if (!parse_finite(c, p[std::size_t(a)])) fail("vertex coordinate " + quote_token(c) + " is not a finite number");
      }
      if (m.vertices.size() >= 0xFFFFFFFFu) fail("too many vertices (more than 2^32 - 1)");
      m.vertices.push_back(p);
    }
    const std::size_t n = m.vertices.size() - first;
    if (n < 3) fail("a facet has " + std::to_string(n) + " vertices; it needs at least 3");
    for (std::size_t k = 1; k + 1 < n; ++k)
      add_triangle(m, std::uint32_t(first), std::uint32_t(first + k), std::uint32_t(first + k + 1));
    expect("endfacet");
    ++facets;
  }
  if (facets == 0) throw io_error(path, "ASCII STL holds no facets");
  return m;
}

}  // namespace detail

/**
 * @brief Parses STL bytes (ASCII or binary, detected as described in this file's notes).
 * @param path the name used in error messages.
 * @throws io_error naming @p path and the line (ASCII) or byte (binary) of the problem: empty or
 *         truncated file, a size that does not match the triangle count, a NaN or infinite
 *         coordinate, a malformed record, no facet at all.
 */
inline triangle_mesh parse_stl(const std::string& path, const std::vector<unsigned char>& bytes) {
  if (bytes.empty()) throw io_error(path, "is empty (0 bytes); an STL file needs at least one facet");
  if (detail::stl_binary_size(bytes) || !detail::stl_starts_solid(bytes)) return detail::parse_stl_binary(path, bytes);
  if (std::memchr(bytes.data(), 0, bytes.size()) == nullptr) return detail::parse_stl_ascii(path, bytes);
  // "solid" and a NUL byte: a binary file whose header starts with "solid" (truncated or padded, as
  // its size does not match its count) or a text file with a stray NUL. Where the ASCII reading fails,
  // the binary reading names the problem when its count is plausible (a size within a factor of 2 of
  // the file's), else the ASCII reading's failure does
  try {
    return detail::parse_stl_ascii(path, bytes);
  } catch (const io_error& e) {
    const std::uint32_t count = detail::le32(bytes, 80);
    const std::uint64_t want = 84 + 50 * std::uint64_t(count);
    if (bytes.size() >= 84 && count != 0 && want <= 2 * std::uint64_t(bytes.size()) && bytes.size() <= 2 * want)
      return detail::parse_stl_binary(path, bytes);
    throw io_error(path, e.problem() + "; and it is not binary STL either (" + std::to_string(bytes.size()) +
                             " bytes, not 84 + 50 x the triangle count at byte 80)");
  }
}

/// Reads an STL file (see parse_stl()).
inline triangle_mesh read_stl(const std::string& path) { return parse_stl(path, read_file(path)); }

/**
 * @brief Writes @p mesh as binary STL: an 80-byte header, the triangle count, then per triangle its
 *        unit normal (from the vertex order), three vertices as little-endian float32 and two zero
 *        attribute bytes. Coordinates are rounded to float.
 * @throws io_error naming @p path when a triangle refers to a missing vertex, there are more than
 *         2^32 - 1 triangles, or the file cannot be written.
 */
inline void write_stl(const std::string& path, const triangle_mesh& mesh) {
  if (mesh.triangles.size() > 0xFFFFFFFFu) throw io_error(path, "binary STL holds at most 2^32 - 1 triangles");
  detail::check_vertex_indices(path, mesh);
  std::vector<unsigned char> out(84 + 50 * mesh.triangles.size(), 0);
  const char head[] = "binary STL written by geovoronoi";
  std::memcpy(out.data(), head, sizeof head - 1);
  auto put32 = [&](std::size_t at, std::uint32_t x) {
    for (int b = 0; b < 4; ++b) out[at + std::size_t(b)] = static_cast<unsigned char>(x >> (8 * b));
  };
  auto putf = [&](std::size_t at, double x) {
    const float f = static_cast<float>(x);
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    put32(at, u);
  };
  put32(80, static_cast<std::uint32_t>(mesh.triangles.size()));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    const auto &a = mesh.vertices[tri[0]], &b = mesh.vertices[tri[1]], &c = mesh.vertices[tri[2]];
    double n[3] = {(b[1] - a[1]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[1] - a[1]),
                   (b[2] - a[2]) * (c[0] - a[0]) - (b[0] - a[0]) * (c[2] - a[2]),
                   (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    const std::size_t at = 84 + 50 * t;
    for (int k = 0; k < 3; ++k) putf(at + 4 * std::size_t(k), len > 0 ? n[k] / len : 0.0);
    for (int v = 0; v < 3; ++v)
      for (int k = 0; k < 3; ++k) putf(at + 12 + 12 * std::size_t(v) + 4 * std::size_t(k), mesh.vertices[tri[v]][k]);
  }
  detail::write_file(path, out.data(), out.size());
}

}  // namespace geovoronoi::io

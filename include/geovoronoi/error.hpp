#pragma once
/// @file error.hpp
/// @brief The exceptions the library throws.
///
/// Invalid arguments (bad extents, seeds, field sizes, options) throw std::invalid_argument with a
/// message that names the problem. A user metric that returns a negative or NaN weight throws
/// geovoronoi::metric_error when a backend can detect it; distances that overflow the distance type
/// throw geovoronoi::overflow_error; a progress callback that asks to stop makes the call throw
/// geovoronoi::cancelled. Backends with their own failure modes
/// (CUDA) derive their exceptions from geovoronoi::error.
///
/// A message that echoes a piece of its input (a token of a file, a header value, a name) passes it
/// through geovoronoi::printable(), so that no message carries control bytes, bytes that are not
/// UTF-8, or megabytes of one token.

#include <cstddef>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <string_view>

namespace geovoronoi {

/// Base of the library's own runtime errors (not of std::invalid_argument, which it also throws).
class error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A metric produced an edge weight that is negative or NaN, which breaks every shortest-path solver.
class metric_error : public error {
 public:
  using error::error;
};

/// A path sum (or an edge weight) overflowed the distance type: a voxel that a finite path reaches
/// would come out unreachable. The message names the voxel and the value; computing in double or
/// rescaling the field or the spacing avoids it (docs/errors.md, "Overflow").
class overflow_error : public error {
 public:
  using error::error;
};

/// A long computation was cancelled by its progress callback.
class cancelled : public error {
 public:
  cancelled() : error("geovoronoi: cancelled by the progress callback") {}
};

/// How many bytes of an input a message echoes at most (printable()'s default limit).
inline constexpr std::size_t echo_limit = 64;

/**
 * @brief A piece of input as a message may echo it: valid UTF-8 text passes through; control bytes
 *        (below 0x20, 0x7f), C1 controls (U+0080 to U+009F), the line separators U+2028 and U+2029,
 *        and every byte that is not part of a well-formed UTF-8 character are written \xNN.
 * @param s     the input
 * @param limit the most bytes of @p s echoed: a longer piece is cut at a character boundary at or
 *              before @p limit bytes and followed by "... (N bytes)", N its whole length
 *              (std::string::npos: no limit)
 */
inline std::string printable(std::string_view s, std::size_t limit = echo_limit) {
  const auto byte = [&](std::size_t i) { return static_cast<unsigned char>(s[i]); };
  const auto cont = [&](std::size_t i, unsigned lo = 0x80, unsigned hi = 0xbf) {
    return i < s.size() && byte(i) >= lo && byte(i) <= hi;
  };
  // length of the well-formed character at i (0: not one), and whether it is printed as is
  const auto character = [&](std::size_t i, bool& shown) -> std::size_t {
    const unsigned b = byte(i);
    shown = true;
    if (b < 0x80) {
      shown = b >= 0x20 && b != 0x7f;
      return 1;
    }
    if (b >= 0xc2 && b <= 0xdf) {
      if (!cont(i + 1)) return 0;
      shown = !(b == 0xc2 && byte(i + 1) < 0xa0);  // C1 controls: U+0080 to U+009F
      return 2;
    }
    if (b >= 0xe0 && b <= 0xef) {
      const unsigned lo = b == 0xe0 ? 0xa0 : 0x80, hi = b == 0xed ? 0x9f : 0xbf;
      if (!cont(i + 1, lo, hi) || !cont(i + 2)) return 0;
      shown = !(b == 0xe2 && byte(i + 1) == 0x80 && (byte(i + 2) == 0xa8 || byte(i + 2) == 0xa9));
      return 3;
    }
    if (b >= 0xf0 && b <= 0xf4) {
      const unsigned lo = b == 0xf0 ? 0x90 : 0x80, hi = b == 0xf4 ? 0x8f : 0xbf;
      return cont(i + 1, lo, hi) && cont(i + 2) && cont(i + 3) ? 4 : 0;
    }
    return 0;
  };
  std::string out;
  std::size_t i = 0;
  while (i < s.size()) {
    bool shown = false;
    const std::size_t n = character(i, shown);
    const std::size_t step = n ? n : 1;
    if (limit != std::string::npos && i + step > limit && s.size() > limit) break;
    if (n && shown) {
      out.append(s.data() + i, n);
    } else {
      for (std::size_t j = i; j < i + step; ++j) {
        char buf[8];
        std::snprintf(buf, sizeof buf, "\\x%02x", unsigned(byte(j)));
        out += buf;
      }
    }
    i += step;
  }
  if (i < s.size()) out += "... (" + std::to_string(s.size()) + " bytes)";
  return out;
}

}  // namespace geovoronoi

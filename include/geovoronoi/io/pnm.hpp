#pragma once
/// @file io/pnm.hpp
/// @brief PGM / PPM import (P2, P3, P5, P6; maxval up to 65535) as a 2D image, or extruded to n
///        slices of a 3D volume (SOFA's steak and plate scenes are 2D drawings extruded this way).
///
/// Row 0 of the picture (its top) becomes y = 0; column 0 becomes x = 0. For PPM, one channel is
/// selected (red by default, the channel SOFA's steak scene uses) or the mean of the three.
///
/// @code
/// geovoronoi::io::pnm_options o;
/// o.extrude = 15;                         // 15 identical slices along z
/// auto field = geovoronoi::io::read_pnm<float>("steak.ppm", o);
/// @endcode

#include <geovoronoi/io/common.hpp>

namespace geovoronoi::io {

/// Options of read_pnm().
struct pnm_options {
  /// PPM channel to keep: 0 red, 1 green, 2 blue, -1 the mean of the three. Ignored for PGM.
  int channel = 0;
  /// Number of slices along z (>= 1); every slice is a copy of the picture.
  index_t extrude = 1;
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
  std::array<double, 3> origin{0.0, 0.0, 0.0};
};

/**
 * @brief Parses the bytes of a PGM or PPM picture (named @p path in messages) as a single-channel volume of width x height x extrude voxels.
 * @throws io_error naming the file and the problem (bad magic, header, maxval, truncated pixels).
 */
template <class T>
volume<T> parse_pnm(const std::string& path, const std::vector<unsigned char>& bytes, const pnm_options& opt = {}) {
  if (opt.extrude < 1 || opt.extrude > 1000000)
    throw io_error(path, "extrusion to " + std::to_string(opt.extrude) + " slices is out of range (1 to 10^6)");
  if (opt.channel < -1 || opt.channel > 2) throw io_error(path, "PPM channel must be -1, 0, 1 or 2");
  if (bytes.size() < 2 || bytes[0] != 'P' || (bytes[1] != '2' && bytes[1] != '3' && bytes[1] != '5' && bytes[1] != '6'))
    throw io_error(path, "not a PGM/PPM file (magic P2, P3, P5 or P6 expected)");
  const char kind = char(bytes[1]);
  const bool ascii = kind == '2' || kind == '3';
  const int colours = (kind == '3' || kind == '6') ? 3 : 1;
  std::size_t pos = 2;
  auto skip_space = [&] {
    while (pos < bytes.size()) {
      const unsigned char c = bytes[pos];
      if (c == '#') {
        while (pos < bytes.size() && bytes[pos] != '\n') ++pos;
      } else if (c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f') {
        ++pos;
      } else {
        break;
      }
    }
  };
  auto number = [&](const char* what) -> std::uint64_t {
    skip_space();
    if (pos >= bytes.size() || bytes[pos] < '0' || bytes[pos] > '9')
      throw io_error(path, std::string("missing or bad ") + what);
    std::uint64_t n = 0;
    while (pos < bytes.size() && bytes[pos] >= '0' && bytes[pos] <= '9') {
      n = n * 10 + std::uint64_t(bytes[pos] - '0');
      if (n > (std::uint64_t(1) << 40)) throw io_error(path, std::string(what) + " is absurdly large");
      ++pos;
    }
    return n;
  };
  const std::uint64_t width = number("width"), height = number("height"), maxval = number("maxval");
  if (width == 0 || height == 0) throw io_error(path, "the picture is empty (width or height 0)");
  if (maxval == 0 || maxval > 65535) throw io_error(path, "maxval " + std::to_string(maxval) + " is out of range (1 to 65535)");
  std::uint64_t pixels = 0, samples = 0, voxels = 0;
  if (!detail::checked_mul(width, height, pixels, detail::max_voxels) ||
      !detail::checked_mul(pixels, std::uint64_t(colours), samples, detail::max_voxels) ||
      !detail::checked_mul(pixels, std::uint64_t(opt.extrude), voxels, detail::max_voxels))
    throw io_error(path, "the picture size is absurd");
  const std::size_t bps = maxval > 255 ? 2 : 1;
  if (ascii) {
    if (samples * 2 > bytes.size() - pos + 1)  // every sample needs a digit and a separator
      throw io_error(path, "the header announces " + std::to_string(samples) + " samples, more than the file can hold");
  } else {
    if (pos >= bytes.size()) throw io_error(path, "truncated: no pixel data");
    ++pos;  // exactly one whitespace byte after maxval
    if (samples * bps > bytes.size() - pos)
      throw io_error(path, "truncated: " + std::to_string(samples * bps) + " bytes of pixels expected, " +
                               std::to_string(bytes.size() - pos) + " present");
  }
  std::vector<double> value(static_cast<std::size_t>(pixels));
  for (std::size_t p = 0; p < pixels; ++p) {
    double c[3] = {0, 0, 0};
    for (int k = 0; k < colours; ++k) {
      std::uint64_t s;
      if (ascii) {
        s = number("pixel value");
      } else if (bps == 1) {
        s = bytes[pos++];
      } else {
        s = (std::uint64_t(bytes[pos]) << 8) | bytes[pos + 1];
        pos += 2;
      }
      if (s > maxval) throw io_error(path, "pixel value " + std::to_string(s) + " exceeds maxval " + std::to_string(maxval));
      c[k] = double(s);
    }
    value[p] = colours == 1 ? c[0] : opt.channel < 0 ? (c[0] + c[1] + c[2]) / 3.0 : c[opt.channel];
  }
  volume<T> v;
  v.dims = opt.extrude > 1 ? 3 : 2;
  v.extents = {index_t(width), index_t(height), opt.extrude};
  v.spacing = opt.spacing;
  v.origin = opt.origin;
  v.stored = bps == 1 ? element_type::uint8 : element_type::uint16;
  for (std::size_t p = 0; p < pixels; ++p)
    if (!detail::representable<T>(value[p]))
      throw io_error(path, "cannot be read as " + std::string(detail::type_name<T>()) + ": " +
                               detail::unrepresentable<T>(value[p], p));
  detail::resize_or_throw(v.data, std::size_t(voxels), path, "the extruded volume");
  for (std::size_t z = 0; z < std::size_t(opt.extrude); ++z)
    for (std::size_t p = 0; p < pixels; ++p) v.data[z * pixels + p] = static_cast<T>(value[p]);
  return v;
}

/// Reads a PGM or PPM file (see parse_pnm()).
template <class T>
volume<T> read_pnm(const std::string& path, const pnm_options& opt = {}) {
  return parse_pnm<T>(path, read_file(path), opt);
}

/// Writes a single-channel 8-bit picture as binary PGM (P5), rows from y = 0; values are clamped to
/// 0..255 (NaN is written as 0).
template <class T>
void write_pgm(const std::string& path, const T* values, index_t width, index_t height) {
  const std::string hdr = "P5\n" + std::to_string(width) + " " + std::to_string(height) + "\n255\n";
  std::vector<unsigned char> out(hdr.begin(), hdr.end());
  for (index_t i = 0; i < width * height; ++i) {
    const double x = double(values[i]);
    out.push_back(static_cast<unsigned char>(!(x > 0) ? 0 : x >= 255 ? 255 : x + 0.5));
  }
  detail::write_file(path, out.data(), out.size());
}

}  // namespace geovoronoi::io

#pragma once
/// @file io/rgb_image.hpp
/// @brief An 8-bit RGB canvas (`rgb_image`) and the two operations pictures are assembled with
///        (`crop`, `hstack`). Writing one to disk is io/png.hpp's job; drawing volumes on one is
///        io/picture.hpp's.

#include <geovoronoi/io/common.hpp>

#include <algorithm>
#include <vector>

namespace geovoronoi::io {

/// 8-bit RGB colour.
struct rgb {
  unsigned char r = 0, g = 0, b = 0;
  friend bool operator==(rgb x, rgb y) { return x.r == y.r && x.g == y.g && x.b == y.b; }
  friend bool operator!=(rgb x, rgb y) { return !(x == y); }
};

/// An 8-bit RGB picture, rows top to bottom.
struct rgb_image {
  index_t width = 0, height = 0;
  std::vector<unsigned char> pixels;  ///< 3 bytes per pixel, row-major

  rgb_image() = default;
  rgb_image(index_t w, index_t h, rgb fill = {}) : width(w), height(h), pixels(std::size_t(w * h * 3)) {
    for (index_t i = 0; i < w * h; ++i) set_index(i, fill);
  }
  void set_index(index_t i, rgb c) {
    pixels[std::size_t(3 * i)] = c.r, pixels[std::size_t(3 * i + 1)] = c.g, pixels[std::size_t(3 * i + 2)] = c.b;
  }
  /// Sets pixel (x, y); a pixel outside the picture is ignored (drawing may run over the edge).
  void set(index_t x, index_t y, rgb c) {
    if (x >= 0 && y >= 0 && x < width && y < height) set_index(x + width * y, c);
  }
  /// @pre 0 <= x < width, 0 <= y < height
  rgb get(index_t x, index_t y) const {
    const std::size_t i = std::size_t(3 * (x + width * y));
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
  }
  /// Fills the rectangle [x0, x0+w) x [y0, y0+h), clipped to the picture.
  void fill(index_t x0, index_t y0, index_t w, index_t h, rgb c) {
    for (index_t y = std::max<index_t>(y0, 0); y < std::min(y0 + h, height); ++y)
      for (index_t x = std::max<index_t>(x0, 0); x < std::min(x0 + w, width); ++x) set_index(x + width * y, c);
  }
  /// Copies @p src with its top-left corner at (x0, y0), clipped to this picture.
  void paste(const rgb_image& src, index_t x0, index_t y0) {
    for (index_t y = 0; y < src.height; ++y)
      for (index_t x = 0; x < src.width; ++x) set(x0 + x, y0 + y, src.get(x, y));
  }
};

/// The part [x0, x0+w) x [y0, y0+h) of a picture (clipped to it).
inline rgb_image crop(const rgb_image& pic, index_t x0, index_t y0, index_t w, index_t h) {
  x0 = std::clamp<index_t>(x0, 0, pic.width), y0 = std::clamp<index_t>(y0, 0, pic.height);
  w = std::clamp<index_t>(w, 0, pic.width - x0), h = std::clamp<index_t>(h, 0, pic.height - y0);
  rgb_image out(w, h);
  for (index_t y = 0; y < h; ++y)
    for (index_t x = 0; x < w; ++x) out.set(x, y, pic.get(x0 + x, y0 + y));
  return out;
}

/// Two pictures side by side, top-aligned; where their heights differ the rest is @p background.
inline rgb_image hstack(const rgb_image& a, const rgb_image& b, rgb background = {40, 40, 40}) {
  rgb_image out(a.width + b.width, std::max(a.height, b.height), background);
  out.paste(a, 0, 0);
  out.paste(b, a.width, 0);
  return out;
}

}  // namespace geovoronoi::io

#pragma once
/// @file io/png.hpp
/// @brief Pictures: an RGB canvas, a PNG writer (libpng) and montages of three orthogonal mid-slices
///        of a volume — labels (distinct colours, cell borders, stiff material hatched, seeds
///        marked), a distance heat map with iso-lines, and one node's shape-function weight.
///
/// Needs libpng at link time (CMake: PNG::PNG) when write_png() is used; without <png.h> (or with
/// GEOVORONOI_NO_PNG defined) write_png() throws io_error and the rendering helpers still work.
///
/// Montage layout (3D): the XY slice at z = nz/2 on the left, the XZ slice at y = ny/2 in the middle,
/// the YZ slice at x = nx/2 on the right; in every panel the first axis runs right and the second
/// down (row 0 is y = 0 or z = 0). A 2D grid gives one panel. Each voxel becomes a square of
/// `scale` pixels (automatic: about 400 pixels for the largest panel side).
///
/// @code
/// auto pic = geovoronoi::io::label_montage(d.label, d.seeds, &stiffness);
/// geovoronoi::io::write_png("labels.png", pic);
/// @endcode

#include <geovoronoi/io/common.hpp>

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdio>

#if __has_include(<png.h>) && !defined(GEOVORONOI_NO_PNG)
#include <png.h>
#define GEOVORONOI_IO_HAVE_PNG 1
#else
#define GEOVORONOI_IO_HAVE_PNG 0
#endif

namespace geovoronoi::io {

/// 8-bit RGB colour.
struct rgb {
  unsigned char r = 0, g = 0, b = 0;
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
  void set(index_t x, index_t y, rgb c) {
    if (x >= 0 && y >= 0 && x < width && y < height) set_index(x + width * y, c);
  }
  rgb get(index_t x, index_t y) const {
    const std::size_t i = std::size_t(3 * (x + width * y));
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
  }
};

/// Writes an RGB picture as PNG. @throws io_error naming the file on failure or without libpng.
inline void write_png(const std::string& path, const rgb_image& pic) {
#if GEOVORONOI_IO_HAVE_PNG
  if (pic.width <= 0 || pic.height <= 0 || pic.pixels.size() != std::size_t(pic.width * pic.height * 3))
    throw io_error(path, "refusing to write an empty or inconsistent picture");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw io_error(path, "cannot open the file for writing");
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<png_bytep> rows(std::size_t(pic.height));
  for (index_t y = 0; y < pic.height; ++y)
    rows[std::size_t(y)] = const_cast<png_bytep>(pic.pixels.data() + std::size_t(3 * pic.width * y));
  bool ok = png && info;
  if (ok && setjmp(png_jmpbuf(png)) == 0) {
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(pic.width), png_uint_32(pic.height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
  } else {
    ok = false;
  }
  png_destroy_write_struct(&png, &info);
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed) throw io_error(path, "libpng failed to write the picture");
#else
  (void)pic;
  throw io_error(path, "PNG output needs libpng (not available in this build)");
#endif
}

namespace detail {

inline rgb hsv(double h, double s, double v) {
  h = std::fmod(h, 1.0) * 6.0;
  const int i = int(h);
  const double f = h - i, p = v * (1 - s), q = v * (1 - s * f), t = v * (1 - s * (1 - f));
  double r, g, b;
  switch (i % 6) {
    case 0: r = v, g = t, b = p; break;
    case 1: r = q, g = v, b = p; break;
    case 2: r = p, g = v, b = t; break;
    case 3: r = p, g = q, b = v; break;
    case 4: r = t, g = p, b = v; break;
    default: r = v, g = p, b = q; break;
  }
  return {static_cast<unsigned char>(r * 255 + 0.5), static_cast<unsigned char>(g * 255 + 0.5),
          static_cast<unsigned char>(b * 255 + 0.5)};
}

inline rgb mix(rgb a, rgb b, double t) {
  auto m = [t](unsigned char x, unsigned char y) { return static_cast<unsigned char>(x + (y - x) * t + 0.5); };
  return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b)};
}

/// A dark-to-bright heat colour map (black-purple-red-orange-yellow-white) on [0, 1].
inline rgb heat(double t) {
  static const rgb stops[] = {{10, 7, 40}, {90, 20, 120}, {190, 40, 90}, {245, 110, 30}, {250, 200, 50}, {255, 255, 220}};
  if (!(t > 0)) return stops[0];
  if (t >= 1) return stops[5];
  const double s = t * 5;
  const int i = int(s);
  return mix(stops[i], stops[i + 1], s - i);
}

/// One panel: a 2D slice of a volume described by the two axes it spans and the fixed coordinate.
struct panel {
  int u, v;        ///< axes along the panel's width and height
  int fixed_axis;  ///< -1 for a 2D grid
  index_t fixed;
  index_t w, h, x0 = 0;  ///< size in voxels, left offset in pixels
};

template <int Dim>
std::vector<panel> panels_of(const grid<Dim>& g) {
  if constexpr (Dim == 2) {
    return {panel{0, 1, -1, 0, g.extent(0), g.extent(1)}};
  } else {
    return {panel{0, 1, 2, g.extent(2) / 2, g.extent(0), g.extent(1)},
            panel{0, 2, 1, g.extent(1) / 2, g.extent(0), g.extent(2)},
            panel{1, 2, 0, g.extent(0) / 2, g.extent(1), g.extent(2)}};
  }
}

/// Lays the panels out left to right, returns the canvas and the voxel-to-pixel scale.
template <int Dim>
rgb_image montage_canvas(const grid<Dim>& g, std::vector<panel>& ps, int& scale) {
  index_t big = 1;
  for (const auto& p : ps) big = std::max({big, p.w, p.h});
  if (scale <= 0) scale = int(std::clamp<index_t>(400 / big, 1, 12));
  const index_t gap = 6;
  index_t width = gap, height = 0;
  for (auto& p : ps) {
    p.x0 = width;
    width += p.w * scale + gap;
    height = std::max(height, p.h * scale);
  }
  (void)g;
  return rgb_image(width, height + 2 * gap, rgb{40, 40, 40});
}

/// Voxel index of pixel (px, py) of panel p (scale pixels per voxel), or -1 outside the panel.
template <int Dim>
index_t voxel_at(const grid<Dim>& g, const panel& p, index_t px, index_t py, int scale) {
  const index_t a = (px - p.x0) / scale, b = (py - 6) / scale;
  if (px < p.x0 || py < 6 || a >= p.w || b >= p.h) return -1;
  coord<Dim> c{};
  c[p.u] = a;
  c[p.v] = b;
  if constexpr (Dim == 3) c[p.fixed_axis] = p.fixed;
  return g.index(c);
}

/// Paints each panel pixel with colour(voxel, px, py); returns the canvas.
template <int Dim, class Colour>
rgb_image paint(const grid<Dim>& g, std::vector<panel>& ps, int& scale, Colour colour) {
  rgb_image pic = montage_canvas(g, ps, scale);
  for (const auto& p : ps)
    for (index_t py = 6; py < 6 + p.h * scale; ++py)
      for (index_t px = p.x0; px < p.x0 + p.w * scale; ++px) pic.set(px, py, colour(voxel_at(g, p, px, py, scale), px, py));
  return pic;
}

/// Draws a line pixel where the class of a pixel differs from its right or lower neighbour's.
template <int Dim, class Class>
void draw_borders(rgb_image& pic, const grid<Dim>& g, const std::vector<panel>& ps, int scale, Class cls, rgb colour) {
  for (const auto& p : ps)
    for (index_t py = 6; py < 6 + p.h * scale; ++py)
      for (index_t px = p.x0; px < p.x0 + p.w * scale; ++px) {
        const index_t v = voxel_at(g, p, px, py, scale);
        const auto c = cls(v);
        const index_t r = px + 1 < p.x0 + p.w * scale ? voxel_at(g, p, px + 1, py, scale) : v;
        const index_t d = py + 1 < 6 + p.h * scale ? voxel_at(g, p, px, py + 1, scale) : v;
        if ((r != v && cls(r) != c) || (d != v && cls(d) != c)) pic.set(px, py, colour);
      }
}

/// Marks seeds: a filled square where the seed lies on (or next to) the slice, a hollow one otherwise.
template <int Dim>
void draw_seeds(rgb_image& pic, const grid<Dim>& g, const std::vector<panel>& ps, int scale,
                const std::vector<index_t>& seeds, rgb fill) {
  const index_t r = std::max<index_t>(3, scale + 1);
  for (const auto& p : ps)
    for (index_t s : seeds) {
      if (s < 0 || s >= g.size()) continue;
      const auto c = g.coords(s);
      bool on = true;
      if constexpr (Dim == 3) on = std::abs(c[p.fixed_axis] - p.fixed) <= 1;
      const index_t cx = p.x0 + c[p.u] * scale + scale / 2, cy = 6 + c[p.v] * scale + scale / 2;
      for (index_t dy = -r - 1; dy <= r + 1; ++dy)
        for (index_t dx = -r - 1; dx <= r + 1; ++dx) {
          const bool edge = std::max(std::abs(dx), std::abs(dy)) >= r;
          const bool outline = std::max(std::abs(dx), std::abs(dy)) == r + 1;
          if (outline) pic.set(cx + dx, cy + dy, rgb{0, 0, 0});
          else if (on || edge) pic.set(cx + dx, cy + dy, fill);
        }
    }
}

}  // namespace detail

/// The part [x0, x0+w) x [y0, y0+h) of a picture (clipped to it).
inline rgb_image crop(const rgb_image& pic, index_t x0, index_t y0, index_t w, index_t h) {
  x0 = std::clamp<index_t>(x0, 0, pic.width), y0 = std::clamp<index_t>(y0, 0, pic.height);
  w = std::clamp<index_t>(w, 0, pic.width - x0), h = std::clamp<index_t>(h, 0, pic.height - y0);
  rgb_image out(w, h);
  for (index_t y = 0; y < h; ++y)
    for (index_t x = 0; x < w; ++x) out.set(x, y, pic.get(x0 + x, y0 + y));
  return out;
}

/// Two pictures side by side (top-aligned, dark background where heights differ).
inline rgb_image hstack(const rgb_image& a, const rgb_image& b) {
  rgb_image out(a.width + b.width, std::max(a.height, b.height), rgb{40, 40, 40});
  for (index_t y = 0; y < a.height; ++y)
    for (index_t x = 0; x < a.width; ++x) out.set(x, y, a.get(x, y));
  for (index_t y = 0; y < b.height; ++y)
    for (index_t x = 0; x < b.width; ++x) out.set(a.width + x, y, b.get(x, y));
  return out;
}

/// Width in pixels of a montage's first (XY) panel including the margins, for crop().
template <int Dim>
index_t first_panel_width(const grid<Dim>& g, const rgb_image& montage) {
  auto ps = detail::panels_of(g);
  int scale = 0;
  const auto canvas = detail::montage_canvas(g, ps, scale);
  // the automatic scale is a function of the grid alone, so it matches the montage's
  return canvas.width == montage.width ? ps[0].x0 + ps[0].w * scale + 6 : montage.width;
}

/// A distinct colour for label l (golden-angle hues, alternating brightness); dark grey for -1.
inline rgb label_colour(label_t l) {
  if (l < 0) return {25, 25, 25};
  const double h = std::fmod(0.13 + 0.618033988749895 * l, 1.0);
  return detail::hsv(h, l % 2 ? 0.55 : 0.75, l % 3 == 1 ? 0.80 : 0.95);
}

/**
 * @brief Label montage: each cell in its colour with black borders, seeds as white squares, and,
 *        when a stiffness image is given, the stiffest material (values at least `stiff_ratio` times
 *        the median inside value) hatched in grey so one sees the cells bend around it.
 */
template <int Dim, class S = float>
rgb_image label_montage(const image<label_t, Dim>& label, const std::vector<index_t>& seeds,
                        const image<S, Dim>* stiffness = nullptr, double stiff_ratio = 100.0, int scale = 0) {
  const auto& g = label.geometry();
  auto ps = detail::panels_of(g);
  double threshold = std::numeric_limits<double>::infinity();
  if (stiffness) {
    std::vector<double> in;
    for (index_t v = 0; v < g.size(); v += std::max<index_t>(1, g.size() / 100000))
      if ((*stiffness)[v] > 0) in.push_back(double((*stiffness)[v]));
    if (!in.empty()) {
      std::nth_element(in.begin(), in.begin() + std::ptrdiff_t(in.size() / 2), in.end());
      threshold = in[in.size() / 2] * stiff_ratio;
    }
  }
  auto pic = detail::paint(g, ps, scale, [&](index_t v, index_t px, index_t py) {
    if (v < 0) return rgb{40, 40, 40};
    rgb c = label_colour(label[v]);
    if (stiffness && double((*stiffness)[v]) >= threshold)
      c = ((px + py) / 3) % 2 ? detail::mix(c, rgb{235, 235, 235}, 0.75) : detail::mix(c, rgb{90, 90, 90}, 0.6);
    return c;
  });
  detail::draw_borders(pic, g, ps, scale, [&](index_t v) { return v < 0 ? no_label - 1 : label[v]; }, rgb{0, 0, 0});
  detail::draw_seeds(pic, g, ps, scale, seeds, rgb{255, 255, 255});
  return pic;
}

/**
 * @brief Heat map of a scalar volume (distance or weight) on [lo, hi] with `levels` iso-lines;
 *        non-finite values (unreachable voxels) in dark grey. hi <= lo: the finite range of the data.
 */
template <class T, int Dim>
rgb_image heat_montage(const image<T, Dim>& values, int levels = 10, double lo = 0.0, double hi = -1.0,
                       const std::vector<index_t>& seeds = {}, int scale = 0) {
  const auto& g = values.geometry();
  if (!(hi > lo)) {
    hi = lo;
    for (index_t v = 0; v < g.size(); ++v)
      if (std::isfinite(double(values[v]))) hi = std::max(hi, double(values[v]));
    if (!(hi > lo)) hi = lo + 1;
  }
  auto ps = detail::panels_of(g);
  auto t_of = [&](index_t v) { return (double(values[v]) - lo) / (hi - lo); };
  auto pic = detail::paint(g, ps, scale, [&](index_t v, index_t, index_t) {
    if (v < 0) return rgb{40, 40, 40};
    if (!std::isfinite(double(values[v]))) return rgb{60, 60, 60};
    return detail::heat(t_of(v));
  });
  if (levels > 0)
    detail::draw_borders(pic, g, ps, scale, [&](index_t v) -> long long {
      if (v < 0 || !std::isfinite(double(values[v]))) return -1;
      return (long long)std::floor(std::clamp(t_of(v), 0.0, 1.0) * levels * 0.9999);
    }, rgb{255, 255, 255});
  if (!seeds.empty()) detail::draw_seeds(pic, g, ps, scale, seeds, rgb{80, 200, 255});
  return pic;
}

/// Distance montage: heat map of the finite distances with `levels` iso-lines, seeds marked.
template <class T, int Dim>
rgb_image distance_montage(const image<T, Dim>& distance, const std::vector<index_t>& seeds = {}, int levels = 12) {
  return heat_montage(distance, levels, 0.0, -1.0, seeds);
}

/// Shape-function montage: one node's weight in [0, 1] with iso-lines every 0.1, that node marked.
template <class T, int Dim>
rgb_image weight_montage(const image<T, Dim>& weight, index_t node_voxel = -1) {
  std::vector<index_t> s;
  if (node_voxel >= 0) s.push_back(node_voxel);
  return heat_montage(weight, 10, 0.0, 1.0, s);
}

}  // namespace geovoronoi::io

#pragma once
/// @file io/picture.hpp
/// @brief Pictures of a volume people can read: the three orthogonal slices through one voxel, drawn
///        true to the grid's spacing, with a title, node markers numbered by node index, a colour bar
///        with numbers and its unit (heat pictures), and a legend of every mark the picture uses.
///
/// Layout (3D): the XY slice (x right, y down) at the top left; below it the XZ slice (x right,
/// z down), as wide as XY; right of it the ZY slice (z right, y down), as tall as XY. A grid with a
/// single z slice, a 2D grid, or `picture_options::xy_only` gives the XY panel alone. The title runs
/// across the top (wrapped to the picture's width); the colour bar and legend form a column on the
/// right. Each panel is drawn spacing-true: a voxel is `spacing(a) * pixels_per_unit` pixels along
/// axis a, so an MRI of 1 x 1 x 3 mm voxels is not squashed.
///
/// Colours are stable across pictures: node i (the seed with index i) has `node_colour(i)`, which
/// is also the colour of its cell in a label picture, in every picture of a run.
///
/// Text uses a built-in 5x7 bitmap font (capitals, digits, a few symbols), no font files.
///
/// @code
/// namespace gio = geovoronoi::io;
/// gio::picture_options o;
/// o.title = {"labels, metric min_stiffness"};
/// gio::write_png("labels.png", gio::label_picture(d.label, d.seeds, &stiffness, o));
/// gio::write_png("distance.png", gio::distance_picture(d.distance, d.seeds, "mm", o));
/// @endcode

#include <geovoronoi/io/common.hpp>
#include <geovoronoi/io/detail/font.hpp>
#include <geovoronoi/io/rgb_image.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace geovoronoi::io {

/// Colour of the canvas around the panels, of the text on it, and of voxels outside the domain or
/// not reached by any node.
inline constexpr rgb picture_background{250, 250, 248}, picture_ink{20, 20, 20}, picture_outside{72, 72, 72};

/// A distinct colour for label l (golden-angle hues, alternating saturation and brightness).
/// @pre l >= 0; a negative label (outside, unreached) is drawn in `picture_outside`.
inline rgb label_colour(label_t l);

/// The colour of node i in every picture: the colour of its cell in a label picture.
inline rgb node_colour(index_t i) { return label_colour(label_t(i)); }

/// The heat colour map (dark purple, red, orange, yellow, near-white) at t in [0, 1]; t is clamped.
inline rgb heat_colour(double t);

/// The values a heat picture maps to its colour map's ends, and what the data held.
struct colour_range {
  double lo = 0.0, hi = 1.0;            ///< mapped to heat_colour(0) and heat_colour(1)
  double data_lo = 0.0, data_hi = 1.0;  ///< the smallest and largest finite value in the data
  double percentile_lo = 0.0, percentile_hi = 100.0;  ///< which percentiles lo and hi are (for the caption)
  bool clipped_lo() const { return data_lo < lo; }
  bool clipped_hi() const { return data_hi > hi; }
};

/// A fixed range [lo, hi] (e.g. [0, 1] for a weight); data_lo/data_hi are set from @p values.
template <class T, int Dim>
colour_range fixed_range(const image<T, Dim>& values, double lo, double hi);

/**
 * @brief A robust colour range: lo and hi are the @p p_lo and @p p_hi percentiles of the finite
 *        values (nearest rank), so a few outliers (a distance across bone, a voxel behind a wall)
 *        do not squeeze everything else into one colour. p_lo = 0, p_hi = 100: the full range.
 *        Volumes of more than 2^21 voxels are sampled with a fixed stride (deterministic).
 * @pre 0 <= p_lo < p_hi <= 100
 */
template <class T, int Dim>
colour_range robust_range(const image<T, Dim>& values, double p_lo = 1.0, double p_hi = 99.0);

/// What a picture shows and how it is laid out.
struct picture_options {
  /// Title lines (wrapped at spaces to the picture's width). The renderer adds a line naming the
  /// slices shown (3D).
  std::vector<std::string> title;
  /// The voxel the three slices pass through; -1 on an axis: its middle (extent / 2).
  std::array<index_t, 3> slice{{-1, -1, -1}};
  /// 3D: draw only the XY slice.
  bool xy_only = false;
  /// Draw the column on the right (colour bar, legend).
  bool legend = true;
  /// Pixels per unit of length; 0: automatic (the panels about 560 pixels on their longer side, a
  /// voxel of the finest spacing between 1 and 40 pixels).
  double pixels_per_unit = 0.0;
  /// Size in pixels of one dot of the font (a glyph is 5 x 7 dots).
  int text_scale = 2;
  /// This node is drawn with a larger marker (the node whose weight is pictured); -1: none.
  index_t highlight_node = -1;
  /// Node indices are written beside the markers when there are at most this many nodes.
  std::size_t max_node_labels = 64;
  /// Label pictures: a cut surface, drawn as a thick line between two voxels that are neighbours in
  /// a panel (they share a face) where `cut_between(u, v)` is true; empty: none.
  std::function<bool(index_t, index_t)> cut_between;
  /// Label pictures: voxels outlined (inside their region's border) where `marked(v)` is true, e.g.
  /// those a change affected, named `marked_text` in the legend; empty: none.
  std::function<bool(index_t)> marked;
  std::string marked_text = "CHANGED";
};

/// The colours of a label picture's cut line and of the outline of marked voxels.
inline constexpr rgb picture_cut{220, 20, 60}, picture_marked{255, 255, 255};

// ---------------------------------------------------------------------------------------------------

inline rgb label_colour(label_t l) {
  if (l < 0) return picture_outside;
  const double h = std::fmod(0.13 + 0.618033988749895 * l, 1.0) * 6.0, s = l % 2 ? 0.55 : 0.75,
               v = l % 3 == 1 ? 0.80 : 0.95;
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
  auto byte = [](double x) { return static_cast<unsigned char>(x * 255 + 0.5); };
  return {byte(r), byte(g), byte(b)};
}

namespace detail {

inline rgb mix(rgb a, rgb b, double t) {
  auto m = [t](unsigned char x, unsigned char y) { return static_cast<unsigned char>(x + (y - x) * t + 0.5); };
  return {m(a.r, b.r), m(a.g, b.g), m(a.b, b.b)};
}

inline std::string format_value(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", x);
  return buf;
}

}  // namespace detail

inline rgb heat_colour(double t) {
  static const rgb stops[] = {{10, 7, 40}, {90, 20, 120}, {190, 40, 90}, {245, 110, 30}, {250, 200, 50}, {255, 255, 220}};
  if (!(t > 0)) return stops[0];
  if (t >= 1) return stops[5];
  const double s = t * 5;
  const int i = int(s);
  return detail::mix(stops[i], stops[i + 1], s - i);
}

template <class T, int Dim>
colour_range fixed_range(const image<T, Dim>& values, double lo, double hi) {
  colour_range r;
  r.lo = lo, r.hi = hi;
  r.data_lo = std::numeric_limits<double>::infinity(), r.data_hi = -r.data_lo;
  for (index_t v = 0; v < values.size(); ++v) {
    const double x = double(values[v]);
    if (std::isfinite(x)) r.data_lo = std::min(r.data_lo, x), r.data_hi = std::max(r.data_hi, x);
  }
  if (!(r.data_lo <= r.data_hi)) r.data_lo = lo, r.data_hi = hi;
  return r;
}

template <class T, int Dim>
colour_range robust_range(const image<T, Dim>& values, double p_lo, double p_hi) {
  if (!(p_lo >= 0 && p_lo < p_hi && p_hi <= 100))
    throw std::invalid_argument("geovoronoi::io::robust_range: percentiles must satisfy 0 <= p_lo < p_hi <= 100");
  const index_t stride = std::max<index_t>(1, values.size() >> 21);
  std::vector<double> x;
  for (index_t v = 0; v < values.size(); v += stride)
    if (std::isfinite(double(values[v]))) x.push_back(double(values[v]));
  colour_range r = fixed_range(values, 0.0, 1.0);
  r.percentile_lo = p_lo, r.percentile_hi = p_hi;
  if (x.empty()) return r;
  auto rank = [&](double p) {
    const auto k = std::ptrdiff_t(std::llround(p / 100.0 * double(x.size() - 1)));
    std::nth_element(x.begin(), x.begin() + k, x.end());
    return x[std::size_t(k)];
  };
  r.lo = p_lo == 0 ? r.data_lo : rank(p_lo);
  r.hi = p_hi == 100 ? r.data_hi : rank(p_hi);
  if (!(r.hi > r.lo)) {  // (nearly) constant data: a unit-wide range from its value
    r.lo = std::min(r.lo, r.data_lo);
    r.hi = std::max(r.lo + 1.0, r.data_hi);
  }
  return r;
}

namespace detail {

/// One panel: a slice spanned by axes u (rightwards) and v (downwards) at coordinate `fixed` of
/// `fixed_axis` (-1 in 2D), nu x nv voxels drawn into the w x h pixels at (x0, y0).
struct view {
  int u = 0, v = 1, fixed_axis = -1;
  index_t fixed = 0, nu = 1, nv = 1;
  index_t x0 = 0, y0 = 0, w = 1, h = 1;
  std::string tag;
  /// The voxel coordinate along u of pixel column px (inside the panel).
  index_t a_of(index_t px) const { return std::min(nu - 1, (px - x0) * nu / w); }
  index_t b_of(index_t py) const { return std::min(nv - 1, (py - y0) * nv / h); }
  bool contains(index_t px, index_t py) const { return px >= x0 && py >= y0 && px < x0 + w && py < y0 + h; }
  /// Pixel of the centre of voxel (a, b).
  index_t cx(index_t a) const { return x0 + index_t((double(a) + 0.5) * double(w) / double(nu)); }
  index_t cy(index_t b) const { return y0 + index_t((double(b) + 0.5) * double(h) / double(nv)); }
};

/// The panels of a picture of grid g, placed in a block whose top-left corner is (0, 0).
template <int Dim>
struct panel_layout {
  std::vector<view> views;
  std::array<index_t, 3> at{{0, 0, 0}};
  index_t width = 0, height = 0;
  double ppu = 1.0;  ///< pixels per unit of length
};

template <int Dim>
panel_layout<Dim> make_layout(const grid<Dim>& g, const picture_options& o) {
  panel_layout<Dim> L;
  const bool three = Dim == 3 && !o.xy_only && g.extent(Dim - 1) > 1;
  for (int a = 0; a < Dim; ++a) {
    const index_t want = o.slice[std::size_t(a)];
    L.at[std::size_t(a)] = want < 0 ? g.extent(a) / 2 : std::min(want, g.extent(a) - 1);
  }
  const double X = double(g.extent(0)) * g.spacing(0), Y = double(g.extent(1)) * g.spacing(1);
  const double Z = three ? double(g.extent(Dim - 1)) * g.spacing(Dim - 1) : 0.0;
  double finest = g.spacing(0);
  for (int a = 1; a < Dim; ++a) finest = std::min(finest, g.spacing(a));
  double ppu = o.pixels_per_unit;
  if (!(ppu > 0)) {
    ppu = 560.0 / std::max(X + Z, Y + Z);
    ppu = std::clamp(ppu, 1.0 / finest, 40.0 / finest);
  }
  L.ppu = ppu;
  auto px = [&](index_t n, int axis) { return std::max<index_t>(1, index_t(std::llround(double(n) * g.spacing(axis) * ppu))); };
  const index_t gap = 6;
  auto make = [&](int u, int v, int fixed_axis, std::string tag) {
    view w;
    w.u = u, w.v = v, w.fixed_axis = fixed_axis;
    w.fixed = fixed_axis >= 0 ? L.at[std::size_t(fixed_axis)] : 0;
    w.nu = g.extent(u), w.nv = g.extent(v);
    w.w = px(w.nu, u), w.h = px(w.nv, v);
    w.tag = std::move(tag);
    return w;
  };
  if (!three) {
    L.views.push_back(make(0, 1, Dim == 3 ? 2 : -1, ""));
    L.width = L.views[0].w, L.height = L.views[0].h;
    return L;
  }
  auto at = [&](int a) { return std::to_string(L.at[std::size_t(a)]); };
  view xy = make(0, 1, 2, "XY, Z=" + at(2)), xz = make(0, 2, 1, "XZ, Y=" + at(1)), zy = make(2, 1, 0, "ZY, X=" + at(0));
  xz.y0 = xy.h + gap;
  zy.x0 = xy.w + gap;
  L.width = zy.x0 + zy.w, L.height = xz.y0 + xz.h;
  L.views = {xy, xz, zy};
  return L;
}

/// The voxel at pixel (px, py) of view w, in grid g.
template <int Dim>
index_t voxel_of(const grid<Dim>& g, const view& w, index_t px, index_t py) {
  coord<Dim> c{};
  c[w.u] = w.a_of(px);
  c[w.v] = w.b_of(py);
  if (w.fixed_axis >= 0 && w.fixed_axis < Dim) c[w.fixed_axis] = w.fixed;
  return g.index(c);
}

/// Paints every pixel of every panel with colour(voxel, px, py).
template <int Dim, class Colour>
void paint(rgb_image& pic, const grid<Dim>& g, const std::vector<view>& views, Colour colour) {
  for (const auto& w : views)
    for (index_t py = w.y0; py < w.y0 + w.h; ++py)
      for (index_t px = w.x0; px < w.x0 + w.w; ++px) pic.set(px, py, colour(voxel_of(g, w, px, py), px, py));
}

/// Draws a line pixel where the class of a pixel's voxel differs from its right or lower neighbour's.
template <int Dim, class Class>
void draw_borders(rgb_image& pic, const grid<Dim>& g, const std::vector<view>& views, Class cls, rgb colour) {
  for (const auto& w : views)
    for (index_t py = w.y0; py < w.y0 + w.h; ++py)
      for (index_t px = w.x0; px < w.x0 + w.w; ++px) {
        const index_t v = voxel_of(g, w, px, py);
        const auto c = cls(v);
        const index_t r = px + 1 < w.x0 + w.w ? voxel_of(g, w, px + 1, py) : v;
        const index_t d = py + 1 < w.y0 + w.h ? voxel_of(g, w, px, py + 1) : v;
        if ((r != v && cls(r) != c) || (d != v && cls(d) != c)) pic.set(px, py, colour);
      }
}

/// Draws a line 3 pixels wide on the border between two pixels whose voxels are in-panel neighbours
/// with `between(u, v)` true.
template <int Dim, class Between>
void draw_between(rgb_image& pic, const grid<Dim>& g, const std::vector<view>& views, Between between, rgb colour) {
  for (const auto& w : views)
    for (index_t py = w.y0; py < w.y0 + w.h; ++py)
      for (index_t px = w.x0; px < w.x0 + w.w; ++px) {
        const index_t v = voxel_of(g, w, px, py);
        if (px + 1 < w.x0 + w.w) {
          const index_t r = voxel_of(g, w, px + 1, py);
          if (r != v && between(v, r))
            for (index_t x = std::max(w.x0, px - 1); x <= std::min(w.x0 + w.w - 1, px + 1); ++x) pic.set(x, py, colour);
        }
        if (py + 1 < w.y0 + w.h) {
          const index_t d = voxel_of(g, w, px, py + 1);
          if (d != v && between(v, d))
            for (index_t y = std::max(w.y0, py - 1); y <= std::min(w.y0 + w.h - 1, py + 1); ++y) pic.set(px, y, colour);
        }
      }
}

/// Outlines the regions of marked voxels: a pixel of a marked voxel next to (4-neighbours) a pixel
/// of an unmarked voxel or the panel's edge takes the colour.
template <int Dim, class Marked>
void draw_outline(rgb_image& pic, const grid<Dim>& g, const std::vector<view>& views, Marked marked, rgb colour) {
  for (const auto& w : views)
    for (index_t py = w.y0; py < w.y0 + w.h; ++py)
      for (index_t px = w.x0; px < w.x0 + w.w; ++px) {
        if (!marked(voxel_of(g, w, px, py))) continue;
        bool edge = false;
        const index_t nx[4] = {px - 1, px + 1, px, px}, ny[4] = {py, py, py - 1, py + 1};
        for (int k = 0; k < 4 && !edge; ++k)
          edge = !w.contains(nx[k], ny[k]) || !marked(voxel_of(g, w, nx[k], ny[k]));
        if (edge) pic.set(px, py, colour);
      }
}

/// A node marker centred at (cx, cy): black outer ring, white ring, and inside either the node's
/// colour (filled: the node lies in the slice) or nothing (hollow: a projection of a node off it).
inline void draw_marker(rgb_image& pic, index_t cx, index_t cy, index_t r, rgb fill, bool filled) {
  for (index_t dy = -r - 1; dy <= r + 1; ++dy)
    for (index_t dx = -r - 1; dx <= r + 1; ++dx) {
      const index_t d = std::max(std::abs(dx), std::abs(dy));
      if (d == r + 1) pic.set(cx + dx, cy + dy, rgb{0, 0, 0});
      else if (d >= r - 1) pic.set(cx + dx, cy + dy, rgb{255, 255, 255});
      else if (filled) pic.set(cx + dx, cy + dy, fill);
    }
}

inline index_t marker_radius(const picture_options& o) { return 2 + 2 * index_t(o.text_scale); }

/// Marks the nodes (voxel indices, node i = nodes[i]) in every panel, numbered when there are few.
template <int Dim>
void draw_nodes(rgb_image& pic, const grid<Dim>& g, const std::vector<view>& views,
                const std::vector<index_t>& nodes, const picture_options& o) {
  const rgb white{255, 255, 255}, black{0, 0, 0};
  for (const auto& w : views) {
    // draw the projected (hollow) markers first so a node in the slice is never hidden by one
    for (int pass = 0; pass < 2; ++pass)
      for (std::size_t i = 0; i < nodes.size(); ++i) {
        const index_t s = nodes[i];
        if (s < 0 || s >= g.size()) continue;
        const auto c = g.coords(s);
        const bool on = w.fixed_axis < 0 || w.fixed_axis >= Dim || std::abs(c[w.fixed_axis] - w.fixed) <= 1;
        if (on != (pass == 1)) continue;
        const index_t cx = w.cx(c[w.u]), cy = w.cy(c[w.v]);
        // a projection is smaller and unnumbered: many nodes project onto the same row of a side panel
        const index_t r = marker_radius(o) + (index_t(i) == o.highlight_node ? 3 : 0) - (on ? 0 : 2);
        draw_marker(pic, cx, cy, r, node_colour(index_t(i)), on);
        if (on && nodes.size() <= o.max_node_labels)
          draw_text(pic, cx + r + 3, cy - text_height(o.text_scale) / 2, std::to_string(i), o.text_scale, white, &black);
      }
    if (!w.tag.empty())
      draw_text(pic, w.x0 + 4, w.y0 + w.h - 4 - text_height(o.text_scale), w.tag, o.text_scale, white, &black);
  }
}

/// One entry of the legend column: a swatch and its text.
struct legend_item {
  enum kind_t { fill, hatch, line, node_filled, node_hollow } kind;
  rgb colour;
  std::string text;
};

/// A column of lines and legend entries, measured before it is drawn.
struct column {
  struct entry {
    enum what_t { text_line, legend_entry, colour_bar } what;
    std::string s;
    legend_item item{legend_item::fill, {}, {}};
  };
  std::vector<entry> entries;
  index_t bar_height = 0;
  const colour_range* range = nullptr;
  int levels = 0;
};

inline void draw_hatch_swatch(rgb_image& pic, index_t x, index_t y, index_t w, index_t h, rgb base);

/// Width and height of the column (bar ticks included), for text at scale s.
inline std::array<index_t, 2> column_size(const column& c, int s) {
  const index_t line = text_height(s) + 2 * s + 2, sw = 10 * s + 4;
  index_t w = 0, h = 0;
  for (const auto& e : c.entries) {
    if (e.what == column::entry::text_line) w = std::max(w, text_width(e.s, s)), h += line;
    else if (e.what == column::entry::legend_entry) w = std::max(w, sw + 3 * s + text_width(e.item.text, s)), h += line + 2;
    else {
      index_t tick = 0;
      for (int k = 0; k <= 4; ++k)
        tick = std::max(tick, text_width(">" + format_value(c.range->lo + k / 4.0 * (c.range->hi - c.range->lo)), s));
      w = std::max(w, 9 * s + 4 * s + tick), h += c.bar_height + text_height(s) + 4 * s;
    }
  }
  return {w, h};
}

inline void draw_column(rgb_image& pic, index_t x, index_t y, const column& c, int s) {
  const index_t line = text_height(s) + 2 * s + 2, sw = 10 * s + 4, swh = text_height(s) + 2;
  const rgb black{0, 0, 0}, white{255, 255, 255};
  for (const auto& e : c.entries) {
    if (e.what == column::entry::text_line) {
      draw_text(pic, x, y, e.s, s, picture_ink);
      y += line;
    } else if (e.what == column::entry::legend_entry) {
      const auto& it = e.item;
      const index_t cy = y + swh / 2;
      switch (it.kind) {
        case legend_item::fill: pic.fill(x, y, sw, swh, it.colour); break;
        case legend_item::hatch: draw_hatch_swatch(pic, x, y, sw, swh, it.colour); break;
        case legend_item::line:
          pic.fill(x, y, sw, swh, rgb{150, 150, 150});
          pic.fill(x, cy, sw, 1, it.colour);
          break;
        case legend_item::node_filled:
        case legend_item::node_hollow:
          pic.fill(x, y - 1, sw, swh + 2, rgb{150, 150, 150});
          draw_marker(pic, x + sw / 2, cy, swh / 2 - 1, it.colour, it.kind == legend_item::node_filled);
          break;
      }
      if (it.kind != legend_item::line && it.kind != legend_item::node_filled && it.kind != legend_item::node_hollow) {
        pic.fill(x - 1, y - 1, sw + 2, 1, black), pic.fill(x - 1, y + swh, sw + 2, 1, black);
        pic.fill(x - 1, y - 1, 1, swh + 2, black), pic.fill(x + sw, y - 1, 1, swh + 2, black);
      }
      draw_text(pic, x + sw + 3 * s, y + 1, it.text, s, picture_ink);
      y += line + 2;
    } else {
      // the colour bar: top row heat(1) = hi, bottom row heat(0) = lo, five numbered ticks
      const colour_range& r = *c.range;
      const index_t bw = 9 * s, bh = c.bar_height, top = y + text_height(s) / 2;
      for (index_t j = 0; j < bh; ++j) {
        const double t = bh > 1 ? 1.0 - double(j) / double(bh - 1) : 1.0;
        pic.fill(x, top + j, bw, 1, heat_colour(t));
      }
      if (c.levels > 0)
        for (int k = 1; k < c.levels; ++k)
          pic.fill(x, top + bh - 1 - index_t(std::llround(double(k) / c.levels * double(bh - 1))), bw / 3, 1, white);
      pic.fill(x - 1, top - 1, bw + 2, 1, black), pic.fill(x - 1, top + bh, bw + 2, 1, black);
      pic.fill(x - 1, top - 1, 1, bh + 2, black), pic.fill(x + bw, top - 1, 1, bh + 2, black);
      for (int k = 0; k <= 4; ++k) {
        const double f = k / 4.0;
        const index_t ty = top + bh - 1 - index_t(std::llround(f * double(bh - 1)));
        std::string label = format_value(r.lo + f * (r.hi - r.lo));
        if (k == 4 && r.clipped_hi()) label = ">" + label;
        if (k == 0 && r.clipped_lo()) label = "<" + label;
        pic.fill(x + bw, ty, 3 * s, 1, black);
        draw_text(pic, x + bw + 4 * s, ty - text_height(s) / 2, label, s, picture_ink);
      }
      y += bh + text_height(s) + 4 * s;
    }
  }
}

inline bool hatch_light(index_t px, index_t py) { return ((px + py) / 3) % 2 != 0; }

inline rgb hatched(rgb c, index_t px, index_t py) {
  return hatch_light(px, py) ? mix(c, rgb{235, 235, 235}, 0.75) : mix(c, rgb{90, 90, 90}, 0.6);
}

inline void draw_hatch_swatch(rgb_image& pic, index_t x, index_t y, index_t w, index_t h, rgb base) {
  for (index_t j = 0; j < h; ++j)
    for (index_t i = 0; i < w; ++i) pic.set(x + i, y + j, hatched(base, x + i, y + j));
}

/// Splits text at spaces into lines at most `width` pixels wide (a longer word gets its own line).
inline std::vector<std::string> wrap(const std::string& text, index_t width, int s) {
  std::vector<std::string> lines;
  std::string cur, word;
  auto flush_word = [&] {
    if (word.empty()) return;
    const std::string joined = cur.empty() ? word : cur + " " + word;
    if (!cur.empty() && text_width(joined, s) > width) lines.push_back(cur), cur = word;
    else cur = joined;
    word.clear();
  };
  for (char ch : text) {
    if (ch == ' ') flush_word();
    else word += ch;
  }
  flush_word();
  if (!cur.empty()) lines.push_back(cur);
  return lines;
}

/// Assembles a picture: title, the panels painted by `draw_panels(pic, views)`, the column.
template <int Dim, class DrawPanels>
rgb_image assemble(const grid<Dim>& g, const picture_options& o, const column& col, DrawPanels draw_panels) {
  auto L = make_layout(g, o);
  const int s = std::max(1, o.text_scale);
  const index_t margin = 4 * s, gap = 6 * s;
  const auto cs = o.legend ? column_size(col, s) : std::array<index_t, 2>{0, 0};
  index_t width = L.width + (o.legend ? gap + cs[0] : 0);
  std::vector<std::string> title_lines = o.title;
  std::string grid_text, spacing_text;
  for (int a = 0; a < Dim; ++a) {
    grid_text += (a ? "X" : "") + std::to_string(g.extent(a));
    spacing_text += (a ? "X" : "") + format_value(g.spacing(a));
  }
  grid_text += " VOXELS OF " + spacing_text;
  if (Dim == 3 && L.views.size() == 3)
    title_lines.push_back("SLICES THROUGH VOXEL (" + std::to_string(L.at[0]) + ", " + std::to_string(L.at[1]) + ", " +
                          std::to_string(L.at[2]) + ") IN " + grid_text);
  else if (Dim == 3 && g.extent(2) > 1)
    title_lines.push_back("SLICE Z=" + std::to_string(L.at[2]) + " IN " + grid_text);
  else
    title_lines.push_back(grid_text);
  std::vector<std::string> lines;
  for (const auto& t : title_lines)
    for (auto& l : wrap(t, width, s)) width = std::max(width, text_width(l, s)), lines.push_back(std::move(l));
  const index_t line = text_height(s) + 3 * s;
  const index_t top = margin + index_t(lines.size()) * line + (lines.empty() ? 0 : 3 * s);
  const index_t height = top + std::max(L.height, cs[1]) + margin;
  rgb_image pic(width + 2 * margin, height, picture_background);
  for (std::size_t i = 0; i < lines.size(); ++i) draw_text(pic, margin, margin + index_t(i) * line, lines[i], s, picture_ink);
  for (auto& w : L.views) w.x0 += margin, w.y0 += top;
  draw_panels(pic, L.views);
  if (o.legend) draw_column(pic, margin + L.width + gap, top, col, s);
  return pic;
}

inline void add_node_legend(column& col, bool three_d, bool numbered) {
  using E = column::entry;
  col.entries.push_back({E::legend_entry, "", {legend_item::node_filled, node_colour(0), three_d ? "NODE IN SLICE (+-1)" : "NODE"}});
  if (three_d) col.entries.push_back({E::legend_entry, "", {legend_item::node_hollow, {}, "NODE OFF SLICE (NO NUMBER)"}});
  if (numbered) col.entries.push_back({E::text_line, "(NUMBER = NODE INDEX)", {}});
}

}  // namespace detail

/**
 * @brief Label picture: each cell in its node's colour with black borders, nodes marked and
 *        numbered; with a stiffness image, the stiffest material (at least `stiff_ratio` times the
 *        median inside value) hatched so one sees the cells bend around it; a cut drawn and
 *        changed voxels outlined when picture_options::cut_between / marked are set.
 * @param nodes voxel index of node i at position i (diagram::seeds)
 */
template <int Dim, class S = float>
rgb_image label_picture(const image<label_t, Dim>& label, const std::vector<index_t>& nodes,
                        const image<S, Dim>* stiffness = nullptr, const picture_options& o = {},
                        double stiff_ratio = 100.0) {
  const auto& g = label.geometry();
  double threshold = std::numeric_limits<double>::infinity();
  bool any_stiff = false;
  if (stiffness) {
    std::vector<double> in;
    for (index_t v = 0; v < g.size(); v += std::max<index_t>(1, g.size() / 100000))
      if ((*stiffness)[v] > 0) in.push_back(double((*stiffness)[v]));
    if (!in.empty()) {
      std::nth_element(in.begin(), in.begin() + std::ptrdiff_t(in.size() / 2), in.end());
      threshold = in[in.size() / 2] * stiff_ratio;
    }
    for (index_t v = 0; v < g.size() && !any_stiff; ++v) any_stiff = double((*stiffness)[v]) >= threshold;
  }
  using E = detail::column::entry;
  detail::column col;
  col.entries.push_back({E::text_line, "LEGEND", {}});
  col.entries.push_back({E::legend_entry, "", {detail::legend_item::line, rgb{0, 0, 0}, "CELL BORDER"}});
  if (any_stiff)
    col.entries.push_back({E::legend_entry, "", {detail::legend_item::hatch, label_colour(0),
                                         "STIFF: >=" + detail::format_value(stiff_ratio) + "X MEDIAN"}});
  col.entries.push_back({E::legend_entry, "", {detail::legend_item::fill, picture_outside, "OUTSIDE/UNREACHED"}});
  if (o.cut_between) col.entries.push_back({E::legend_entry, "", {detail::legend_item::line, picture_cut, "CUT"}});
  if (o.marked)
    col.entries.push_back({E::legend_entry, "", {detail::legend_item::line, picture_marked, o.marked_text + " (OUTLINED)"}});
  if (!nodes.empty())
    detail::add_node_legend(col, Dim == 3 && g.extent(Dim - 1) > 1 && !o.xy_only, nodes.size() <= o.max_node_labels);
  col.entries.push_back({E::text_line, "CELL COLOUR = ITS NODE'S", {}});
  return detail::assemble(g, o, col, [&](rgb_image& pic, const std::vector<detail::view>& views) {
    detail::paint(pic, g, views, [&](index_t v, index_t px, index_t py) {
      rgb c = label_colour(label[v]);
      if (stiffness && double((*stiffness)[v]) >= threshold) c = detail::hatched(c, px, py);
      return c;
    });
    detail::draw_borders(pic, g, views, [&](index_t v) { return label[v] < 0 ? label_t(-1) : label[v]; }, rgb{0, 0, 0});
    if (o.marked) detail::draw_outline(pic, g, views, o.marked, picture_marked);
    if (o.cut_between) detail::draw_between(pic, g, views, o.cut_between, picture_cut);
    detail::draw_nodes(pic, g, views, nodes, o);
  });
}

/**
 * @brief Heat picture of a scalar volume on `range` (heat_colour(0) at range.lo, heat_colour(1)
 *        at range.hi, values outside clamped), with `levels` - 1 white iso-lines evenly between;
 *        non-finite values (unreachable voxels) in picture_outside. The colour bar is captioned
 *        @p caption (what and unit) and says when the range clips the data.
 */
template <class T, int Dim>
rgb_image heat_picture(const image<T, Dim>& values, const colour_range& range, const std::string& caption,
                       const std::vector<index_t>& nodes = {}, const picture_options& o = {}, int levels = 10) {
  const auto& g = values.geometry();
  const double lo = range.lo, span = range.hi > range.lo ? range.hi - range.lo : 1.0;
  auto t_of = [&](index_t v) { return (double(values[v]) - lo) / span; };
  using E = detail::column::entry;
  detail::column col;
  col.range = &range;
  col.levels = levels;
  col.entries.push_back({E::text_line, caption, {}});
  col.entries.push_back({E::colour_bar, "", {}});
  if (range.clipped_lo() || range.clipped_hi()) {
    col.entries.push_back({E::text_line, "COLOURS CLIPPED TO THE", {}});
    col.entries.push_back({E::text_line, detail::format_value(range.percentile_lo) + "-" +
                                        detail::format_value(range.percentile_hi) + " % RANGE, DATA", {}});
    col.entries.push_back({E::text_line, detail::format_value(range.data_lo) + " TO " + detail::format_value(range.data_hi), {}});
  }
  if (levels > 1)
    col.entries.push_back({E::legend_entry, "", {detail::legend_item::line, rgb{255, 255, 255},
                                         "ISO-LINE EVERY " + detail::format_value(span / levels)}});
  col.entries.push_back({E::legend_entry, "", {detail::legend_item::fill, picture_outside, "OUTSIDE/UNREACHED"}});
  if (!nodes.empty())
    detail::add_node_legend(col, Dim == 3 && g.extent(Dim - 1) > 1 && !o.xy_only, nodes.size() <= o.max_node_labels);
  // the bar as tall as the panels leave room for, at least 100 pixels
  const auto L = detail::make_layout(g, o);
  const index_t rest = detail::column_size(col, std::max(1, o.text_scale))[1];
  col.bar_height = std::max<index_t>(100, L.height - rest);
  return detail::assemble(g, o, col, [&](rgb_image& pic, const std::vector<detail::view>& views) {
    detail::paint(pic, g, views, [&](index_t v, index_t, index_t) {
      return std::isfinite(double(values[v])) ? heat_colour(t_of(v)) : picture_outside;
    });
    if (levels > 1)
      detail::draw_borders(pic, g, views, [&](index_t v) -> long long {
        if (!std::isfinite(double(values[v]))) return -1;
        return (long long)std::floor(std::clamp(t_of(v), 0.0, 1.0) * levels * 0.9999);
      }, rgb{255, 255, 255});
    detail::draw_nodes(pic, g, views, nodes, o);
  });
}

/// Distance picture: heat map from 0 to the 99th percentile of the finite distances (stated in
/// the colour bar when it clips), 10 iso-lines, nodes marked. @p unit: the distance's unit.
template <class T, int Dim>
rgb_image distance_picture(const image<T, Dim>& distance, const std::vector<index_t>& nodes,
                           const std::string& unit, const picture_options& o = {}, double p_hi = 99.0) {
  auto r = robust_range(distance, 0.0, p_hi);
  r.lo = std::min(0.0, r.lo);
  return heat_picture(distance, r, "DISTANCE (" + unit + ")", nodes, o, 10);
}

/// Shape-function picture: the weight of node @p node on [0, 1], iso-lines every 0.1, every node
/// marked and `node` drawn larger.
template <class T, int Dim>
rgb_image weight_picture(const image<T, Dim>& weight, index_t node, const std::vector<index_t>& nodes,
                         picture_options o = {}) {
  o.highlight_node = node;
  return heat_picture(weight, fixed_range(weight, 0.0, 1.0), "WEIGHT OF NODE " + std::to_string(node) + " (NO UNIT)",
                      nodes, o, 10);
}

}  // namespace geovoronoi::io

// Pictures: the font puts ink where its glyphs say, panels follow the grid's spacing, the robust
// range clips outliers and says so, the colour bar runs from one end of the colour map to the
// other, node markers carry their node's colour (the same in every picture) and number.
#include <geovoronoi/io/picture.hpp>

#include <doctest/doctest.h>

#include <algorithm>
#include <limits>
#include <set>
#include <tuple>
#include <vector>

namespace gio = geovoronoi::io;
namespace gd = geovoronoi::io::detail;
using geovoronoi::index_t;
using geovoronoi::label_t;

namespace {

/// The pixels of a 5x7 glyph drawn by hand, row by row ('#' ink).
const char* const zero_glyph[7] = {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."};
const char* const one_glyph[7] = {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."};
const char* const e_glyph[7] = {"#####", "#....", "#....", "####.", "#....", "#....", "#####"};

void check_glyph(const gio::rgb_image& pic, index_t x0, index_t y0, int scale, const char* const* rows, gio::rgb ink) {
  for (int r = 0; r < 7; ++r)
    for (int c = 0; c < 5; ++c)
      for (int dy = 0; dy < scale; ++dy)
        for (int dx = 0; dx < scale; ++dx) {
          const bool want = rows[r][c] == '#';
          const bool got = pic.get(x0 + c * scale + dx, y0 + r * scale + dy) == ink;
          CHECK_MESSAGE(want == got, "row ", r, " column ", c);
        }
}

/// Row of the panels' top edge in a picture with `lines` title lines (text scale 2, margin 8).
index_t panel_top(int lines) { return 8 + lines * (7 * 2 + 3 * 2) + (lines ? 6 : 0); }

}  // namespace

TEST_CASE("picture: label colours are distinct for the first 64 labels; nodes share them") {
  std::set<std::tuple<int, int, int>> seen;
  for (int l = 0; l < 64; ++l) {
    const auto c = gio::label_colour(l);
    seen.insert({c.r, c.g, c.b});
    CHECK(gio::node_colour(l) == c);
  }
  CHECK(seen.size() == 64);
  CHECK(gio::label_colour(-1) == gio::picture_outside);
}

TEST_CASE("picture: text puts ink where the glyphs say, at any scale") {
  const gio::rgb ink{255, 255, 255};
  for (int scale : {1, 2, 3}) {
    gio::rgb_image pic(40 * scale, 10 * scale);
    gd::draw_text(pic, 1, 2, "1e0", scale, ink);  // lower case is drawn as capitals
    check_glyph(pic, 1, 2, scale, one_glyph, ink);
    check_glyph(pic, 1 + 6 * scale, 2, scale, e_glyph, ink);
    check_glyph(pic, 1 + 12 * scale, 2, scale, zero_glyph, ink);
    // nothing in the blank column between the glyphs, nor above or below
    for (index_t y = 0; y < pic.height; ++y)
      for (int dx = 0; dx < scale; ++dx) CHECK(pic.get(1 + 5 * scale + dx, y) != ink);
    for (index_t x = 0; x < pic.width; ++x) CHECK(pic.get(x, 1) != ink);
    CHECK(gd::text_width("1e0", scale) == 17 * scale);
  }
  // an unknown character is a question mark, not nothing
  gio::rgb_image q(8, 9), unknown(8, 9);
  gd::draw_text(q, 1, 1, "?", 1, ink);
  gd::draw_text(unknown, 1, 1, "\x7f", 1, ink);
  CHECK(q.pixels == unknown.pixels);
  // a halo surrounds the ink, and only the ink's neighbours
  gio::rgb_image h(12, 12, {9, 9, 9});
  const gio::rgb black{0, 0, 0};
  gd::draw_text(h, 3, 2, "1", 1, ink, &black);
  CHECK(h.get(3 + 2, 2) == ink);
  CHECK(h.get(3 + 2, 1) == black);    // above the top of the 1
  CHECK(h.get(3 + 4, 1) == gio::rgb{9, 9, 9});  // not next to any ink
}

TEST_CASE("picture: word wrap keeps every line within the width") {
  const auto lines = gd::wrap("WEIGHT OF NODE 3 ON THE STEAK, METRIC MIN_STIFFNESS", 100, 2);
  CHECK(lines.size() > 2);
  std::string joined;
  for (const auto& l : lines) {
    CHECK((gd::text_width(l, 2) <= 100 || l.find(' ') == std::string::npos));
    joined += (joined.empty() ? "" : " ") + l;
  }
  CHECK(joined == "WEIGHT OF NODE 3 ON THE STEAK, METRIC MIN_STIFFNESS");
}

TEST_CASE("picture: panels are spacing-true") {
  // 40 x 30 x 10 voxels of 1 x 2 x 3 mm: 40 x 60 x 30 mm
  const geovoronoi::grid<3> g({40, 30, 10}, {1.0, 2.0, 3.0});
  gio::picture_options o;
  const auto L = gd::make_layout(g, o);
  REQUIRE(L.views.size() == 3);
  const auto& xy = L.views[0];
  const auto& xz = L.views[1];
  const auto& zy = L.views[2];
  CHECK(double(xy.w) == doctest::Approx(40 * L.ppu).epsilon(0.02));
  CHECK(double(xy.h) == doctest::Approx(60 * L.ppu).epsilon(0.02));
  CHECK(double(xz.h) == doctest::Approx(30 * L.ppu).epsilon(0.02));
  CHECK(double(zy.w) == doctest::Approx(30 * L.ppu).epsilon(0.02));
  CHECK(xz.w == xy.w);  // XZ below XY shares its x axis
  CHECK(zy.h == xy.h);  // ZY beside XY shares its y axis
  CHECK(L.height == xy.h + 6 + xz.h);
  // drawn: a label that changes at y = 10 (20 mm) and z = 5 (15 mm) shows up at those depths
  geovoronoi::image<label_t, 3> label(g);
  for (index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    label[v] = label_t((c[1] < 10 ? 0 : 1) + (c[2] < 5 ? 0 : 2));
  }
  o.title = {"T"};
  o.slice = {20, 15, 2};
  const auto pic = gio::label_picture(label, {}, static_cast<const geovoronoi::image<float, 3>*>(nullptr), o);
  // the panels' top-left corner in the picture: find the first row of label 0's colour in column 10
  const index_t x = 4 * 2 + 10;
  index_t top = -1, run = 0;
  for (index_t y = 0; y < pic.height && top < 0; ++y)
    if (pic.get(x, y) == gio::label_colour(0)) top = y;
  REQUIRE(top >= 0);
  while (pic.get(x, top + run) == gio::label_colour(0)) ++run;
  // 20 mm of label 0, less the border line drawn on its last row
  CHECK(double(run + 1) == doctest::Approx(20 * L.ppu).epsilon(0.05));
}

TEST_CASE("picture: a 2D grid, a single-slice volume and xy_only give one panel") {
  gio::picture_options o;
  CHECK(gd::make_layout(geovoronoi::grid<2>({8, 4}), o).views.size() == 1);
  CHECK(gd::make_layout(geovoronoi::grid<3>({8, 4, 1}), o).views.size() == 1);
  o.xy_only = true;
  CHECK(gd::make_layout(geovoronoi::grid<3>({8, 4, 6}), o).views.size() == 1);
  // tiny grids are drawn at most 40 pixels per voxel
  const auto L = gd::make_layout(geovoronoi::grid<2>({8, 4}), o);
  CHECK(L.width == 8 * 40);
  CHECK(L.height == 4 * 40);
}

TEST_CASE("picture: the robust range clips outliers and says so") {
  const geovoronoi::grid<2> g({100, 10});
  geovoronoi::image<float, 2> x(g);
  for (index_t v = 0; v < g.size(); ++v) x[v] = float(v);  // 0 .. 999
  for (index_t v : {3, 500, 777}) x[v] = 1e9f;             // three outliers
  x[10] = std::numeric_limits<float>::infinity();         // not finite: ignored
  const auto r = gio::robust_range(x, 1.0, 99.0);
  CHECK(r.data_hi == 1e9);
  CHECK(r.data_lo == 0.0);
  CHECK(r.hi < 1000.0);
  CHECK(r.hi > 980.0);
  CHECK(r.lo > 5.0);
  CHECK(r.lo < 15.0);
  CHECK(r.clipped_hi());
  CHECK(r.clipped_lo());
  const auto full = gio::robust_range(x, 0.0, 100.0);
  CHECK(full.lo == 0.0);
  CHECK(full.hi == 1e9);
  CHECK_FALSE(full.clipped_hi());
  CHECK_THROWS_AS(gio::robust_range(x, 50.0, 10.0), std::invalid_argument);
  // constant data: a range of width one, not a division by zero
  const auto flat = gio::robust_range(geovoronoi::image<float, 2>(g, 2.0f));
  CHECK(flat.hi > flat.lo);
}

TEST_CASE("picture: the colour bar runs from heat(0) at the bottom to heat(1) at the top") {
  const geovoronoi::grid<2> g({60, 40});
  geovoronoi::image<float, 2> x(g);
  for (index_t v = 0; v < g.size(); ++v) x[v] = float(g.coords(v)[0]);
  gio::picture_options o;
  o.title = {"RAMP"};
  const auto r = gio::robust_range(x, 0.0, 100.0);
  const auto pic = gio::heat_picture(x, r, "X (MM)", {}, o, 0);
  const auto L = gd::make_layout(g, o);
  REQUIRE(L.views.size() == 1);
  // the bar is the only place right of the panels with heat(1) under a black frame line
  const auto top_colour = gio::heat_colour(1.0), bottom_colour = gio::heat_colour(0.0);
  index_t bx = -1, by = -1;
  for (index_t y = 1; y < pic.height && bx < 0; ++y)
    for (index_t xx = 8 + L.width; xx < pic.width && bx < 0; ++xx)
      if (pic.get(xx, y) == top_colour && pic.get(xx, y - 1) == gio::rgb{0, 0, 0}) bx = xx, by = y;
  REQUIRE(bx >= 0);
  index_t y = by;
  while (y + 1 < pic.height && pic.get(bx, y + 1) != gio::rgb{0, 0, 0}) ++y;
  CHECK(pic.get(bx, y) == bottom_colour);
  CHECK(y - by + 1 >= 100);
  // in the panel, the left column (x = 0) is heat(0) and the right column heat(1)
  const index_t py = panel_top(2) + L.views[0].cy(20);  // RAMP, then the grid
  CHECK(pic.get(8 + L.views[0].cx(0), py) == bottom_colour);
  CHECK(pic.get(8 + L.views[0].cx(59), py) == top_colour);
}

TEST_CASE("picture: clipped values take the end colour, the rest keep their shades") {
  const geovoronoi::grid<2> g({50, 20});
  geovoronoi::image<float, 2> x(g);
  for (index_t v = 0; v < g.size(); ++v) x[v] = float(g.coords(v)[0]);
  x[g.index({49, 10})] = 1e12f;  // one outlier
  gio::picture_options o;
  const auto L = gd::make_layout(g, o);
  const auto pic = gio::heat_picture(x, gio::robust_range(x, 0.0, 99.0), "X", {}, o, 0);
  const auto& w = L.views[0];
  auto at = [&](index_t i, index_t j) { return pic.get(8 + w.cx(i), panel_top(1) + w.cy(j)); };
  CHECK(at(49, 10) == gio::heat_colour(1.0));
  CHECK(at(25, 10) != gio::heat_colour(1.0));
  CHECK(at(25, 10) == gio::heat_colour(25.0 / 49.0));  // the 99th percentile of 0..49 (and one more) is 49
  // a linear range would have drawn everything but the outlier in heat(0)
  const auto lin = gio::heat_picture(x, gio::robust_range(x, 0.0, 100.0), "X", {}, o, 0);
  CHECK(lin.get(8 + w.cx(25), panel_top(1) + w.cy(10)) == gio::heat_colour(0.0));
}

TEST_CASE("picture: node markers: filled in the slice with the node's colour and numbered, hollow off it") {
  const geovoronoi::grid<3> g({30, 20, 10});
  geovoronoi::image<float, 3> d(g, 1.0f);
  const std::vector<index_t> nodes{g.index({5, 5, 5}), g.index({20, 12, 0})};
  gio::picture_options o;
  const auto L = gd::make_layout(g, o);
  const auto pic = gio::heat_picture(d, gio::robust_range(d), "D", nodes, o, 0);
  const auto& xy = L.views[0];
  const index_t top = panel_top(1);  // one title line: the slices
  // node 0 lies in the XY slice z = 5: its marker's centre has node 0's colour
  const index_t cx0 = 8 + xy.cx(5), cy0 = top + xy.cy(5);
  CHECK(pic.get(cx0, cy0) == gio::node_colour(0));
  // and its number is written right of the marker: white ink there
  const index_t r = gd::marker_radius(o);
  int white = 0;
  for (index_t yy = cy0 - 7; yy <= cy0 + 7; ++yy)
    for (index_t xx = cx0 + r + 3; xx < cx0 + r + 3 + 10; ++xx) white += pic.get(xx, yy) == gio::rgb{255, 255, 255};
  CHECK(white >= 10);
  // node 1 (z = 0) is off the slice: hollow, the heat colour shows through, with a white ring
  const index_t cx1 = 8 + xy.cx(20), cy1 = top + xy.cy(12);
  CHECK(pic.get(cx1, cy1) != gio::node_colour(1));
  CHECK(pic.get(cx1, cy1) == pic.get(8 + xy.cx(25), top + xy.cy(15)));
  CHECK(pic.get(cx1 + r - 2, cy1) == gio::rgb{255, 255, 255});
  // the same node has the same colour in a label picture (its cell) and in a heat picture
  geovoronoi::image<label_t, 3> label(g, 0);
  const auto lp = gio::label_picture(label, nodes, static_cast<const geovoronoi::image<float, 3>*>(nullptr), o);
  CHECK(lp.get(cx0, cy0) == gio::node_colour(0));
  CHECK(lp.get(8 + xy.cx(15), top + xy.cy(15)) == gio::label_colour(0));
}

TEST_CASE("picture: stiff material is hatched and named in the legend") {
  const geovoronoi::grid<2> g({40, 20});
  geovoronoi::image<label_t, 2> label(g, 0);
  geovoronoi::image<float, 2> stiff(g, 1.0f);
  for (index_t j = 0; j < 20; ++j) stiff[g.index({20, j})] = 1e6f, stiff[g.index({21, j})] = 1e6f;
  gio::picture_options o;
  const auto L = gd::make_layout(g, o);
  const auto pic = gio::label_picture(label, {}, &stiff, o);
  std::set<std::tuple<int, int, int>> in_bar;
  const auto& w = L.views[0];
  for (index_t y = panel_top(1) + 2; y < panel_top(1) + L.height - 2; ++y)
    for (index_t x = 8 + w.cx(20) - 2; x <= 8 + w.cx(21) + 2; ++x) {
      const auto c = pic.get(x, y);
      in_bar.insert({c.r, c.g, c.b});
    }
  CHECK(in_bar.size() >= 2);  // two hatch shades
  CHECK(in_bar.count({gio::label_colour(0).r, gio::label_colour(0).g, gio::label_colour(0).b}) == 0);
  // without the stiffness image the same pixels are the cell's colour
  const auto plain = gio::label_picture(label, {}, static_cast<const geovoronoi::image<float, 2>*>(nullptr), o);
  CHECK(plain.get(8 + w.cx(20), panel_top(1) + w.cy(10)) == gio::label_colour(0));
}

TEST_CASE("picture: a cut is drawn between the voxels it separates, marked voxels are outlined") {
  const geovoronoi::grid<2> g({40, 20});
  geovoronoi::image<label_t, 2> label(g, 0);
  gio::picture_options o;
  const auto L = gd::make_layout(g, o);
  const auto& w = L.views[0];
  const index_t row = panel_top(1) + w.cy(10);
  auto columns_of = [&](const gio::rgb_image& pic, gio::rgb c) {
    std::vector<index_t> xs;
    for (index_t x = 8; x < 8 + w.w; ++x)
      if (pic.get(x, row) == c) xs.push_back(x - 8);
    return xs;
  };
  const auto plain = gio::label_picture(label, {}, static_cast<const geovoronoi::image<float, 2>*>(nullptr), o);
  CHECK(columns_of(plain, gio::picture_cut).empty());
  CHECK(columns_of(plain, gio::picture_marked).empty());
  // the cut between columns 19 and 20; columns 30 and up marked
  o.cut_between = [&](index_t u, index_t v) {
    const auto a = g.coords(u)[0], b = g.coords(v)[0];
    return std::min(a, b) == 19 && std::max(a, b) == 20;
  };
  o.marked = [&](index_t v) { return g.coords(v)[0] >= 30; };
  const auto pic = gio::label_picture(label, {}, static_cast<const geovoronoi::image<float, 2>*>(nullptr), o);
  const auto cut = columns_of(pic, gio::picture_cut);
  REQUIRE(!cut.empty());
  for (const index_t x : cut) CHECK((w.a_of(x) == 19 || w.a_of(x) == 20));
  const auto marked = columns_of(pic, gio::picture_marked);
  REQUIRE(!marked.empty());
  for (const index_t x : marked) CHECK(w.a_of(x) >= 30);
  CHECK(std::find_if(marked.begin(), marked.end(), [&](index_t x) { return w.a_of(x) == 30; }) != marked.end());
  CHECK(pic.get(8 + w.cx(35), row) == gio::label_colour(0));  // the inside of the marked region keeps its colour
  CHECK(pic.get(8 + w.cx(10), row) == gio::label_colour(0));
}

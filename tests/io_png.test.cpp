// PNG writer and montages: the file is a PNG of the canvas' size, label colours are distinct, seeds
// and iso-lines are drawn, and write errors name the file.
#include "io_test_util.hpp"

#include <geovoronoi/io/png.hpp>

#include <set>
#include <tuple>

namespace gio = geovoronoi::io;
using geovoronoi::index_t;
using io_test::scratch;

namespace {
std::uint32_t be32(const std::string& s, std::size_t at) {
  return (std::uint32_t(std::uint8_t(s[at])) << 24) | (std::uint32_t(std::uint8_t(s[at + 1])) << 16) |
         (std::uint32_t(std::uint8_t(s[at + 2])) << 8) | std::uint32_t(std::uint8_t(s[at + 3]));
}
}  // namespace

TEST_CASE("png: label colours are distinct for the first 64 labels") {
  std::set<std::tuple<int, int, int>> seen;
  for (int l = 0; l < 64; ++l) {
    const auto c = gio::label_colour(l);
    seen.insert({c.r, c.g, c.b});
  }
  CHECK(seen.size() == 64);
}

TEST_CASE("png: label and distance montages of a 3D diagram") {
  const geovoronoi::grid<3> g({20, 10, 6});
  geovoronoi::image<geovoronoi::label_t, 3> label(g);
  geovoronoi::image<float, 3> dist(g), stiff(g, 1.0f);
  for (index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    label[v] = c[0] < 10 ? 0 : 1;
    dist[v] = float(std::abs(double(c[0]) - (c[0] < 10 ? 3.0 : 15.0)));
    if (c[0] == 10) stiff[v] = 1e6f;
  }
  label[0] = -1;
  dist[0] = std::numeric_limits<float>::infinity();
  const std::vector<index_t> seeds{g.index({3, 5, 3}), g.index({15, 5, 3})};
  const auto pic = gio::label_montage(label, seeds, &stiff);
  // three panels side by side: 20x10, 20x6, 10x6 voxels with the automatic scale
  const index_t scale = 12;  // 400 / 20 = 20, capped at 12 pixels per voxel
  CHECK(pic.width == 6 + (20 + 20 + 10) * scale + 3 * 6);
  CHECK(pic.height == 10 * scale + 12);
  // the XY panel shows label 0's colour left and label 1's right of the stiff wall
  const auto left = pic.get(6 + 1 * scale + 2, 6 + 1 * scale + 2), right = pic.get(6 + 18 * scale + 2, 6 + 1 * scale + 2);
  const auto c0 = gio::label_colour(0), c1 = gio::label_colour(1);
  CHECK((left.r == c0.r && left.g == c0.g && left.b == c0.b));
  CHECK((right.r == c1.r && right.g == c1.g && right.b == c1.b));
  // the seed on the slice is a white square
  const auto s = pic.get(6 + 3 * scale + scale / 2, 6 + 5 * scale + scale / 2);
  CHECK((s.r == 255 && s.g == 255 && s.b == 255));
  gio::write_png(scratch("labels.png"), pic);
  const std::string file = io_test::read_all(scratch("labels.png"));
  REQUIRE(file.size() > 33);
  CHECK(file.substr(1, 3) == "PNG");
  CHECK(be32(file, 16) == std::uint32_t(pic.width));
  CHECK(be32(file, 20) == std::uint32_t(pic.height));

  const auto heat = gio::distance_montage(dist, seeds, 6);
  CHECK(heat.width == pic.width);
  // iso-lines are white pixels somewhere in the XY panel
  int white = 0;
  for (index_t x = 6; x < 6 + 20 * scale; ++x) {
    const auto p = heat.get(x, 6 + 8 * scale);
    white += p.r == 255 && p.g == 255 && p.b == 255;
  }
  CHECK(white > 0);
  geovoronoi::image<float, 3> w(g, 0.5f);
  CHECK(gio::weight_montage(w, seeds[0]).height == pic.height);
  const auto both = gio::hstack(gio::crop(pic, 0, 0, gio::first_panel_width(g, pic), pic.height), pic);
  CHECK(both.width == 6 + 20 * scale + 6 + pic.width);
}

TEST_CASE("png: a 2D grid gives one panel; write errors name the file") {
  const geovoronoi::grid<2> g({8, 4});
  geovoronoi::image<geovoronoi::label_t, 2> label(g, 0);
  const auto pic = gio::label_montage(label, {});
  CHECK(pic.width == 6 + 8 * 12 + 6);
  CHECK_THROWS_AS(gio::write_png(scratch("missing/dir/x.png"), pic), gio::io_error);
  CHECK_THROWS_AS(gio::write_png(scratch("empty.png"), gio::rgb_image()), gio::io_error);
}

// Four fingers one voxel apart, coarsened by 4: a regular coarse grid glues neighbouring fingers (a
// coarse cell spans both sides of a gap), a branching grid keeps them apart (docs/branching.md).
// Writes the two label pictures side by side, painted at the fine resolution, to the PNG named on
// the command line (default branching-fingers.png): docs/images/branching-fingers.png.
#include <geovoronoi.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>

#include <algorithm>
#include <cstdio>
#include <string>
#include <vector>

namespace gv = geovoronoi;
namespace gio = geovoronoi::io;

int main(int argc, char** argv) {
  const std::string path = argc > 1 ? argv[1] : "branching-fingers.png";
  const int factor = 4;
  const auto fine = gv::phantom::fingers(gv::grid<3>({55, 48, 4}), 4, 1);  // fingers 13 wide, gaps x = 13, 27, 41
  // seed 0 at the tip of the first finger, seed 1 in the palm under the last one
  const std::vector<gv::coord<3>> seeds{{6, 47, 1}, {48, 2, 1}};
  std::vector<gv::index_t> nodes;
  for (const auto& s : seeds) nodes.push_back(fine.geometry().index(s));

  // the branching grid, painted on the fine grid
  const auto bg = gv::make_branching_grid(fine, factor, gv::connectivity<26>{});
  const auto p = gv::make_problem(bg, gv::min_stiffness{});
  const auto branching = gv::paint_fine(bg, gv::voronoi(gv::seq, p, seeds));

  // the regular coarse grid of the same cells (a cell is material, of the mean value, where any of its
  // voxels is), its labels painted on the fine material
  const gv::grid<3>& cg = bg.coarse();
  gv::image<float, 3> coarse(cg, 0.0f);
  std::vector<int> n(std::size_t(cg.size()), 0);
  for (gv::index_t v = 0; v < fine.geometry().size(); ++v) {
    if (!(fine[v] > 0)) continue;
    auto c = fine.geometry().coords(v);
    for (int a = 0; a < 3; ++a) c[a] /= factor;
    const auto cell = cg.index(c);
    coarse[cell] += fine[v];
    ++n[std::size_t(cell)];
  }
  for (gv::index_t c = 0; c < cg.size(); ++c)
    if (n[std::size_t(c)]) coarse[c] /= float(n[std::size_t(c)]);
  std::vector<gv::coord<3>> coarse_seeds;
  for (auto s : seeds) {
    for (int a = 0; a < 3; ++a) s[a] /= factor;
    coarse_seeds.push_back(s);
  }
  const auto rc = gv::voronoi(gv::seq, gv::make_problem(cg, coarse, gv::min_stiffness{}, gv::connectivity<26>{}),
                              coarse_seeds);
  gv::image<gv::label_t, 3> regular(fine.geometry(), gv::no_label);
  for (gv::index_t v = 0; v < fine.geometry().size(); ++v) {
    if (!(fine[v] > 0)) continue;
    auto c = fine.geometry().coords(v);
    for (int a = 0; a < 3; ++a) c[a] /= factor;
    regular[v] = rc.label(c);
  }

  gio::picture_options o;
  o.xy_only = true;
  o.legend = false;
  o.slice = {-1, -1, 1};
  o.title = {"REGULAR COARSE GRID, FACTOR 4: GLUED"};
  const auto left = gio::label_picture(regular, nodes, &fine, o);
  o.title = {"BRANCHING GRID, FACTOR 4: FINGERS APART"};
  const auto right = gio::label_picture(branching.label, nodes, &fine, o);
  const gv::index_t gap = 16;
  gio::rgb_image both(left.width + gap + right.width, std::max(left.height, right.height), gio::picture_background);
  for (gv::index_t y = 0; y < left.height; ++y)
    for (gv::index_t x = 0; x < left.width; ++x) both.set(x, y, left.get(x, y));
  for (gv::index_t y = 0; y < right.height; ++y)
    for (gv::index_t x = 0; x < right.width; ++x) both.set(left.width + gap + x, y, right.get(x, y));
  gio::write_png(path, both);
  std::printf("%s: %lld copies, the second finger's tip labelled %d on the regular grid, %d on the branching grid\n",
              path.c_str(), (long long)bg.copies(), int(regular[fine.geometry().index({20, 47, 1})]),
              int(branching.label[fine.geometry().index({20, 47, 1})]));
  return 0;
}

// The smallest useful geovoronoi program: a stiffness volume, three seeds, the geodesic Voronoi
// diagram, and the labels written to a MetaImage file that ParaView, ITK-SNAP or SOFA can open.
//
//   g++ -std=c++17 -O2 -I<geovoronoi>/include -I/usr/include/eigen3 minimal.cpp -o minimal

#include <geovoronoi.hpp>
#include <geovoronoi/io/metaimage.hpp>

#include <cstdio>

int main() {
  namespace gv = geovoronoi;
  // 64 x 48 x 16 voxels of 0.5 mm; soft material (1) with a stiff wall (1000) across x = 32.
  const gv::grid<3> g({64, 48, 16}, {0.5, 0.5, 0.5});
  gv::image<float, 3> stiffness(g, 1.0f);
  for (gv::index_t z = 0; z < 16; ++z)
    for (gv::index_t y = 0; y < 40; ++y) stiffness({32, y, z}) = 1000.0f;

  const std::vector<gv::coord<3>> seeds{{10, 10, 8}, {50, 10, 8}, {30, 40, 8}};
  const auto d = gv::voronoi(gv::seq, g, stiffness, seeds, gv::min_stiffness{}, gv::connectivity<26>{});

  std::printf("voxel (60, 47, 8) belongs to seed %d at geodesic distance %g\n", d.label({60, 47, 8}),
              double(d.distance({60, 47, 8})));
  gv::io::write_metaimage("minimal_labels.mha", d.label);  // MET_INT, -1 outside the object
  return 0;
}

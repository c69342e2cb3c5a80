// libFuzzer target: the STL (ASCII and binary) and OBJ parsers on the same bytes, and a cut and a
// voxelization (both inside rules, surface voxels and fractions) built from whatever mesh they accept
// on a small grid (the exact predicates must not overflow or crash; the checks throw
// std::invalid_argument, the only exception voxelize documents besides bad_alloc).
#include "fuzz_common.hpp"
#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/obj.hpp>
#include <geovoronoi/io/stl.hpp>
#include <geovoronoi/voxelize.hpp>

#include <stdexcept>

namespace {
void cut_small(const geovoronoi::triangle_mesh& m) {
  if (m.triangles.size() > 64) return;  // keep each run short
  try {
    const geovoronoi::grid<3> g({5, 4, 3}, {1.0, 0.5, 2.0}, {-1.0, 0.0, 0.5});
    (void)geovoronoi::cut_from_mesh(g, geovoronoi::connectivity<26>{}, m);
  } catch (const std::invalid_argument&) {  // vertices far outside the lattice range
  }
  const geovoronoi::grid<3> g({6, 5, 4}, {1.0, 0.5, 2.0}, {-1.0, 0.0, 0.5});
  std::vector<geovoronoi::voxelize_part> parts(1);
  parts[0].mesh = m;
  for (auto rule : {geovoronoi::inside_rule::closed, geovoronoi::inside_rule::winding}) {
    geovoronoi::voxelize_options o;
    o.rule = rule;
    o.surface_inside = rule == geovoronoi::inside_rule::winding;
    o.fraction_samples = 2;
    o.threads = 1;
    try {
      const auto v = geovoronoi::voxelize<float>(parts, g, o);
      for (float f : v.fraction)
        if (!(f >= 0.0f && f <= 1.0f)) __builtin_trap();
    } catch (const std::invalid_argument&) {  // open, flipped, self-intersecting, degenerate, far away
    }
  }
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = fuzz_bytes(data, size);
  try {
    cut_small(geovoronoi::io::parse_stl("input.stl", bytes));
  } catch (const geovoronoi::io::io_error&) {
  }
  try {
    cut_small(geovoronoi::io::parse_obj("input.obj", bytes));
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

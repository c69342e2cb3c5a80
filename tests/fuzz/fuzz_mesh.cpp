// libFuzzer target: the STL (ASCII and binary) and OBJ parsers on the same bytes, and a cut built from
// whatever mesh they accept on a small grid (the exact predicates must not overflow or crash).
#include "fuzz_common.hpp"
#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/obj.hpp>
#include <geovoronoi/io/stl.hpp>

#include <stdexcept>

namespace {
void cut_small(const geovoronoi::triangle_mesh& m) {
  if (m.triangles.size() > 64) return;  // keep each run short
  try {
    const geovoronoi::grid<3> g({5, 4, 3}, {1.0, 0.5, 2.0}, {-1.0, 0.0, 0.5});
    (void)geovoronoi::cut_from_mesh(g, geovoronoi::connectivity<26>{}, m);
  } catch (const std::invalid_argument&) {  // vertices far outside the lattice range
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

// libFuzzer target: the PGM/PPM reader (with a small extrusion).
#include "fuzz_common.hpp"
#include <geovoronoi/io/pnm.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = fuzz_path(".pgm");
  fuzz_write(path, data, size);
  try {
    geovoronoi::io::pnm_options o;
    o.extrude = 2;
    auto v = geovoronoi::io::read_pnm<float>(path, o);
    (void)v;
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

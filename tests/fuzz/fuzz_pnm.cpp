// libFuzzer target: the PGM/PPM parser (with a small extrusion).
#include "fuzz_common.hpp"
#include <geovoronoi/io/pnm.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    geovoronoi::io::pnm_options o;
    o.extrude = 2;
    (void)geovoronoi::io::parse_pnm<float>("input.pgm", fuzz_bytes(data, size), o);
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

// libFuzzer target: the NumPy .npy parser and its mapping to a volume.
#include "fuzz_common.hpp"
#include <geovoronoi/io/npy.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    auto a = geovoronoi::io::parse_npy<float>("input.npy", fuzz_bytes(data, size));
    (void)geovoronoi::io::npy_to_volume<float>("input.npy", std::move(a));
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

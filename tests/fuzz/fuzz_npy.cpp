// libFuzzer target: the NumPy .npy reader.
#include "fuzz_common.hpp"
#include <geovoronoi/io/npy.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string path = fuzz_path(".npy");
  fuzz_write(path, data, size);
  try {
    auto v = geovoronoi::io::read_npy_volume<float>(path);
    (void)v;
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

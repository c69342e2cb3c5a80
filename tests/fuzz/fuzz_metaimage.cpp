// libFuzzer target: the MetaImage header parser and data reader (.mha, data in the same file, and
// .mhd pointing at a fixed raw file holding the same bytes).
#include "fuzz_common.hpp"
#include <geovoronoi/io/metaimage.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::string mha = fuzz_path(".mha");
  static const std::string raw = fuzz_path(".raw");
  fuzz_write(mha, data, size);
  try {
    auto v = geovoronoi::io::read_metaimage<float>(mha);
    (void)v;
  } catch (const geovoronoi::io::io_error&) {
  }
  try {
    auto v = geovoronoi::io::read_metaimage<double>(mha, geovoronoi::io::channel_layout::planar);
    (void)v;
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

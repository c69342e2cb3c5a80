// libFuzzer target: the MetaImage header parser and data reader (.mha, data in the same buffer; a
// header naming another data file makes the reader look for a file that does not exist).
#include "fuzz_common.hpp"
#include <geovoronoi/io/metaimage.hpp>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto bytes = fuzz_bytes(data, size);
  try {
    (void)geovoronoi::io::parse_metaimage<float>("/nonexistent-fuzz-dir/input.mha", bytes);
  } catch (const geovoronoi::io::io_error&) {
  }
  try {
    (void)geovoronoi::io::parse_metaimage<double>("/nonexistent-fuzz-dir/input.mha", bytes,
                                                  geovoronoi::io::channel_layout::planar);
  } catch (const geovoronoi::io::io_error&) {
  }
  return 0;
}

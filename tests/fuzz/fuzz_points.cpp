// libFuzzer target: the tool's seed and points reader (tools/geovoronoi/seed_file.hpp, the CSV rows of
// --seeds and --at) on any bytes, in voxel and world mode, and geovoronoi::printable, which every
// message that echoes input goes through: its output must hold no control byte, C1 control or byte
// outside well-formed UTF-8, and must stay short when cut.
#include "fuzz_common.hpp"
#include "seed_file.hpp"

#include <geovoronoi/error.hpp>

#include <string>

namespace {
/// Whether @p s is printable's promise: no byte below 0x20, no 0x7f, no C1 control, only
/// well-formed UTF-8 (checked by a decoder of its own, not printable's).
bool clean(const std::string& s) {
  for (std::size_t i = 0; i < s.size();) {
    const unsigned b = static_cast<unsigned char>(s[i]);
    if (b < 0x80) {
      if (b < 0x20 || b == 0x7f) return false;
      ++i;
      continue;
    }
    const std::size_t n = b >= 0xf0 ? 4 : b >= 0xe0 ? 3 : b >= 0xc2 ? 2 : 0;
    if (n == 0 || b > 0xf4 || i + n > s.size()) return false;
    unsigned cp = b & (0x7f >> n);
    for (std::size_t k = 1; k < n; ++k) {
      const unsigned c = static_cast<unsigned char>(s[i + k]);
      if ((c & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (c & 0x3f);
    }
    const unsigned least[] = {0, 0, 0x80, 0x800, 0x10000};
    if (cp < least[n] || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) return false;
    if ((cp >= 0x80 && cp <= 0x9f) || cp == 0x2028 || cp == 0x2029) return false;
    i += n;
  }
  return true;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  for (const bool integers : {true, false}) {
    try {
      (void)gvcli::parse_seed_rows("input.csv", text, integers, integers ? "seed file" : "points file");
    } catch (const gvcli::usage_error& e) {
      if (!clean(gvcli::printable(e.what()))) __builtin_trap();
    }
  }
  const std::string cut = geovoronoi::printable(text);
  if (!clean(cut) || cut.size() > 4 * geovoronoi::echo_limit + 40) __builtin_trap();
  if (!clean(geovoronoi::printable(text, std::string::npos))) __builtin_trap();
  return 0;
}

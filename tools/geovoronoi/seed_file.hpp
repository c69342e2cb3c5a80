#pragma once
// The seed file of the geovoronoi tool: CSV rows of voxel indices (or world coordinates). Only the
// file's syntax is checked here; whether a seed is inside the grid, unmasked and unique is the
// library's check (voronoi() throws std::invalid_argument naming the seed, see job.cpp).
#include "errors.hpp"  // require_regular_file
#include "usage_error.hpp"

#include <geovoronoi/error.hpp>
#include <geovoronoi/io/common.hpp>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace gvcli {

/// One seed as read from the CSV file: up to three numbers and the line it came from.
struct seed_row {
  double x[3] = {0, 0, 0};
  int count = 0;
  int line = 0;
};

/// The rows of the seed (or points) file @p text, named @p path in messages (read_seed_rows() without
/// the reading; the fuzzer drives it on any bytes). A usage_error names the line of a bad row.
inline std::vector<seed_row> parse_seed_rows(const std::string& path, const std::string& text, bool integers,
                                             const std::string& what = "seed file") {
  std::vector<seed_row> rows;
  std::size_t pos = text.compare(0, 3, "\xEF\xBB\xBF") == 0 ? 3 : 0;
  int line = 0;
  while (pos < text.size()) {
    auto end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    std::string l = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    if (const auto h = l.find('#'); h != std::string::npos) l.erase(h);
    for (char& c : l)
      if (c == '\t' || c == '\r') c = ' ';
    if (l.find_first_not_of(' ') == std::string::npos) continue;
    seed_row r;
    r.line = line;
    std::size_t p = 0;
    while (true) {
      const auto comma = l.find(',', p);
      std::string field = l.substr(p, comma == std::string::npos ? std::string::npos : comma - p);
      const auto b = field.find_first_not_of(' ');
      const auto e = field.find_last_not_of(' ');
      field = b == std::string::npos ? std::string() : field.substr(b, e - b + 1);
      if (r.count == 3) throw usage_error(path + ":" + std::to_string(line) + ": more than 3 values");
      char* stop = nullptr;
      const double v = std::strtod(field.c_str(), &stop);
      if (field.empty() || *stop != '\0' || !std::isfinite(v))
        throw usage_error(path + ":" + std::to_string(line) + ": '" + geovoronoi::printable(field) + "' is not a number");
      if (integers && (v != std::floor(v) || field.find_first_of(".eE") != std::string::npos))
        throw usage_error(path + ":" + std::to_string(line) + ": '" + geovoronoi::printable(field) +
                          "' is not an integer voxel index (use --world for physical coordinates)");
      r.x[r.count++] = v;
      if (comma == std::string::npos) break;
      p = comma + 1;
    }
    if (r.count < 2) throw usage_error(path + ":" + std::to_string(line) + ": expected i,j,k (3 comma-separated values)");
    rows.push_back(r);
  }
  if (rows.empty()) throw usage_error(path + ": no " + (what == "seed file" ? "seeds" : "points") + " in the file");
  return rows;
}

/// Reads `i,j,k` (or `x,y,z` in world units) per line; `#` starts a comment; blank lines are skipped.
/// Two values are accepted for single-slice volumes (k = 0). A UTF-8 byte-order mark at the start
/// (Excel's "CSV UTF-8") is skipped. A folder, FIFO, socket or device is refused before it is opened.
/// @p what names the file in messages ("seed file", "points file"). The file is read with the
/// library's io::read_file, so the run's io::read_log records it like every other input.
inline std::vector<seed_row> read_seed_rows(const std::string& path, bool integers, const std::string& what = "seed file") {
  require_regular_file(path, ("a " + what).c_str());
  std::error_code ec;
  if (std::filesystem::file_size(path, ec) > (std::uintmax_t(1) << 30) && !ec)
    throw usage_error(path + ": " + what + " larger than 1 GiB");
  std::string text;
  try {
    const auto bytes = geovoronoi::io::read_file(path);
    text.assign(bytes.begin(), bytes.end());
  } catch (const geovoronoi::io::out_of_memory&) {
    throw;
  } catch (const geovoronoi::io::io_error& e) {
    throw usage_error(path + ": cannot read the " + what + ": " + e.problem());
  }
  return parse_seed_rows(path, text, integers, what);
}

}  // namespace gvcli

#pragma once
// The seed file of the geovoronoi tool: CSV rows of voxel indices (or world coordinates). Only the
// file's syntax is checked here; whether a seed is inside the grid, unmasked and unique is the
// library's check (voronoi() throws std::invalid_argument naming the seed, see job.cpp).
#include "errors.hpp"  // require_regular_file
#include "usage_error.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace gvcli {

/// One seed as read from the CSV file: up to three numbers and the line it came from.
struct seed_row {
  double x[3] = {0, 0, 0};
  int count = 0;
  int line = 0;
};

/// Reads `i,j,k` (or `x,y,z` in world units) per line; `#` starts a comment; blank lines are skipped.
/// Two values are accepted for single-slice volumes (k = 0). A UTF-8 byte-order mark at the start
/// (Excel's "CSV UTF-8") is skipped. A folder, FIFO, socket or device is refused before it is opened.
inline std::vector<seed_row> read_seed_rows(const std::string& path, bool integers) {
  require_regular_file(path, "a seed file");
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) throw usage_error(path + ": cannot open the seed file");
  std::string text;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) {
    text.append(buf, n);
    if (text.size() > (std::size_t(1) << 30)) {
      std::fclose(f);
      throw usage_error(path + ": seed file larger than 1 GiB");
    }
  }
  const bool read_error = std::ferror(f) != 0;
  std::fclose(f);
  if (read_error) throw usage_error(path + ": cannot read the seed file");
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
        throw usage_error(path + ":" + std::to_string(line) + ": '" + field + "' is not a number");
      if (integers && (v != std::floor(v) || field.find_first_of(".eE") != std::string::npos))
        throw usage_error(path + ":" + std::to_string(line) + ": '" + field +
                          "' is not an integer voxel index (use --world for physical coordinates)");
      r.x[r.count++] = v;
      if (comma == std::string::npos) break;
      p = comma + 1;
    }
    if (r.count < 2) throw usage_error(path + ":" + std::to_string(line) + ": expected i,j,k (3 comma-separated values)");
    rows.push_back(r);
  }
  if (rows.empty()) throw usage_error(path + ": no seeds in the file");
  return rows;
}

}  // namespace gvcli

// See meshes.hpp.
#include "meshes.hpp"

#include "errors.hpp"

#include <geovoronoi/io/mesh.hpp>
#include <geovoronoi/io/picture.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <utility>

namespace gvcli {

namespace {

/// The whole of @p s as a finite double (strtod's syntax, no surrounding text); false otherwise.
bool parse_number(const std::string& s, double& x) {
  if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
  char* end = nullptr;
  errno = 0;
  x = std::strtod(s.c_str(), &end);
  return *end == '\0' && errno != ERANGE && std::isfinite(x);
}

/// The whole of @p s as an integer (base 10, optional sign); false otherwise.
bool parse_integer(const std::string& s, long long& x) {
  if (s.empty() || std::isspace(static_cast<unsigned char>(s.front()))) return false;
  char* end = nullptr;
  errno = 0;
  x = std::strtoll(s.c_str(), &end, 10);
  return *end == '\0' && errno != ERANGE;
}

/// Splits @p text at its last colon when what follows is a number: (before, after); else nothing.
bool split_number(const std::string& text, std::string& before, std::string& after) {
  const auto c = text.rfind(':');
  if (c == std::string::npos) return false;
  double x;
  if (!parse_number(text.substr(c + 1), x)) return false;
  std::string b = text.substr(0, c), a = text.substr(c + 1);  // (before may be text itself)
  before = std::move(b), after = std::move(a);
  return true;
}

/// @p text as one number or three comma-separated numbers (x,y,z), for @p option.
std::array<std::string, 3> three(const std::string& option, const std::string& text, bool one_allowed) {
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const auto c = text.find(',', start);
    parts.push_back(text.substr(start, c == std::string::npos ? std::string::npos : c - start));
    if (c == std::string::npos) break;
    start = c + 1;
  }
  if (parts.size() == 1 && one_allowed) return {parts[0], parts[0], parts[0]};
  if (parts.size() != 3)
    throw usage_error(option + " takes " + (one_allowed ? "one value or " : "") + "three comma-separated values " +
                      "(x,y,z), got '" + text + "'");
  return {parts[0], parts[1], parts[2]};
}

}  // namespace

mesh_spec parse_mesh_spec(const std::string& text) {
  mesh_spec s;
  std::string rest = text, last, value;
  if (split_number(rest, rest, last)) {
    std::string before;
    if (split_number(rest, before, value)) {  // MESH:VALUE:LABEL
      long long l = 0;
      if (!parse_integer(last, l) || l < 1 || l > std::numeric_limits<gv::label_t>::max())
        throw usage_error("mesh '" + text + "': the label '" + last + "' must be an integer from 1 to " +
                          std::to_string(std::numeric_limits<gv::label_t>::max()));
      s.label = gv::label_t(l);
      rest = before;
    } else {  // MESH:VALUE
      value = last;
    }
    parse_number(value, s.value);
  }
  if (rest.empty()) throw usage_error("mesh '" + text + "': names no file (MESH[:VALUE[:LABEL]])");
  s.path = rest;
  return s;
}

std::set<std::string> mesh_grid_options() { return {"--voxel-size", "--voxels", "--pad"}; }
std::set<std::string> mesh_grid_flags() { return {"--rotate", "--winding"}; }
std::set<std::string> voxelize_only_options() {
  return {"--overlap", "--fraction", "--outside-value", "--format", "--precision"};
}
std::set<std::string> voxelize_only_flags() { return {"--surface-inside"}; }

gv::voxelize_options parse_voxelize_options(const arguments& a) {
  gv::voxelize_options o;
  const bool size = a.has("--voxel-size"), count = a.has("--voxels");
  if (size == count)
    throw usage_error(size ? "give --voxel-size or --voxels, not both"
                           : "meshes need a grid: --voxel-size S (or SX,SY,SZ) or --voxels NX,NY,NZ");
  if (size) {
    const auto t = three("--voxel-size", a.get("--voxel-size"), true);
    for (int k = 0; k < 3; ++k) {
      double x = 0;
      if (!parse_number(t[std::size_t(k)], x) || !(x > 0))
        throw usage_error("--voxel-size: '" + t[std::size_t(k)] + "' is not a positive number");
      o.voxel_size[k] = x;
    }
  } else {
    const auto t = three("--voxels", a.get("--voxels"), false);
    for (int k = 0; k < 3; ++k) {
      long long n = 0;
      if (!parse_integer(t[std::size_t(k)], n) || n < 1 || n > (1LL << 31))
        throw usage_error("--voxels: '" + t[std::size_t(k)] + "' is not a voxel count (an integer from 1 to 2^31)");
      o.voxels[k] = gv::index_t(n);
    }
  }
  o.pad = gv::index_t(a.integer("--pad", 0, 0, 1 << 20));
  o.principal_axes = a.has("--rotate");
  o.rule = a.has("--winding") ? gv::inside_rule::winding : gv::inside_rule::closed;
  const std::string overlap = a.get("--overlap", "last");
  if (overlap == "last") o.overlap = gv::overlap_rule::last_wins;
  else if (overlap == "first") o.overlap = gv::overlap_rule::first_wins;
  else if (overlap == "max") o.overlap = gv::overlap_rule::max_value;
  else if (overlap == "min") o.overlap = gv::overlap_rule::min_value;
  else if (overlap == "error") o.overlap = gv::overlap_rule::error;
  else throw usage_error("--overlap must be last, first, max, min or error, got '" + overlap + "'");
  o.surface_inside = a.has("--surface-inside");
  o.fraction_samples = int(a.integer("--fraction", 0, 0, 64));
  if (a.has("--outside-value") && !parse_number(a.get("--outside-value"), o.outside_value))
    throw usage_error("--outside-value: '" + a.get("--outside-value") + "' is not a finite number");
  return o;
}

std::vector<gv::voxelize_part> read_mesh_parts(const std::vector<mesh_spec>& specs) {
  std::vector<gv::voxelize_part> parts;
  for (const auto& s : specs) {
    std::string ext = std::filesystem::path(s.path).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".stl" && ext != ".obj")
      throw usage_error(s.path + ": a mesh must be a .stl or .obj file, optionally followed by :VALUE or "
                        ":VALUE:LABEL (numbers)");
    require_regular_file(s.path, "a mesh");
    gv::voxelize_part p;
    p.mesh = geovoronoi::io::read_mesh(s.path);
    p.value = s.value;
    p.label = s.label;
    p.name = s.path;
    parts.push_back(std::move(p));
  }
  return parts;
}

template <class T>
gv::voxelization<T> voxelize_parts(const std::vector<gv::voxelize_part>& parts, const gv::voxelize_options& o) {
  try {
    return gv::voxelize<T>(parts, o);
  } catch (const std::invalid_argument& e) {
    throw usage_error(library_message(e));
  }
}

template gv::voxelization<float> voxelize_parts(const std::vector<gv::voxelize_part>&, const gv::voxelize_options&);
template gv::voxelization<double> voxelize_parts(const std::vector<gv::voxelize_part>&, const gv::voxelize_options&);

std::vector<std::size_t> label_counts(const gv::image<gv::label_t, 3>& label) {
  std::vector<std::size_t> n(1, 0);
  for (gv::index_t v = 0; v < label.size(); ++v) {
    const gv::label_t l = label[v];
    if (l < 0) continue;
    if (std::size_t(l) >= n.size()) n.resize(std::size_t(l) + 1, 0);
    ++n[std::size_t(l)];
  }
  return n;
}

std::string voxelize_summary(const std::vector<gv::voxelize_part>& parts, const gv::image<gv::label_t, 3>& label,
                             const gv::voxelize_stats& stats) {
  const auto n = label_counts(label);
  std::string s;
  char buf[256];
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const gv::label_t l = parts[i].label ? parts[i].label : gv::label_t(i + 1);
    const std::size_t c = std::size_t(l) < n.size() ? n[std::size_t(l)] : 0;
    const std::string name = std::filesystem::path(parts[i].name).filename().string();
    std::snprintf(buf, sizeof buf, "%s (label %d): %zu voxels", printable(name.empty() ? "part" : name).c_str(), int(l), c);
    s += (i ? ", " : "") + std::string(buf);
  }
  const auto& g = label.geometry();
  const double voxel = g.spacing(0) * g.spacing(1) * g.spacing(2);
  const double vv = voxel * double(stats.inside_voxels);
  std::snprintf(buf, sizeof buf, "; mesh volume %.6g, voxel volume %.6g", stats.mesh_volume, vv);
  s += buf;
  if (stats.mesh_volume > 0) {
    std::snprintf(buf, sizeof buf, " (%+.2f%%)", 100.0 * (vv - stats.mesh_volume) / stats.mesh_volume);
    s += buf;
  }
  return s;
}

template <class S>
geovoronoi::io::rgb_image mesh_label_picture(const gv::image<gv::label_t, 3>& label, const gv::image<S, 3>* stiffness,
                                             const std::string& title) {
  gv::image<gv::label_t, 3> shown(label.geometry(), -1);
  for (gv::index_t v = 0; v < label.size(); ++v)
    if (label[v] > 0) shown[v] = label[v];
  geovoronoi::io::picture_options o;
  o.title = {title};
  return geovoronoi::io::label_picture(shown, {}, stiffness, o);
}

template geovoronoi::io::rgb_image mesh_label_picture(const gv::image<gv::label_t, 3>&, const gv::image<float, 3>*,
                                                      const std::string&);
template geovoronoi::io::rgb_image mesh_label_picture(const gv::image<gv::label_t, 3>&, const gv::image<double, 3>*,
                                                      const std::string&);

}  // namespace gvcli

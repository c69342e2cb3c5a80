#pragma once
/// @file io/vti.hpp
/// @brief VTK XML ImageData (`.vti`) writer: one grid, several named point-data arrays, for ParaView.
///
/// Voxel centres are the VTK points, so the file's Origin is the grid origin (voxel 0's centre), its
/// WholeExtent is 0..n-1 per axis and its Direction is the grid's direction matrix (row by row, VTK's
/// order; ParaView 5.10+ and VTK 9 apply it). Arrays are written either as raw binary in an appended block
/// (compact, the default) or base64 inline (pure text, survives any transfer). Multi-component arrays
/// are interleaved per voxel, as VTK expects.
///
/// @code
/// geovoronoi::io::vti_writer w(d.geometry());
/// w.add("distance", d.distance);
/// w.add("label", d.label);
/// w.write("voronoi.vti");
/// @endcode

#include <geovoronoi/io/common.hpp>

#include <memory>
#include <sstream>

namespace geovoronoi::io {

/// How vti_writer stores array data.
enum class vti_encoding { appended_raw, inline_base64 };

namespace detail {

inline const char* vtk_type_name(element_type t) {
  switch (t) {
    case element_type::int8: return "Int8";
    case element_type::uint8: return "UInt8";
    case element_type::int16: return "Int16";
    case element_type::uint16: return "UInt16";
    case element_type::int32: return "Int32";
    case element_type::uint32: return "UInt32";
    case element_type::int64: return "Int64";
    case element_type::uint64: return "UInt64";
    case element_type::float32: return "Float32";
    case element_type::float64: return "Float64";
  }
  return "";
}

inline std::string base64(const unsigned char* p, std::size_t n) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  for (std::size_t i = 0; i < n; i += 3) {
    const unsigned a = p[i], b = i + 1 < n ? p[i + 1] : 0u, c = i + 2 < n ? p[i + 2] : 0u;
    const unsigned w = (a << 16) | (b << 8) | c;
    out += abc[(w >> 18) & 63];
    out += abc[(w >> 12) & 63];
    out += i + 1 < n ? abc[(w >> 6) & 63] : '=';
    out += i + 2 < n ? abc[w & 63] : '=';
  }
  return out;
}

}  // namespace detail

/// Collects arrays on one grid and writes them as a VTK XML ImageData file.
template <int Dim>
class vti_writer {
 public:
  explicit vti_writer(const grid<Dim>& g, vti_encoding encoding = vti_encoding::appended_raw)
      : grid_(g), encoding_(encoding) {}

  /// Adds an array of `components` values per voxel, interleaved (values.size() == voxels * components).
  template <class T>
  vti_writer& add(const std::string& name, const T* values, std::size_t count, int components = 1) {
    if (components < 1 || count != std::size_t(grid_.size()) * std::size_t(components))
      throw std::invalid_argument("geovoronoi::io::vti_writer: array '" + name + "' has " + std::to_string(count) +
                                  " values for " + std::to_string(grid_.size()) + " voxels x " +
                                  std::to_string(components) + " components");
    array a;
    a.name = name;
    a.type = element_type_of<T>();
    a.components = components;
    a.bytes.resize(count * sizeof(T));
    if (count) std::memcpy(a.bytes.data(), values, count * sizeof(T));
    arrays_.push_back(std::move(a));
    return *this;
  }

  /// Adds a single-component image on the writer's grid.
  template <class T>
  vti_writer& add(const std::string& name, const image<T, Dim>& img) {
    if (!(img.geometry() == grid_))
      throw std::invalid_argument("geovoronoi::io::vti_writer: array '" + name + "' is on another grid");
    return add(name, img.data(), std::size_t(img.size()), 1);
  }

  /// Adds planar channels (channel c of voxel v at c*voxels + v) as one multi-component array.
  template <class T>
  vti_writer& add_planar(const std::string& name, const std::vector<T>& planar, int components) {
    const std::size_t n = std::size_t(grid_.size());
    if (components < 1 || planar.size() != n * std::size_t(components))
      throw std::invalid_argument("geovoronoi::io::vti_writer: array '" + name + "' has the wrong size");
    const auto inter = detail::reorder_channels(planar, n, std::size_t(components), false);
    return add(name, inter.data(), inter.size(), components);
  }

  /// Writes the file (little-endian, UInt64 block headers). The first array is the active scalar.
  void write(const std::string& path) const {
    std::ostringstream x;
    const bool le = detail::host_is_little_endian();
    x << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"1.0\" byte_order=\""
      << (le ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n";
    std::string extent, origin, spacing, direction;
    for (int a = 0; a < 3; ++a) {
      const index_t n = a < Dim ? grid_.extent(a) : 1;
      extent += (a ? " 0 " : "0 ") + std::to_string(n - 1);
      origin += (a ? " " : "") + detail::format_double(a < Dim ? grid_.origin()[a] : 0.0);
      spacing += (a ? " " : "") + detail::format_double(a < Dim ? grid_.spacing(a) : 1.0);
      // VTK's Direction is the 3 x 3 direction matrix row by row (a 2D grid's, padded with z = identity)
      for (int b = 0; b < 3; ++b)
        direction += (a || b ? " " : "") +
                     detail::format_double(a < Dim && b < Dim ? grid_.direction(a, b) : (a == b ? 1.0 : 0.0));
    }
    x << "  <ImageData WholeExtent=\"" << extent << "\" Origin=\"" << origin << "\" Spacing=\"" << spacing
      << "\" Direction=\"" << direction << "\">\n";
    x << "    <Piece Extent=\"" << extent << "\">\n      <PointData";
    if (!arrays_.empty()) x << " Scalars=\"" << arrays_[0].name << "\"";
    x << ">\n";
    std::uint64_t offset = 0;
    for (const auto& a : arrays_) {
      x << "        <DataArray type=\"" << detail::vtk_type_name(a.type) << "\" Name=\"" << a.name
        << "\" NumberOfComponents=\"" << a.components << "\" format=\""
        << (encoding_ == vti_encoding::appended_raw ? "appended" : "binary") << "\"";
      if (encoding_ == vti_encoding::appended_raw) {
        x << " offset=\"" << offset << "\"/>\n";
        offset += 8 + a.bytes.size();
      } else {
        std::vector<unsigned char> block(8 + a.bytes.size());
        const std::uint64_t n = a.bytes.size();
        std::memcpy(block.data(), &n, 8);
        if (!a.bytes.empty()) std::memcpy(block.data() + 8, a.bytes.data(), a.bytes.size());
        x << ">\n          " << detail::base64(block.data(), block.size()) << "\n        </DataArray>\n";
      }
    }
    x << "      </PointData>\n      <CellData/>\n    </Piece>\n  </ImageData>\n";
    std::string text = x.str();
    std::vector<unsigned char> out(text.begin(), text.end());
    if (encoding_ == vti_encoding::appended_raw) {
      const std::string open = "  <AppendedData encoding=\"raw\">\n   _";
      out.insert(out.end(), open.begin(), open.end());
      for (const auto& a : arrays_) {
        const std::uint64_t n = a.bytes.size();
        const auto* p = reinterpret_cast<const unsigned char*>(&n);
        out.insert(out.end(), p, p + 8);
        out.insert(out.end(), a.bytes.begin(), a.bytes.end());
      }
      const std::string close = "\n  </AppendedData>\n";
      out.insert(out.end(), close.begin(), close.end());
    }
    const std::string end = "</VTKFile>\n";
    out.insert(out.end(), end.begin(), end.end());
    detail::write_file(path, out.data(), out.size());
  }

 private:
  struct array {
    std::string name;
    element_type type;
    int components;
    std::vector<unsigned char> bytes;
  };
  grid<Dim> grid_;
  vti_encoding encoding_;
  std::vector<array> arrays_;
};

}  // namespace geovoronoi::io

#pragma once
/// @file io/npy.hpp
/// @brief NumPy `.npy` arrays (format versions 1.0, 2.0 and 3.0), read and write; uncompressed `.npz`
///        archives of them, write.
///
/// Axis order: a C-ordered numpy array of shape (nz, ny, nx) — index [z, y, x] — has its last index
/// fastest in memory, which is exactly geovoronoi's x-fastest layout v = x + nx*(y + ny*z). So
/// `np.load("f.npy")[z, y, x]` is voxel (x, y, z), a 2D array [y, x] is a 2D grid, and the writers
/// here produce shape (nz, ny, nx). A Fortran-ordered array (fortran_order True) of shape
/// (nx, ny, nz) has the same memory order and is read as such. Element types: b1, i1/u1 ... i8/u8,
/// f4, f8, in either byte order.
///
/// @code
/// auto field = geovoronoi::io::read_npy_image<float, 3>("stiffness.npy");   // numpy shape (nz, ny, nx)
/// geovoronoi::io::write_npy("labels.npy", diagram.label);                    // int32, shape (nz, ny, nx)
/// @endcode

#include <geovoronoi/io/common.hpp>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdlib>

namespace geovoronoi::io {

/// A NumPy array: its shape (numpy's order), memory order and values converted to T.
template <class T>
struct npy_array {
  std::vector<index_t> shape;
  bool fortran_order = false;
  element_type stored = element_type_of<T>();
  std::vector<T> data;  ///< in the file's memory order
};

namespace detail {

inline const char* npy_descr(element_type t) {
  switch (t) {
    case element_type::int8: return "|i1";
    case element_type::uint8: return "|u1";
    case element_type::int16: return "<i2";
    case element_type::uint16: return "<u2";
    case element_type::int32: return "<i4";
    case element_type::uint32: return "<u4";
    case element_type::int64: return "<i8";
    case element_type::uint64: return "<u8";
    case element_type::float32: return "<f4";
    case element_type::float64: return "<f8";
  }
  return "";
}

/// The value text after `'key':` in a numpy header dict, or empty when absent.
inline std::string npy_field(const std::string& dict, const std::string& key) {
  for (const char q : {'\'', '"'}) {
    const std::string k = std::string(1, q) + key + std::string(1, q);
    const auto p = dict.find(k);
    if (p == std::string::npos) continue;
    auto c = dict.find(':', p + k.size());
    if (c == std::string::npos) return {};
    ++c;
    while (c < dict.size() && dict[c] == ' ') ++c;
    if (c < dict.size() && dict[c] == '(') {
      const auto e = dict.find(')', c);
      return e == std::string::npos ? std::string() : dict.substr(c, e - c + 1);
    }
    auto e = c;
    if (c < dict.size() && (dict[c] == '\'' || dict[c] == '"')) {
      e = dict.find(dict[c], c + 1);
      return e == std::string::npos ? std::string() : dict.substr(c, e - c + 1);
    }
    while (e < dict.size() && dict[e] != ',' && dict[e] != '}') ++e;
    return dict.substr(c, e - c);
  }
  return {};
}

}  // namespace detail

/**
 * @brief Parses the bytes of a .npy file (named @p path in messages).
 * @throws io_error naming the file and the problem for a bad magic, header, type, shape, or a file
 *         shorter or longer than the shape implies.
 */
template <class T>
npy_array<T> parse_npy(const std::string& path, const std::vector<unsigned char>& bytes) {
  if (bytes.size() < 10 || bytes[0] != 0x93 || std::memcmp(bytes.data() + 1, "NUMPY", 5) != 0)
    throw io_error(path, "not a NumPy .npy file (bad magic)");
  const int major = bytes[6];
  std::size_t header_len, header_start;
  if (major == 1) {
    header_len = std::size_t(bytes[8]) | (std::size_t(bytes[9]) << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (bytes.size() < 12) throw io_error(path, "truncated .npy header");
    header_len = std::size_t(bytes[8]) | (std::size_t(bytes[9]) << 8) | (std::size_t(bytes[10]) << 16) |
                 (std::size_t(bytes[11]) << 24);
    header_start = 12;
  } else {
    throw io_error(path, ".npy format version " + std::to_string(major) + " is not supported");
  }
  if (header_len > bytes.size() - header_start) throw io_error(path, "the .npy header runs past the end of the file");
  const std::string dict(reinterpret_cast<const char*>(bytes.data()) + header_start, header_len);
  if (dict.find('{') == std::string::npos || dict.find('}') == std::string::npos)
    throw io_error(path, "the .npy header is not a dict");

  std::string descr = detail::npy_field(dict, "descr");
  if (descr.size() < 2) throw io_error(path, "the .npy header has no 'descr'");
  descr = descr.substr(1, descr.size() - 2);
  if (descr.size() < 3) throw io_error(path, "unsupported dtype '" + geovoronoi::printable(descr) + "'");
  const char order = descr[0], kind = descr[1];
  const std::string size_text = descr.substr(2);
  if (size_text.size() != 1 || size_text[0] < '1' || size_text[0] > '8')
    throw io_error(path, "unsupported dtype '" + geovoronoi::printable(descr) + "'");
  const int size = size_text[0] - '0';
  element_type type;
  if ((kind == 'i' || kind == 'u' || kind == 'b') && (size == 1 || size == 2 || size == 4 || size == 8)) {
    const bool is_signed = kind == 'i';
    type = size == 1 ? (is_signed ? element_type::int8 : element_type::uint8)
         : size == 2 ? (is_signed ? element_type::int16 : element_type::uint16)
         : size == 4 ? (is_signed ? element_type::int32 : element_type::uint32)
                     : (is_signed ? element_type::int64 : element_type::uint64);
    if (kind == 'b' && size != 1) throw io_error(path, "unsupported dtype '" + geovoronoi::printable(descr) + "'");
  } else if (kind == 'f' && (size == 4 || size == 8)) {
    type = size == 4 ? element_type::float32 : element_type::float64;
  } else {
    throw io_error(path, "unsupported dtype '" + geovoronoi::printable(descr) + "' (integers, bool, float32 and float64 only)");
  }
  if (order != '<' && order != '>' && order != '|' && order != '=')
    throw io_error(path, "unsupported byte order in dtype '" + geovoronoi::printable(descr) + "'");
  const bool swap = size > 1 && ((order == '>') == detail::host_is_little_endian()) && order != '|' && order != '=';

  // exactly True or False, as NumPy's own reader requires (a Python literal that is a bool)
  std::string fo = detail::npy_field(dict, "fortran_order");
  while (!fo.empty() && (fo.back() == ' ' || fo.back() == '\t')) fo.pop_back();
  npy_array<T> a;
  if (fo == "True") a.fortran_order = true;
  else if (fo != "False")
    throw io_error(path, "the .npy header has no valid 'fortran_order' (" +
                             (fo.empty() ? std::string("none") : "'" + geovoronoi::printable(fo) + "'") +
                             "; it must be True or False)");

  const std::string shape = detail::npy_field(dict, "shape");
  if (shape.size() < 2 || shape.front() != '(' || shape.back() != ')') throw io_error(path, "the .npy header has no valid 'shape'");
  std::uint64_t count = 1;
  {
    std::string inner = shape.substr(1, shape.size() - 2);
    std::size_t p = 0;
    while (p < inner.size()) {
      while (p < inner.size() && (inner[p] == ' ' || inner[p] == ',')) ++p;
      if (p >= inner.size()) break;
      std::size_t e = p;
      while (e < inner.size() && inner[e] != ',' && inner[e] != ' ') ++e;
      const std::string w = inner.substr(p, e - p);
      char* end = nullptr;
      const long long n = std::strtoll(w.c_str(), &end, 10);
      if (end == w.c_str() || *end != '\0' || n < 0) throw io_error(path, "bad dimension '" + geovoronoi::printable(w) + "' in the .npy shape");
      if (!detail::checked_mul(count, std::uint64_t(n), count, detail::max_voxels))
        throw io_error(path, "the .npy shape implies more than 2^40 elements");
      a.shape.push_back(index_t(n));
      if (a.shape.size() > 32) throw io_error(path, "the .npy shape has more than 32 dimensions");
      p = e;
    }
  }
  const std::size_t data_start = header_start + header_len;
  const std::uint64_t need = count * std::uint64_t(size);
  const std::size_t have = bytes.size() - data_start;
  if (need > have)
    throw io_error(path, "the shape implies " + std::to_string(need) + " bytes of data but the file holds " +
                             std::to_string(have) + " (truncated?)");
  if (need < have)
    throw io_error(path, "the file holds " + std::to_string(have - need) + " bytes more than the shape implies");
  a.stored = type;
  std::vector<unsigned char> raw(bytes.begin() + std::ptrdiff_t(data_start), bytes.end());
  if (swap) detail::byte_swap(raw.data(), std::size_t(count), std::size_t(size));
  detail::resize_or_throw(a.data, std::size_t(count), path, "the array");
  detail::convert(path, type, raw.data(), std::size_t(count), a.data.data());
  if (kind == 'b')
    for (auto& x : a.data) x = x != T(0) ? T(1) : T(0);
  return a;
}

/// Reads a .npy file (see parse_npy()).
template <class T>
npy_array<T> read_npy(const std::string& path) {
  return parse_npy<T>(path, read_file(path));
}

/// The bytes of a C-ordered .npy file holding `count` values of the given numpy shape, element type
/// `type` (what write_npy() writes and write_npz() stores).
template <class T>
std::vector<unsigned char> npy_bytes(const std::string& path, const T* data, const std::vector<index_t>& shape,
                                     element_type type = element_type_of<T>()) {
  std::uint64_t count = 1;
  for (auto n : shape) {
    if (n < 0) throw io_error(path, "negative dimension in the .npy shape");
    count *= std::uint64_t(n);
  }
  std::string dict = std::string("{'descr': '") + detail::npy_descr(type) + "', 'fortran_order': False, 'shape': (";
  for (std::size_t i = 0; i < shape.size(); ++i) dict += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) dict += ",";
  dict += "), }";
  // pad with spaces so that the data start on a 64-byte boundary, header ends with '\n'
  std::size_t total = 10 + dict.size() + 1;
  const std::size_t padded = (total + 63) / 64 * 64;
  dict.append(padded - total, ' ');
  dict += '\n';
  if (dict.size() > 65535) throw io_error(path, "the .npy header is too long");
  std::vector<unsigned char> out;
  out.reserve(10 + dict.size() + count * element_size(type));
  const unsigned char magic[] = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0};
  out.insert(out.end(), magic, magic + 8);
  out.push_back(static_cast<unsigned char>(dict.size() & 0xff));
  out.push_back(static_cast<unsigned char>(dict.size() >> 8));
  out.insert(out.end(), dict.begin(), dict.end());
  const std::size_t off = out.size();
  out.resize(off + std::size_t(count) * element_size(type));
  detail::convert_back(path, type, data, std::size_t(count), out.data() + off);
  if (!detail::host_is_little_endian()) detail::byte_swap(out.data() + off, std::size_t(count), element_size(type));
  return out;
}

/// Writes `count` values as a C-ordered .npy array of the given numpy shape, element type `type`.
template <class T>
void write_npy(const std::string& path, const T* data, const std::vector<index_t>& shape,
               element_type type = element_type_of<T>()) {
  const auto out = npy_bytes(path, data, shape, type);
  detail::write_file(path, out.data(), out.size());
}

/// The arrays of an .npz file, in the order they are stored: each a name (without ".npy") and the
/// bytes of its .npy file (npy_bytes()).
class npz_entries {
 public:
  /// Adds @p values as array @p name of numpy shape @p shape.
  template <class T>
  npz_entries& add(const std::string& name, const T* values, const std::vector<index_t>& shape) {
    entries_.push_back({name, npy_bytes(name + ".npy", values, shape)});
    return *this;
  }
  /// Adds a 1D array.
  template <class T>
  npz_entries& add(const std::string& name, const std::vector<T>& values) {
    return add(name, values.data(), {index_t(values.size())});
  }
  /// Adds an image, of shape (nz, ny, nx) (3D) or (ny, nx) (2D).
  template <class T, int Dim>
  npz_entries& add(const std::string& name, const image<T, Dim>& img) {
    std::vector<index_t> shape;
    for (int a = Dim - 1; a >= 0; --a) shape.push_back(img.geometry().extent(a));
    return add(name, img.data(), shape);
  }
  struct entry {
    std::string name;
    std::vector<unsigned char> bytes;
  };
  const std::vector<entry>& entries() const noexcept { return entries_; }

 private:
  std::vector<entry> entries_;
};

namespace detail {
/// CRC-32 (ISO 3309, the ZIP checksum) of @p n bytes.
inline std::uint32_t crc32(const unsigned char* p, std::size_t n) noexcept {
  static const auto table = [] {
    std::array<std::uint32_t, 256> t{};
    for (std::uint32_t i = 0; i < 256; ++i) {
      std::uint32_t c = i;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[i] = c;
    }
    return t;
  }();
  std::uint32_t c = 0xFFFFFFFFu;
  for (std::size_t i = 0; i < n; ++i) c = table[(c ^ p[i]) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}
inline void put_le(std::vector<unsigned char>& out, std::uint64_t x, int bytes) {
  for (int i = 0; i < bytes; ++i) out.push_back(static_cast<unsigned char>((x >> (8 * i)) & 0xFFu));
}
}  // namespace detail

/// Writes an uncompressed .npz (numpy.load's format: a ZIP archive of "<name>.npy" members, stored
/// without compression, dated 1980-01-01 so that equal arrays give equal bytes). The archive and each
/// member must stay under 4 GiB and 65,535 members (no ZIP64): an io_error otherwise.
inline void write_npz(const std::string& path, const npz_entries& arrays) {
  const auto& es = arrays.entries();
  if (es.size() >= 0xFFFFu) throw io_error(path, "too many arrays for an .npz without ZIP64");
  std::vector<unsigned char> out, central;
  const std::uint32_t dos_time = 0, dos_date = (0u << 9) | (1u << 5) | 1u;  // 1980-01-01 00:00
  for (const auto& e : es) {
    const std::string name = e.name + ".npy";
    if (e.bytes.size() >= 0xFFFFFFFFull || out.size() + e.bytes.size() + 30 + name.size() >= 0xFFFFFFFFull)
      throw io_error(path, "the array '" + e.name + "' makes the .npz too large (4 GiB) for a ZIP without ZIP64");
    const std::uint32_t crc = detail::crc32(e.bytes.data(), e.bytes.size());
    const std::uint64_t offset = out.size(), size = e.bytes.size();
    // local file header
    detail::put_le(out, 0x04034b50u, 4);
    detail::put_le(out, 20, 2);  // version needed: 2.0
    detail::put_le(out, 0, 2);   // flags
    detail::put_le(out, 0, 2);   // stored
    detail::put_le(out, dos_time, 2);
    detail::put_le(out, dos_date, 2);
    detail::put_le(out, crc, 4);
    detail::put_le(out, size, 4);
    detail::put_le(out, size, 4);
    detail::put_le(out, name.size(), 2);
    detail::put_le(out, 0, 2);
    out.insert(out.end(), name.begin(), name.end());
    out.insert(out.end(), e.bytes.begin(), e.bytes.end());
    // its central directory record
    detail::put_le(central, 0x02014b50u, 4);
    detail::put_le(central, 20, 2);  // made by: MS-DOS, 2.0
    detail::put_le(central, 20, 2);
    detail::put_le(central, 0, 2);
    detail::put_le(central, 0, 2);
    detail::put_le(central, dos_time, 2);
    detail::put_le(central, dos_date, 2);
    detail::put_le(central, crc, 4);
    detail::put_le(central, size, 4);
    detail::put_le(central, size, 4);
    detail::put_le(central, name.size(), 2);
    detail::put_le(central, 0, 2);  // extra
    detail::put_le(central, 0, 2);  // comment
    detail::put_le(central, 0, 2);  // disk
    detail::put_le(central, 0, 2);  // internal attributes
    detail::put_le(central, 0, 4);  // external attributes
    detail::put_le(central, offset, 4);
    central.insert(central.end(), name.begin(), name.end());
  }
  if (out.size() + central.size() >= 0xFFFFFFFFull) throw io_error(path, "the .npz is too large (4 GiB) for a ZIP without ZIP64");
  const std::uint64_t cd_offset = out.size(), cd_size = central.size();
  out.insert(out.end(), central.begin(), central.end());
  detail::put_le(out, 0x06054b50u, 4);
  detail::put_le(out, 0, 2);
  detail::put_le(out, 0, 2);
  detail::put_le(out, es.size(), 2);
  detail::put_le(out, es.size(), 2);
  detail::put_le(out, cd_size, 4);
  detail::put_le(out, cd_offset, 4);
  detail::put_le(out, 0, 2);
  detail::write_file(path, out.data(), out.size());
}

/// Writes a 1D array.
template <class T>
void write_npy(const std::string& path, const std::vector<T>& values) {
  write_npy(path, values.data(), {index_t(values.size())});
}

/// Writes an image as a C-ordered array of shape (nz, ny, nx) (3D) or (ny, nx) (2D).
template <class T, int Dim>
void write_npy(const std::string& path, const image<T, Dim>& img) {
  std::vector<index_t> shape;
  for (int a = Dim - 1; a >= 0; --a) shape.push_back(img.geometry().extent(a));
  write_npy(path, img.data(), shape);
}

/// Reads a .npy array as a volume: 1D (nx), 2D (ny, nx) or 3D (nz, ny, nx) in C order, the reverse
/// shapes in Fortran order; spacing 1, origin 0 (NumPy files carry no geometry).
template <class T>
volume<T> npy_to_volume(const std::string& path, npy_array<T> a) {
  if (a.shape.empty() || a.shape.size() > 3)
    throw io_error(path, "a volume needs a 1D, 2D or 3D array, this one has " + std::to_string(a.shape.size()) + " dimensions");
  volume<T> v;
  v.dims = int(a.shape.size());
  for (std::size_t i = 0; i < a.shape.size(); ++i) {
    if (a.shape[i] == 0) throw io_error(path, "the array has an empty dimension");
    const std::size_t axis = a.fortran_order ? i : a.shape.size() - 1 - i;
    v.extents[axis] = a.shape[i];
  }
  v.stored = a.stored;
  v.data = std::move(a.data);
  return v;
}

/// Reads a .npy file as a volume (see npy_to_volume()).
template <class T>
volume<T> read_npy_volume(const std::string& path) {
  return npy_to_volume<T>(path, read_npy<T>(path));
}

/// Reads a .npy array as an image (spacing 1, origin 0).
template <class T, int Dim = 3>
image<T, Dim> read_npy_image(const std::string& path) {
  const auto v = read_npy_volume<T>(path);
  try {
    return v.template channel<Dim>(0);
  } catch (const std::invalid_argument& e) {
    throw io_error(path, e.what());
  }
}

}  // namespace geovoronoi::io

#pragma once
/// @file io/metaimage.hpp
/// @brief MetaImage volumes: `.mhd` header + separate raw file, and `.mha` with the data in the same
///        file (`ElementDataFile = LOCAL`).
///
/// Reads every MET_* scalar type (MET_CHAR ... MET_DOUBLE, MET_LONG as 4 bytes like MetaIO,
/// MET_LONG_LONG / MET_ULONG_LONG as 8, the `_ARRAY` spellings) and converts it to the requested T;
/// honours HeaderSize (including -1: the data are the last bytes of the file), ElementSpacing (or
/// ElementSize, `spacing`, `scale3d`), Offset / Position / Origin / `translation`, Orientation /
/// TransformMatrix / Rotation, ElementByteOrderMSB / BinaryDataByteOrderMSB, ElementNumberOfChannels,
/// NDims up to 4 (a 4th dimension is read as planar channels) and CompressedData = True (zlib or gzip
/// stream). Compressed data need zlib: define GEOVORONOI_WITH_ZLIB=1 and link zlib (the CMake target
/// geovoronoi::geovoronoi does both when zlib was found at configure time, see docs/io.md); without
/// it such files throw a clear io_error.
///
/// Several channels per voxel are stored interleaved by ITK and VTK, planar (one whole volume per
/// channel) by SOFA; the header does not say which, so the caller chooses with channel_layout.
///
/// @code
/// auto v = geovoronoi::io::read_metaimage<float>("stiffness.mhd");
/// geovoronoi::image<float, 3> field = v.channel<3>(0);
/// geovoronoi::io::write_metaimage("copy.mha", field);
/// @endcode

#include <geovoronoi/io/common.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

#if defined(GEOVORONOI_WITH_ZLIB) && GEOVORONOI_WITH_ZLIB
#if __has_include(<zlib.h>)
#include <zlib.h>
#define GEOVORONOI_IO_HAVE_ZLIB 1
#endif
#endif
#ifndef GEOVORONOI_IO_HAVE_ZLIB
#define GEOVORONOI_IO_HAVE_ZLIB 0
#endif

namespace geovoronoi::io {

/// True when this build can read and write CompressedData = True.
inline constexpr bool metaimage_has_zlib = GEOVORONOI_IO_HAVE_ZLIB != 0;

/// Options of write_metaimage().
struct metaimage_write_options {
  /// Element type written to the file; default: the volume's `stored` type.
  std::optional<element_type> type;
  /// Layout of several channels in the file (ITK/VTK: interleaved; SOFA: planar).
  channel_layout layout = channel_layout::interleaved;
  /// Compress with zlib (CompressedData = True); needs GEOVORONOI_WITH_ZLIB.
  bool compress = false;
  /// Write big-endian data (ElementByteOrderMSB = True).
  bool msb = false;
};

/// The header of a MetaImage file, as parsed (no data).
struct metaimage_header {
  int ndims = 0;
  std::array<index_t, 4> dim_size{1, 1, 1, 1};
  std::array<double, 3> spacing{1.0, 1.0, 1.0};
  std::array<double, 3> origin{0.0, 0.0, 0.0};
  std::array<double, 9> orientation{1, 0, 0, 0, 1, 0, 0, 0, 1};
  int channels = 1;
  element_type type = element_type::uint8;
  bool msb = false;
  bool compressed = false;
  std::int64_t compressed_size = -1;
  std::int64_t header_size = 0;
  std::string data_file;         ///< "LOCAL" or a path relative to the header
  std::size_t data_start = 0;    ///< byte offset just after the ElementDataFile line
};

namespace detail {

inline const char* met_name(element_type t) {
  switch (t) {
    case element_type::int8: return "MET_CHAR";
    case element_type::uint8: return "MET_UCHAR";
    case element_type::int16: return "MET_SHORT";
    case element_type::uint16: return "MET_USHORT";
    case element_type::int32: return "MET_INT";
    case element_type::uint32: return "MET_UINT";
    case element_type::int64: return "MET_LONG_LONG";
    case element_type::uint64: return "MET_ULONG_LONG";
    case element_type::float32: return "MET_FLOAT";
    case element_type::float64: return "MET_DOUBLE";
  }
  return "MET_NONE";
}

inline bool parse_met_type(std::string s, element_type& t) {
  s = lower(s);
  const std::string suffix = "_array";
  if (s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0)
    s.erase(s.size() - suffix.size());
  struct entry { const char* name; element_type type; };
  static const entry table[] = {
      {"met_char", element_type::int8},        {"met_ascii_char", element_type::int8},
      {"met_uchar", element_type::uint8},      {"met_short", element_type::int16},
      {"met_ushort", element_type::uint16},    {"met_int", element_type::int32},
      {"met_uint", element_type::uint32},      {"met_long", element_type::int32},
      {"met_ulong", element_type::uint32},     {"met_long_long", element_type::int64},
      {"met_ulong_long", element_type::uint64}, {"met_float", element_type::float32},
      {"met_double", element_type::float64}};
  for (const auto& e : table)
    if (s == e.name) { t = e.type; return true; }
  return false;
}

inline std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

inline std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  std::string w;
  while (in >> w) out.push_back(w);
  return out;
}

inline double parse_real(const std::string& file, const std::string& key, const std::string& w) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(w.c_str(), &end);
  if (end == w.c_str() || *end != '\0' || errno == ERANGE || !std::isfinite(x))
    throw io_error(file, key + " value '" + geovoronoi::printable(w) + "' is not a finite number");
  return x;
}

inline std::int64_t parse_int(const std::string& file, const std::string& key, const std::string& w) {
  errno = 0;
  char* end = nullptr;
  const long long x = std::strtoll(w.c_str(), &end, 10);
  if (end == w.c_str() || *end != '\0' || errno == ERANGE)
    throw io_error(file, key + " value '" + geovoronoi::printable(w) + "' is not an integer");
  return static_cast<std::int64_t>(x);
}

inline bool parse_bool(const std::string& file, const std::string& key, const std::string& w) {
  const std::string s = lower(w);
  if (s == "true" || s == "1" || s == "yes") return true;
  if (s == "false" || s == "0" || s == "no") return false;
  throw io_error(file, key + " value '" + geovoronoi::printable(w) + "' is not True or False");
}

inline std::vector<double> parse_reals(const std::string& file, const std::string& key, const std::string& v,
                                       std::size_t min_count, std::size_t max_count) {
  const auto ws = words(v);
  if (ws.size() < min_count || ws.size() > max_count)
    throw io_error(file, key + " has " + std::to_string(ws.size()) + " values, expected " +
                             (min_count == max_count ? std::to_string(min_count)
                                                     : std::to_string(min_count) + " to " + std::to_string(max_count)));
  std::vector<double> out;
  for (const auto& w : ws) out.push_back(parse_real(file, key, w));
  return out;
}

/// Parses the header at the start of `bytes` (the whole file for .mhd, the start of a .mha).
inline metaimage_header parse_metaimage_header(const std::string& file, const std::vector<unsigned char>& bytes) {
  using geovoronoi::detail::direction_problem;
  metaimage_header h;
  std::size_t pos = 0;
  int line_no = 0;
  bool have_data_file = false, have_dims = false, have_type = false;
  std::vector<std::string> dim_words;
  std::string spacing_value, element_size_value, origin_value, orientation_value;
  constexpr std::size_t max_header = std::size_t(1) << 20;
  // Lines end as the first one does: LF or CR LF (split at LF; trim() drops the CR), or CR alone (classic
  // Mac OS). The data of a LOCAL file start right after the ElementDataFile line's end, so a LF after a
  // CR-only line's CR is data.
  char eol = 0;
  while (pos < bytes.size() && !have_data_file) {
    if (pos > max_header) throw io_error(file, "no ElementDataFile line in the first MiB: not a MetaImage header");
    std::size_t end = pos;
    if (eol == 0) {
      while (end < bytes.size() && bytes[end] != '\n' && bytes[end] != '\r') ++end;
      if (end < bytes.size()) eol = bytes[end] == '\r' && (end + 1 >= bytes.size() || bytes[end + 1] != '\n') ? '\r' : '\n';
      if (eol == '\n') end = pos;
    }
    const char stop = eol == '\r' ? '\r' : '\n';
    while (end < bytes.size() && bytes[end] != stop) ++end;
    std::string line(reinterpret_cast<const char*>(bytes.data()) + pos, end - pos);
    pos = end < bytes.size() ? end + 1 : end;
    ++line_no;
    for (char ch : line)
      if (ch == '\0') throw io_error(file, "binary data in the header at line " + std::to_string(line_no) +
                                               " (missing ElementDataFile line?)");
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const auto eq = line.find('=');
    if (eq == std::string::npos)
      throw io_error(file, "header line " + std::to_string(line_no) + " is not 'Key = Value': '" +
                               geovoronoi::printable(line) + "'");
    const std::string key = trim(line.substr(0, eq));
    const std::string value = trim(line.substr(eq + 1));
    const std::string k = lower(key);
    if (k == "ndims") {
      const auto n = parse_int(file, key, value);
      if (n < 1 || n > 4) throw io_error(file, "NDims = " + geovoronoi::printable(value) + " is not supported (1 to 4)");
      h.ndims = int(n);
    } else if (k == "dimsize") {
      dim_words = words(value);
      have_dims = true;
    } else if (k == "elementtype") {
      if (!parse_met_type(value, h.type)) throw io_error(file, "unknown ElementType '" + geovoronoi::printable(value) + "'");
      have_type = true;
    } else if (k == "elementnumberofchannels") {
      const auto c = parse_int(file, key, value);
      if (c < 1 || c > 4096) throw io_error(file, "ElementNumberOfChannels = " + geovoronoi::printable(value) + " is out of range (1 to 4096)");
      h.channels = int(c);
    } else if (k == "elementspacing" || k == "spacing" || k == "scale3d") {
      spacing_value = value;
    } else if (k == "elementsize") {
      element_size_value = value;
    } else if (k == "offset" || k == "position" || k == "origin" || k == "translation") {
      origin_value = value;
    } else if (k == "orientation" || k == "transformmatrix" || k == "rotation") {
      orientation_value = value;
    } else if (k == "elementbyteordermsb" || k == "binarydatabyteordermsb") {
      h.msb = parse_bool(file, key, value);
    } else if (k == "binarydata") {
      if (!parse_bool(file, key, value)) throw io_error(file, "BinaryData = False (ASCII data) is not supported");
    } else if (k == "compresseddata") {
      h.compressed = parse_bool(file, key, value);
    } else if (k == "compresseddatasize") {
      h.compressed_size = parse_int(file, key, value);
      if (h.compressed_size < 0) throw io_error(file, "CompressedDataSize = " + geovoronoi::printable(value) + " is negative");
    } else if (k == "headersize") {
      h.header_size = parse_int(file, key, value);
      if (h.header_size < -1) throw io_error(file, "HeaderSize = " + geovoronoi::printable(value) + " is below -1");
    } else if (k == "objecttype") {
      if (lower(value) != "image") throw io_error(file, "ObjectType = " + geovoronoi::printable(value) + " is not an Image");
    } else if (k == "elementdatafile") {
      if (value.empty()) throw io_error(file, "ElementDataFile is empty");
      h.data_file = value;
      h.data_start = pos;
      have_data_file = true;
    }
    // every other key (Comment, CenterOfRotation, AnatomicalOrientation, isPerpective, ...) is ignored
  }
  if (!have_data_file) throw io_error(file, "the header has no ElementDataFile line");
  if (h.ndims == 0) throw io_error(file, "the header has no NDims line");
  if (!have_dims) throw io_error(file, "the header has no DimSize line");
  if (!have_type) throw io_error(file, "the header has no ElementType line");
  if (dim_words.size() != std::size_t(h.ndims))
    throw io_error(file, "DimSize has " + std::to_string(dim_words.size()) + " values but NDims = " +
                             std::to_string(h.ndims));
  std::uint64_t total = 1;
  for (int a = 0; a < h.ndims; ++a) {
    const auto n = parse_int(file, "DimSize", dim_words[std::size_t(a)]);
    if (n < 1) throw io_error(file, "DimSize value " + geovoronoi::printable(dim_words[std::size_t(a)]) + " is not positive");
    if (!checked_mul(total, std::uint64_t(n), total, max_voxels))
      throw io_error(file, "DimSize implies more than 2^40 voxels");
    h.dim_size[std::size_t(a)] = n;
  }
  if (h.ndims == 4 && h.channels != 1 && h.dim_size[3] != 1)
    throw io_error(file, "NDims = 4 with ElementNumberOfChannels > 1 is not supported");
  const int sdims = std::min(h.ndims, 3);
  const std::string& sp = spacing_value.empty() ? element_size_value : spacing_value;
  if (!sp.empty()) {
    const auto s = parse_reals(file, "ElementSpacing", sp, std::size_t(sdims), std::size_t(h.ndims));
    for (int a = 0; a < sdims; ++a) {
      if (!(s[std::size_t(a)] > 0)) throw io_error(file, "ElementSpacing value " + format_double(s[std::size_t(a)]) + " is not positive");
      h.spacing[std::size_t(a)] = s[std::size_t(a)];
    }
  }
  if (!origin_value.empty()) {
    const auto o = parse_reals(file, "Offset", origin_value, std::size_t(sdims), std::size_t(h.ndims));
    for (int a = 0; a < sdims; ++a) h.origin[std::size_t(a)] = o[std::size_t(a)];
  }
  if (!orientation_value.empty()) {
    // ITK's convention: TransformMatrix lists the direction of index axis 0, then of axis 1, ...: the
    // columns of the direction matrix D, so value c * n + r is D(r, c). A 4D file's 4 x 4 matrix
    // keeps its spatial 3 x 3 block.
    const auto o = parse_reals(file, "TransformMatrix", orientation_value, 1, 16);
    int n = 0;
    if (o.size() == std::size_t(sdims * sdims)) n = sdims;
    else if (o.size() == std::size_t(h.ndims * h.ndims)) n = h.ndims;
    else
      throw io_error(file, "TransformMatrix has " + std::to_string(o.size()) + " values for NDims = " +
                               std::to_string(h.ndims));
    for (int r = 0; r < sdims; ++r)
      for (int c = 0; c < sdims; ++c) h.orientation[std::size_t(3 * r + c)] = o[std::size_t(n * c + r)];
    double block[9];
    for (int r = 0; r < sdims; ++r)
      for (int c = 0; c < sdims; ++c) block[sdims * r + c] = h.orientation[std::size_t(3 * r + c)];
    const std::string bad = direction_problem(block, sdims);
    if (!bad.empty()) throw io_error(file, "TransformMatrix: " + bad);
  }
  return h;
}

#if GEOVORONOI_IO_HAVE_ZLIB
/// Inflates a zlib or gzip stream into exactly `expected` bytes. The output grows with what the
/// stream really produces (starting near the compressed size, doubling, never beyond `expected`), so a
/// corrupt or lying stream fails before a large allocation; more or fewer bytes than `expected` throw.
inline std::vector<unsigned char> inflate_exact(const std::string& file, const unsigned char* src, std::size_t n,
                                                std::size_t expected) {
  std::vector<unsigned char> out;
  const auto grow = [&](std::size_t want) {
    want = std::min(expected, want);
    resize_or_throw(out, want, file, "the decompressed data");
  };
  grow(std::max<std::size_t>(std::size_t(1) << 16, 2 * std::min(n, expected)));
  z_stream zs{};
  if (inflateInit2(&zs, 15 + 32) != Z_OK) throw io_error(file, "zlib initialisation failed");
  struct ender {
    z_stream* z;
    ~ender() { inflateEnd(z); }
  } end_stream{&zs};
  std::size_t in_used = 0, done = 0;
  unsigned char spare[16];
  while (true) {
    if (done == out.size() && out.size() < expected) grow(out.size() <= expected / 2 ? 2 * out.size() : expected);
    const std::size_t in_chunk_size = std::min<std::size_t>(n - in_used, 1u << 30);
    zs.next_in = const_cast<unsigned char*>(src) + in_used;
    zs.avail_in = static_cast<uInt>(in_chunk_size);
    uInt out_chunk;
    if (done == expected) {  // any further output means the stream holds more than the header says
      zs.next_out = spare;
      out_chunk = sizeof spare;
    } else {
      zs.next_out = out.data() + done;
      out_chunk = static_cast<uInt>(std::min<std::size_t>(out.size() - done, 1u << 30));
    }
    zs.avail_out = out_chunk;
    const int rc = inflate(&zs, Z_NO_FLUSH);
    const std::size_t consumed = in_chunk_size - zs.avail_in;
    in_used += consumed;
    const std::size_t produced = out_chunk - zs.avail_out;
    if (done == expected && produced > 0)
      throw io_error(file, "compressed data hold more bytes than DimSize and ElementType imply (" +
                               std::to_string(expected) + ")");
    done += produced;
    if (rc == Z_STREAM_END) break;
    if (rc != Z_OK && rc != Z_BUF_ERROR)
      throw io_error(file, std::string("compressed data are corrupt (zlib: ") + (zs.msg ? zs.msg : "error") + ")");
    if (produced == 0 && consumed == 0)
      throw io_error(file, "compressed data are truncated (the stream ends after " + std::to_string(done) + " of " +
                               std::to_string(expected) + " bytes)");
  }
  if (done != expected)
    throw io_error(file, "compressed data hold " + std::to_string(done) + " bytes, DimSize and ElementType imply " +
                             std::to_string(expected));
  return out;
}

inline std::vector<unsigned char> deflate_all(const std::string& file, const unsigned char* src, std::size_t n) {
  uLong bound = compressBound(static_cast<uLong>(n));
  std::vector<unsigned char> out(bound);
  if (compress2(out.data(), &bound, src, static_cast<uLong>(n), Z_DEFAULT_COMPRESSION) != Z_OK)
    throw io_error(file, "zlib compression failed");
  out.resize(bound);
  return out;
}
#endif

}  // namespace detail

/// Reads only the header of a .mhd or .mha file.
inline metaimage_header read_metaimage_header(const std::string& path) {
  return detail::parse_metaimage_header(path, read_file(path));
}

/**
 * @brief Parses a MetaImage file already in memory (read_metaimage() reads it first), converting its
 *        elements to T. A separate ElementDataFile is read relative to @p path.
 * @param path   name of a .mhd (header, data in ElementDataFile) or .mha (ElementDataFile = LOCAL) file.
 * @param header_bytes the file's bytes.
 * @param layout how several channels are stored (ignored for one channel; a 4th dimension is planar).
 * @throws io_error naming the file and the problem for anything malformed, truncated or inconsistent.
 */
template <class T>
volume<T> parse_metaimage(const std::string& path, const std::vector<unsigned char>& header_bytes,
                          channel_layout layout = channel_layout::interleaved) {
  const metaimage_header h = detail::parse_metaimage_header(path, header_bytes);
  std::string data_path = path;
  std::vector<unsigned char> other;
  const std::vector<unsigned char>* data = &header_bytes;
  std::size_t start;
  if (detail::lower(h.data_file) == "local") {
    start = h.data_start;
    if (h.header_size > 0) {
      if (std::uint64_t(h.header_size) > header_bytes.size() - start)
        throw io_error(path, "HeaderSize = " + std::to_string(h.header_size) + " skips past the end of the file");
      start += std::size_t(h.header_size);
    }
  } else {
    const std::string df = detail::lower(h.data_file);
    if (df == "list" || df.rfind("list ", 0) == 0 || h.data_file.find('%') != std::string::npos)
      throw io_error(path, "ElementDataFile = " + geovoronoi::printable(h.data_file) + " (a list of slice files) is not supported");
    data_path = (h.data_file[0] == '/') ? h.data_file : detail::directory_of(path) + h.data_file;
    other = read_file(data_path);
    data = &other;
    start = 0;
    if (h.header_size > 0) {
      if (std::uint64_t(h.header_size) > other.size())
        throw io_error(data_path, "HeaderSize = " + std::to_string(h.header_size) + " is larger than the data file");
      start = std::size_t(h.header_size);
    }
  }
  const std::size_t es = element_size(h.type);
  std::uint64_t voxels = 1, values = 0, bytes = 0;
  for (int a = 0; a < 3; ++a) voxels *= std::uint64_t(h.dim_size[std::size_t(a)]);
  const std::uint64_t channels = std::uint64_t(h.channels) * std::uint64_t(h.dim_size[3]);
  if (!detail::checked_mul(voxels, channels, values, detail::max_voxels) ||
      !detail::checked_mul(values, es, bytes, std::uint64_t(1) << 62))
    throw io_error(path, "DimSize, channels and ElementType imply an absurd data size");
  const std::size_t available = data->size() - start;
  std::vector<unsigned char> raw;
  const unsigned char* payload = nullptr;
  if (h.compressed) {
    std::size_t csize = available;
    if (h.compressed_size >= 0) {
      if (std::uint64_t(h.compressed_size) > available)
        throw io_error(data_path, "CompressedDataSize = " + std::to_string(h.compressed_size) + " but only " +
                                      std::to_string(available) + " bytes follow the header (truncated?)");
      csize = std::size_t(h.compressed_size);
      if (h.header_size == -1) start = data->size() - csize;
    } else if (h.header_size == -1) {
      throw io_error(path, "HeaderSize = -1 with compressed data needs CompressedDataSize");
    }
    // deflate cannot compress better than about 1032:1; a bigger ratio is a lying header
    if (bytes > std::uint64_t(csize) * 1100u + 4096u)
      throw io_error(data_path, "DimSize implies " + std::to_string(bytes) + " bytes, more than " +
                                    std::to_string(csize) + " compressed bytes can hold");
#if GEOVORONOI_IO_HAVE_ZLIB
    raw = detail::inflate_exact(data_path, data->data() + start, csize, std::size_t(bytes));
    payload = raw.data();
#else
    throw io_error(path, "CompressedData = True needs zlib (build with GEOVORONOI_WITH_ZLIB=1 and link zlib)");
#endif
  } else {
    if (h.header_size == -1) {
      if (bytes > data->size())
        throw io_error(data_path, "DimSize and ElementType imply " + std::to_string(bytes) + " bytes but the file holds " +
                                      std::to_string(data->size()));
      start = data->size() - std::size_t(bytes);
      if (data == &header_bytes && start < h.data_start)
        throw io_error(path, "DimSize and ElementType imply more data than the file holds after its header");
    } else if (bytes > available) {
      throw io_error(data_path, "DimSize and ElementType imply " + std::to_string(bytes) + " bytes of data but only " +
                                    std::to_string(available) + " follow the header (truncated?)");
    }
    payload = data->data() + start;
    if (h.msb == detail::host_is_little_endian() && es > 1) {
      detail::resize_or_throw(raw, std::size_t(bytes), data_path, "the byte-swapped data");
      std::memcpy(raw.data(), payload, std::size_t(bytes));
      payload = raw.data();
    }
  }
  if (h.msb == detail::host_is_little_endian() && es > 1)
    detail::byte_swap(const_cast<unsigned char*>(payload), std::size_t(values), es);

  volume<T> v;
  v.dims = std::min(h.ndims, 3);
  for (int a = 0; a < 3; ++a) v.extents[std::size_t(a)] = h.dim_size[std::size_t(a)];
  v.spacing = h.spacing;
  v.origin = h.origin;
  v.orientation = h.orientation;
  v.channels = int(channels);
  v.stored = h.type;
  detail::resize_or_throw(v.data, std::size_t(values), path, "the image");
  detail::convert(data_path, h.type, payload, std::size_t(values), v.data.data());
  if (h.channels > 1 && layout == channel_layout::interleaved) {
    try {
      v.data = detail::reorder_channels(v.data, std::size_t(voxels), std::size_t(h.channels), true);
    } catch (const std::bad_alloc&) {
      throw out_of_memory(path, "out of memory allocating " + detail::byte_count(values * sizeof(T)) +
                                    " to reorder the channels");
    }
  }
  return v;
}

/// Reads a MetaImage file (see parse_metaimage()).
template <class T>
volume<T> read_metaimage(const std::string& path, channel_layout layout = channel_layout::interleaved) {
  return parse_metaimage<T>(path, read_file(path), layout);
}

/// Reads one channel of a MetaImage file as an image (Dim 2 needs a single slice).
template <class T, int Dim = 3>
image<T, Dim> read_metaimage_image(const std::string& path, int channel = 0,
                                   channel_layout layout = channel_layout::interleaved) {
  const auto v = read_metaimage<T>(path, layout);
  try {
    return v.template channel<Dim>(channel);
  } catch (const std::invalid_argument& e) {
    throw io_error(path, e.what());
  }
}

/**
 * @brief Writes a volume as MetaImage: `.mha` gets the data after its header (LOCAL), any other name
 *        (normally `.mhd`) gets a header and a raw file beside it (`.raw`, or `.zraw` compressed).
 *
 * The header uses ITK's key spellings (ObjectType, NDims, BinaryData, BinaryDataByteOrderMSB,
 * CompressedData, TransformMatrix, Offset, ElementSpacing, DimSize, ElementNumberOfChannels,
 * ElementType, ElementDataFile), which SOFA's reader also understands.
 */
template <class T>
void write_metaimage(const std::string& path, const volume<T>& v, const metaimage_write_options& opt = {}) {
  const element_type type = opt.type.value_or(v.stored);
  const int dims = std::max(1, std::min(v.dims, 3));
  {
    double block[9];
    for (int r = 0; r < dims; ++r)
      for (int c = 0; c < dims; ++c) block[dims * r + c] = v.orientation[std::size_t(3 * r + c)];
    const std::string bad = geovoronoi::detail::direction_problem(block, dims);
    if (!bad.empty()) throw std::invalid_argument("geovoronoi::io::write_metaimage: " + path + ": " + bad);
  }
  const std::size_t voxels = static_cast<std::size_t>(v.voxels());
  const std::size_t channels = static_cast<std::size_t>(v.channels);
  if (v.data.size() != voxels * channels)
    throw io_error(path, "volume holds " + std::to_string(v.data.size()) + " values, expected " +
                             std::to_string(voxels * channels));
  const std::vector<T>* values = &v.data;
  std::vector<T> interleaved;
  if (channels > 1 && opt.layout == channel_layout::interleaved) {
    interleaved = detail::reorder_channels(v.data, voxels, channels, false);
    values = &interleaved;
  }
  const std::size_t es = element_size(type);
  std::vector<unsigned char> bytes(values->size() * es);
  detail::convert_back(path, type, values->data(), values->size(), bytes.data());
  if (opt.msb == detail::host_is_little_endian()) detail::byte_swap(bytes.data(), values->size(), es);
  if (opt.compress) {
#if GEOVORONOI_IO_HAVE_ZLIB
    bytes = detail::deflate_all(path, bytes.data(), bytes.size());
#else
    throw io_error(path, "compressed MetaImage output needs zlib (build with GEOVORONOI_WITH_ZLIB=1 and link zlib)");
#endif
  }
  const bool local = detail::extension(path) == ".mha";
  std::string raw_path, raw_name = "LOCAL";
  if (!local) {
    const auto dot = path.find_last_of('.');
    const auto slash = path.find_last_of('/');
    const std::string stem = (dot != std::string::npos && (slash == std::string::npos || dot > slash)) ? path.substr(0, dot) : path;
    raw_path = stem + (opt.compress ? ".zraw" : ".raw");
    raw_name = detail::base_name(raw_path);
  }
  std::ostringstream hdr;
  auto list = [&](const double* x, int n) {
    for (int a = 0; a < n; ++a) hdr << (a ? " " : "") << detail::format_double(x[a]);
  };
  hdr << "ObjectType = Image\nNDims = " << dims << "\nBinaryData = True\nBinaryDataByteOrderMSB = "
      << (opt.msb ? "True" : "False") << "\nCompressedData = " << (opt.compress ? "True" : "False") << "\n";
  if (opt.compress) hdr << "CompressedDataSize = " << bytes.size() << "\n";
  hdr << "TransformMatrix =";  // the columns of the direction matrix, one after another (ITK)
  for (int c = 0; c < dims; ++c)
    for (int r = 0; r < dims; ++r) hdr << " " << detail::format_double(v.orientation[std::size_t(3 * r + c)]);
  hdr << "\nOffset = ";
  list(v.origin.data(), dims);
  hdr << "\nElementSpacing = ";
  list(v.spacing.data(), dims);
  hdr << "\nDimSize =";
  for (int a = 0; a < dims; ++a) hdr << " " << v.extents[std::size_t(a)];
  hdr << "\n";
  if (channels > 1) hdr << "ElementNumberOfChannels = " << channels << "\n";
  hdr << "ElementType = " << detail::met_name(type) << "\nElementDataFile = " << raw_name << "\n";
  const std::string text = hdr.str();
  if (local) {
    std::vector<unsigned char> all(text.begin(), text.end());
    all.insert(all.end(), bytes.begin(), bytes.end());
    detail::write_file(path, all.data(), all.size());
  } else {
    detail::write_file(raw_path, bytes.data(), bytes.size());
    detail::write_file(path, text.data(), text.size());
  }
}

/// Writes one image (any arithmetic T) as MetaImage with its own element type unless opt.type says otherwise.
template <class T, int Dim>
void write_metaimage(const std::string& path, const image<T, Dim>& img, const metaimage_write_options& opt = {}) {
  write_metaimage(path, make_volume<T>(img), opt);
}

}  // namespace geovoronoi::io

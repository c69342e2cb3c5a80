#pragma once
/// @file io/common.hpp
/// @brief Shared pieces of the volume readers and writers: the I/O exception, element types, the
///        multi-channel volume container and bounded file access.
///
/// Every reader checks the sizes a header announces against the bytes the file really holds before
/// it allocates anything, so a malformed or lying file ends in a geovoronoi::io::io_error naming the
/// file and the problem, never in a crash, a hang or a huge allocation.

#include <geovoronoi/config.hpp>
#include <geovoronoi/error.hpp>
#include <geovoronoi/grid.hpp>
#include <geovoronoi/image.hpp>

#include <array>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <fstream>
#include <cmath>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

namespace geovoronoi::io {

/// @brief A file could not be read or written, or its content is malformed. what() starts with the
///        file name; file() and problem() give the two parts separately.
class io_error : public geovoronoi::error {
 public:
  io_error(const std::string& file, const std::string& problem)
      : error(file + ": " + problem), file_(file), problem_(problem) {}
  const std::string& file() const noexcept { return file_; }
  const std::string& problem() const noexcept { return problem_; }

 private:
  std::string file_;
  std::string problem_;
};

/// @brief Memory ran out (or a size beyond the largest possible array was asked for) while reading
///        or writing @p file: not a fault of the file. The message names the size and its purpose.
class out_of_memory : public io_error {
 public:
  using io_error::io_error;
};

/**
 * @brief Records the path of every file that the readers of geovoronoi::io open, or try to open, on
 *        the calling thread while it lives: a MetaImage header's data file included. Logs nest: each
 *        live log of the thread records every read.
 *
 * A program that replaces a folder after reading its inputs asks the log which files it read, rather
 * than listing them itself (the geovoronoi tool refuses an --out folder that holds one of them).
 * @code
 * geovoronoi::io::read_log log;
 * auto v = geovoronoi::io::read_metaimage<float>("field.mhd");
 * // log.paths(): {"field.mhd", "field.raw"}
 * @endcode
 */
class read_log {
 public:
  read_log() { live().push_back(this); }
  ~read_log() {
    auto& l = live();
    for (std::size_t i = l.size(); i-- > 0;)
      if (l[i] == this) {
        l.erase(l.begin() + std::ptrdiff_t(i));
        break;
      }
  }
  read_log(const read_log&) = delete;
  read_log& operator=(const read_log&) = delete;

  /// The paths read (or tried) since this log was made, in order, as the reader was given them.
  const std::vector<std::string>& paths() const noexcept { return paths_; }

  /// Adds @p path to every live log of the calling thread (the readers call it before opening).
  static void record(const std::string& path) {
    for (read_log* l : live()) l->paths_.push_back(path);
  }

 private:
  static std::vector<read_log*>& live() {
    thread_local std::vector<read_log*> logs;
    return logs;
  }
  std::vector<std::string> paths_;
};

/// Scalar element types the formats can carry (MetaImage MET_*, NumPy descr, VTK type names).
enum class element_type { int8, uint8, int16, uint16, int32, uint32, int64, uint64, float32, float64 };

/// Size in bytes of one element of type t.
constexpr std::size_t element_size(element_type t) noexcept {
  switch (t) {
    case element_type::int8: case element_type::uint8: return 1;
    case element_type::int16: case element_type::uint16: return 2;
    case element_type::int32: case element_type::uint32: case element_type::float32: return 4;
    default: return 8;
  }
}

/// The element_type of a C++ arithmetic type (compile error for anything else).
template <class T>
constexpr element_type element_type_of() noexcept {
  static_assert(std::is_arithmetic_v<T> && !std::is_same_v<T, bool>,
                "geovoronoi::io: element types must be integer or floating-point scalars");
  if constexpr (std::is_floating_point_v<T>) {
    static_assert(sizeof(T) == 4 || sizeof(T) == 8, "geovoronoi::io: float and double only");
    return sizeof(T) == 4 ? element_type::float32 : element_type::float64;
  } else if constexpr (std::is_signed_v<T>) {
    return sizeof(T) == 1 ? element_type::int8 : sizeof(T) == 2 ? element_type::int16
         : sizeof(T) == 4 ? element_type::int32 : element_type::int64;
  } else {
    return sizeof(T) == 1 ? element_type::uint8 : sizeof(T) == 2 ? element_type::uint16
         : sizeof(T) == 4 ? element_type::uint32 : element_type::uint64;
  }
}

/// How several channels (components) per voxel are stored in a file.
enum class channel_layout {
  interleaved,  ///< all channels of voxel 0, then of voxel 1, ... (ITK, VTK, NumPy [z,y,x,c])
  planar        ///< one whole volume per channel, channel c of voxel v at c*size + v (SOFA / CImg)
};

/**
 * @brief A volume with any number of channels, as read from or written to a file.
 *
 * In memory the channels are always planar: channel c of voxel v is data[c * voxels() + v], voxels
 * x fastest (v = x + nx*(y + ny*z)). 2D files have extents[2] == 1 and dims == 2.
 */
template <class T>
struct volume {
  int dims = 3;                                  ///< dimensions stored in the file (1, 2 or 3)
  std::array<index_t, 3> extents{1, 1, 1};       ///< voxels along x, y, z
  std::array<double, 3> spacing{1.0, 1.0, 1.0};  ///< physical voxel size
  std::array<double, 3> origin{0.0, 0.0, 0.0};   ///< world position of voxel 0's centre
  std::array<double, 9> orientation{1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< direction cosines, row-major
  int channels = 1;
  element_type stored = element_type_of<T>();    ///< the element type the file held (or will hold)
  std::vector<T> data;                           ///< channels * voxels() values, planar

  index_t voxels() const noexcept { return extents[0] * extents[1] * extents[2]; }

  /// The grid (Dim 2 needs extents[2] == 1), with the direction from `orientation` (its upper-left
  /// 2 x 2 block in 2D).
  /// @throws std::invalid_argument for a 2D view of several slices, or an orientation that is not
  ///         orthonormal (grid's check).
  template <int Dim>
  grid<Dim> geometry() const {
    static_assert(Dim == 2 || Dim == 3, "geovoronoi::io::volume: Dim must be 2 or 3");
    if constexpr (Dim == 2) {
      if (extents[2] != 1)
        throw std::invalid_argument("geovoronoi::io::volume: a 3D volume with " + std::to_string(extents[2]) +
                                    " slices cannot be viewed as a 2D grid");
      return grid<2>({extents[0], extents[1]}, {spacing[0], spacing[1]}, {origin[0], origin[1]},
                     {orientation[0], orientation[1], orientation[3], orientation[4]});
    } else {
      return grid<3>(extents, spacing, origin, orientation);
    }
  }

  /// One channel as an image (copy).
  /// @throws std::invalid_argument if @p c is not a channel, or if data does not hold
  ///         channels * voxels() values.
  template <int Dim = 3>
  image<T, Dim> channel(int c = 0) const {
    if (c < 0 || c >= channels)
      throw std::invalid_argument("geovoronoi::io::volume: channel " + std::to_string(c) + " of " +
                                  std::to_string(channels) + " requested");
    const auto n = static_cast<std::size_t>(voxels());
    if (extents[0] < 1 || extents[1] < 1 || extents[2] < 1 || data.size() / n != static_cast<std::size_t>(channels) ||
        data.size() % n != 0)
      throw std::invalid_argument("geovoronoi::io::volume: data holds " + std::to_string(data.size()) +
                                  " values, but " + std::to_string(channels) + " channels of " +
                                  std::to_string(extents[0]) + " x " + std::to_string(extents[1]) + " x " +
                                  std::to_string(extents[2]) + " voxels need " +
                                  std::to_string(static_cast<std::size_t>(channels) * n));
    const auto cs = static_cast<std::size_t>(c);
    return image<T, Dim>(geometry<Dim>(), std::vector<T>(data.begin() + std::ptrdiff_t(cs * n),
                                                         data.begin() + std::ptrdiff_t((cs + 1) * n)));
  }
};

namespace detail {
/// Whether @p s converts to the arithmetic type D without undefined behaviour or wrapping: finite
/// and within D's range (after truncation toward zero) for an integer D; for a floating D narrower
/// than a floating S, a finite non-zero value must stay finite and non-zero (a double 1e300 read as
/// float would become an infinitely stiff voxel, 1e-50 a masked one); always otherwise.
template <class D, class S>
bool representable(S s) noexcept {
  if constexpr (std::is_floating_point_v<D>) {
    if constexpr (std::is_floating_point_v<S> && (sizeof(D) < sizeof(S))) {
      if (!(s == s) || s == S(0) || std::isinf(s)) return true;
      const S a = s < S(0) ? -s : s;
      return a <= S(std::numeric_limits<D>::max()) && static_cast<D>(a) != D(0);
    }
    return true;
  } else if constexpr (std::is_floating_point_v<S>) {
    if (!(s == s)) return false;
    // [lo, hi) in double: both are powers of two (or 0), so exact
    const double lo = std::is_signed_v<D> ? -std::ldexp(1.0, std::numeric_limits<D>::digits) : 0.0;
    const double hi = std::ldexp(1.0, std::numeric_limits<D>::digits);
    const double t = std::trunc(static_cast<double>(s));
    return t >= lo && t < hi;
  } else {
    using wide_s = std::conditional_t<std::is_signed_v<S>, std::intmax_t, std::uintmax_t>;
    const wide_s w = static_cast<wide_s>(s);
    if constexpr (std::is_signed_v<S>) {
      if (w < 0) return std::is_signed_v<D> && w >= static_cast<std::intmax_t>(std::numeric_limits<D>::lowest());
    }
    // w >= 0 here: compare magnitudes as unsigned
    return sizeof(S) < sizeof(D) || static_cast<std::uintmax_t>(w) <= static_cast<std::uintmax_t>(std::numeric_limits<D>::max());
  }
}

/// Name of a C++ element type for messages.
template <class T>
const char* type_name() noexcept {
  if constexpr (std::is_same_v<T, float>) return "float32";
  else if constexpr (std::is_same_v<T, double>) return "float64";
  else if constexpr (std::is_floating_point_v<T>) return "long double";
  else if constexpr (std::is_signed_v<T>) return sizeof(T) == 1 ? "int8" : sizeof(T) == 2 ? "int16" : sizeof(T) == 4 ? "int32" : "int64";
  else return sizeof(T) == 1 ? "uint8" : sizeof(T) == 2 ? "uint16" : sizeof(T) == 4 ? "uint32" : "uint64";
}

/// "element I is V, which TYPE cannot hold (...)": the reason a conversion was refused.
template <class D, class S>
std::string unrepresentable(S s, std::size_t i) {
  std::string value, why;
  if constexpr (std::is_floating_point_v<S>) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.17g", static_cast<double>(s));
    value = s != s ? "NaN" : std::isinf(s) ? (s > 0 ? "+inf" : "-inf") : buf;
    why = s != s || std::isinf(s) ? "not a finite number" : "out of range";
    if constexpr (std::is_floating_point_v<D>)
      return "element " + std::to_string(i) + " is " + value + ", which " + type_name<D>() + " cannot hold (" +
             (s > S(1) || s < S(-1) ? "beyond its range: it would become infinite" : "too small: it would become 0") +
             "); read it as float64 (double)";
  } else {
    value = std::to_string(s);
    why = "out of range";
  }
  return "element " + std::to_string(i) + " is " + value + ", which " + type_name<D>() + " cannot hold (" + why +
         ": " + type_name<D>() + " holds " + std::to_string(std::numeric_limits<D>::lowest()) + " to " +
         std::to_string(std::numeric_limits<D>::max()) + ")";
}
}  // namespace detail

/// A single-channel volume describing an image (same grid and direction, one channel).
/// @throws std::invalid_argument naming the first value T cannot hold (NaN, infinite or out of
///         range for an integer T).
template <class T, class U, int Dim>
volume<T> make_volume(const image<U, Dim>& img) {
  volume<T> v;
  v.dims = Dim;
  for (int a = 0; a < Dim; ++a) {
    v.extents[a] = img.geometry().extent(a);
    v.spacing[a] = img.geometry().spacing(a);
    v.origin[a] = img.geometry().origin()[a];
    for (int b = 0; b < Dim; ++b) v.orientation[std::size_t(3 * a + b)] = img.geometry().direction(a, b);
  }
  v.data.resize(static_cast<std::size_t>(img.size()));
  for (index_t i = 0; i < img.size(); ++i) {
    if (!detail::representable<T>(img[i]))
      throw std::invalid_argument("geovoronoi::io::make_volume: " + detail::unrepresentable<T>(img[i], std::size_t(i)));
    v.data[static_cast<std::size_t>(i)] = static_cast<T>(img[i]);
  }
  return v;
}

namespace detail {

/// Largest voxel count any reader accepts (2^40); real limits come from the file size.
inline constexpr std::uint64_t max_voxels = std::uint64_t(1) << 40;

/// a * b, or false when it overflows `limit`.
inline bool checked_mul(std::uint64_t a, std::uint64_t b, std::uint64_t& out,
                        std::uint64_t limit = std::numeric_limits<std::uint64_t>::max()) noexcept {
  if (a != 0 && b > limit / a) return false;
  out = a * b;
  return true;
}

inline bool host_is_little_endian() noexcept {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

inline void byte_swap(unsigned char* p, std::size_t n, std::size_t size) noexcept {
  if (size <= 1) return;
  for (std::size_t i = 0; i < n; ++i, p += size)
    for (std::size_t a = 0, b = size - 1; a < b; ++a, --b) std::swap(p[a], p[b]);
}

template <class S, class T>
void convert_from(const std::string& file, const unsigned char* src, std::size_t n, T* out) {
  for (std::size_t i = 0; i < n; ++i) {
    S s;
    std::memcpy(&s, src + i * sizeof(S), sizeof(S));
    if (!representable<T>(s)) throw io_error(file, "cannot be read as " + std::string(type_name<T>()) + ": " + unrepresentable<T>(s, i));
    out[i] = static_cast<T>(s);
  }
}

/// Converts n elements of type `type` (native byte order) to T. A value T cannot hold (NaN, +-inf or
/// out of range for an integer T; fractions are truncated toward zero) throws io_error naming
/// @p file, the element and the value.
template <class T>
void convert(const std::string& file, element_type type, const unsigned char* src, std::size_t n, T* out) {
  switch (type) {
    case element_type::int8: return convert_from<std::int8_t>(file, src, n, out);
    case element_type::uint8: return convert_from<std::uint8_t>(file, src, n, out);
    case element_type::int16: return convert_from<std::int16_t>(file, src, n, out);
    case element_type::uint16: return convert_from<std::uint16_t>(file, src, n, out);
    case element_type::int32: return convert_from<std::int32_t>(file, src, n, out);
    case element_type::uint32: return convert_from<std::uint32_t>(file, src, n, out);
    case element_type::int64: return convert_from<std::int64_t>(file, src, n, out);
    case element_type::uint64: return convert_from<std::uint64_t>(file, src, n, out);
    case element_type::float32: return convert_from<float>(file, src, n, out);
    case element_type::float64: return convert_from<double>(file, src, n, out);
  }
}

template <class D, class T>
void convert_to(const std::string& file, const T* in, std::size_t n, unsigned char* dst) {
  for (std::size_t i = 0; i < n; ++i) {
    if (!representable<D>(in[i])) throw io_error(file, "cannot be written as " + std::string(type_name<D>()) + ": " + unrepresentable<D>(in[i], i));
    const D d = static_cast<D>(in[i]);
    std::memcpy(dst + i * sizeof(D), &d, sizeof(D));
  }
}

/// Converts n values of T to `type` in native byte order; a value the type cannot hold throws
/// io_error naming @p file (as convert()).
template <class T>
void convert_back(const std::string& file, element_type type, const T* in, std::size_t n, unsigned char* dst) {
  switch (type) {
    case element_type::int8: return convert_to<std::int8_t>(file, in, n, dst);
    case element_type::uint8: return convert_to<std::uint8_t>(file, in, n, dst);
    case element_type::int16: return convert_to<std::int16_t>(file, in, n, dst);
    case element_type::uint16: return convert_to<std::uint16_t>(file, in, n, dst);
    case element_type::int32: return convert_to<std::int32_t>(file, in, n, dst);
    case element_type::uint32: return convert_to<std::uint32_t>(file, in, n, dst);
    case element_type::int64: return convert_to<std::int64_t>(file, in, n, dst);
    case element_type::uint64: return convert_to<std::uint64_t>(file, in, n, dst);
    case element_type::float32: return convert_to<float>(file, in, n, dst);
    case element_type::float64: return convert_to<double>(file, in, n, dst);
  }
}

/// "1.5 GiB (1610612736 bytes)" for messages.
inline std::string byte_count(std::uint64_t n) {
  char buf[64];
  if (n >= (std::uint64_t(1) << 30)) std::snprintf(buf, sizeof buf, "%.1f GiB", double(n) / double(1 << 30));
  else if (n >= (std::uint64_t(1) << 20)) std::snprintf(buf, sizeof buf, "%.1f MiB", double(n) / double(1 << 20));
  else if (n >= 1024) std::snprintf(buf, sizeof buf, "%.1f KiB", double(n) / 1024.0);
  else return std::to_string(n) + " bytes";
  return std::string(buf) + " (" + std::to_string(n) + " bytes)";
}

/// v.resize(n), with std::bad_alloc (or a size beyond max_size()) turned into an io::out_of_memory
/// that names @p file, the byte count and what the memory was for.
template <class V>
void resize_or_throw(V& v, std::size_t n, const std::string& file, const char* what) {
  try {
    v.resize(n);
  } catch (const std::bad_alloc&) {
    throw out_of_memory(file, std::string("out of memory allocating ") +
                                  byte_count(std::uint64_t(n) * sizeof(typename V::value_type)) + " for " + what);
  } catch (const std::length_error&) {
    throw out_of_memory(file, std::string("cannot allocate ") +
                                  byte_count(std::uint64_t(n) * sizeof(typename V::value_type)) + " for " + what +
                                  " (beyond the largest possible array)");
  }
}

/// Reorders channel-interleaved values into planar order (or back with to_planar = false).
template <class T>
std::vector<T> reorder_channels(const std::vector<T>& in, std::size_t voxels, std::size_t channels, bool to_planar) {
  if (channels <= 1) return in;
  std::vector<T> out(in.size());
  for (std::size_t v = 0; v < voxels; ++v)
    for (std::size_t c = 0; c < channels; ++c) {
      if (to_planar) out[c * voxels + v] = in[v * channels + c];
      else out[v * channels + c] = in[c * voxels + v];
    }
  return out;
}

/// Writes bytes to a file, throwing io_error on failure.
inline void write_file(const std::string& path, const void* data, std::size_t size, bool append = false) {
  std::ofstream out(path, std::ios::binary | (append ? std::ios::app : std::ios::trunc));
  if (!out) throw io_error(path, "cannot open the file for writing");
  if (size) out.write(static_cast<const char*>(data), static_cast<std::streamsize>(size));
  out.flush();
  if (!out) throw io_error(path, "write error (disk full?)");
}

inline std::string lower(std::string s) {
  for (auto& ch : s) ch = static_cast<char>(ch >= 'A' && ch <= 'Z' ? ch - 'A' + 'a' : ch);
  return s;
}

inline std::string extension(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  const auto dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return {};
  return lower(path.substr(dot));
}

inline std::string directory_of(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  return slash == std::string::npos ? std::string() : path.substr(0, slash + 1);
}

inline std::string base_name(const std::string& path) {
  const auto slash = path.find_last_of("/\\");
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Shortest decimal text that reads back to the same double.
inline std::string format_double(double x) { return geovoronoi::detail::shortest_text(x); }

}  // namespace detail

/// @brief A whole file in memory, as every reader of geovoronoi::io reads its files: recorded in the
///        live read_logs first.
/// @throws io_error when the path is missing, not a regular file (a folder, FIFO or device) or
///         cannot be read; io::out_of_memory when its contents do not fit in memory.
inline std::vector<unsigned char> read_file(const std::string& path) {
  read_log::record(path);
  // a directory opens on some systems and reports a meaningless size: only regular files are read
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    if (std::filesystem::is_directory(path, ec)) throw io_error(path, "is a folder, not a regular file");
    if (std::filesystem::exists(path, ec))
      throw io_error(path, "is not a regular file (a FIFO, socket or device), so it cannot be read");
    throw io_error(path, "cannot open the file for reading (it does not exist)");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) throw io_error(path, "cannot open the file for reading");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size < 0) throw io_error(path, "cannot determine the file size");
  in.seekg(0, std::ios::beg);
  std::vector<unsigned char> bytes;
  detail::resize_or_throw(bytes, static_cast<std::size_t>(size), path, "the file's contents");
  if (size > 0 && !in.read(reinterpret_cast<char*>(bytes.data()), size))
    throw io_error(path, "read error");
  return bytes;
}

}  // namespace geovoronoi::io

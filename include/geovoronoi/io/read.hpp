#pragma once
/// @file io/read.hpp
/// @brief read_volume(): any supported volume file by its extension (.mhd, .mha, .npy, .pgm, .ppm,
///        .pnm), and io/read.hpp includes every reader and writer of geovoronoi::io except the pictures
///        (rgb_image.hpp, png.hpp, picture.hpp).

#include <geovoronoi/io/common.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/npy.hpp>
#include <geovoronoi/io/pnm.hpp>
#include <geovoronoi/io/vti.hpp>

namespace geovoronoi::io {

/// Options of read_volume().
struct read_options {
  /// Slices to extrude a 2D picture (.pgm/.ppm) to; 1 keeps it 2D (one slice).
  index_t extrude = 1;
  /// PPM channel (see pnm_options).
  int pnm_channel = 0;
  /// Layout of several channels in a MetaImage file.
  channel_layout layout = channel_layout::interleaved;
};

/**
 * @brief Reads a volume, choosing the format from the file name's extension.
 * @throws io_error for an unknown extension or any problem with the file.
 */
template <class T>
volume<T> read_volume(const std::string& path, const read_options& opt = {}) {
  const std::string ext = detail::extension(path);
  if (ext == ".mhd" || ext == ".mha") return read_metaimage<T>(path, opt.layout);
  if (ext == ".npy") return read_npy_volume<T>(path);
  if (ext == ".pgm" || ext == ".ppm" || ext == ".pnm") {
    pnm_options p;
    p.extrude = opt.extrude;
    p.channel = opt.pnm_channel;
    return read_pnm<T>(path, p);
  }
  throw io_error(path, "unknown volume format '" + ext + "' (expected .mhd, .mha, .npy, .pgm or .ppm)");
}

}  // namespace geovoronoi::io

#pragma once
/// @file io/png.hpp
/// @brief PNG writer (libpng) for an `rgb_image` (io/rgb_image.hpp). The pictures themselves are
///        drawn by io/picture.hpp.
///
/// Needs libpng at link time (CMake: PNG::PNG) when write_png() is used; without <png.h> (or with
/// GEOVORONOI_NO_PNG defined) write_png() throws io_error.
///
/// @code
/// geovoronoi::io::rgb_image pic(64, 32, {255, 0, 0});
/// geovoronoi::io::write_png("red.png", pic);
/// @endcode

#include <geovoronoi/io/rgb_image.hpp>

#include <csetjmp>
#include <cstdio>

#if __has_include(<png.h>) && !defined(GEOVORONOI_NO_PNG)
#include <png.h>
#define GEOVORONOI_IO_HAVE_PNG 1
#else
#define GEOVORONOI_IO_HAVE_PNG 0
#endif

namespace geovoronoi::io {

/// Writes an RGB picture as PNG. @throws io_error naming the file on failure or without libpng.
inline void write_png(const std::string& path, const rgb_image& pic) {
#if GEOVORONOI_IO_HAVE_PNG
  if (pic.width <= 0 || pic.height <= 0 || pic.pixels.size() != std::size_t(pic.width * pic.height * 3))
    throw io_error(path, "refusing to write an empty or inconsistent picture");
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw io_error(path, "cannot open the file for writing");
  // libpng's default handlers print to stderr; these keep its message for the one io_error instead
  struct handlers {
    static void error(png_structp p, png_const_charp msg) {
      auto* where = static_cast<std::string*>(png_get_error_ptr(p));
      if (where && msg) *where = msg;
      png_longjmp(p, 1);
    }
    static void warning(png_structp, png_const_charp) {}
  };
  std::string message;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, &message, handlers::error, handlers::warning);
  png_infop info = png ? png_create_info_struct(png) : nullptr;
  std::vector<png_bytep> rows(std::size_t(pic.height));
  for (index_t y = 0; y < pic.height; ++y)
    rows[std::size_t(y)] = const_cast<png_bytep>(pic.pixels.data() + std::size_t(3 * pic.width * y));
  volatile bool ok = png && info;  // volatile: read after a longjmp from libpng
  if (ok && setjmp(png_jmpbuf(png)) == 0) {
    png_init_io(png, f);
    png_set_IHDR(png, info, png_uint_32(pic.width), png_uint_32(pic.height), 8, PNG_COLOR_TYPE_RGB,
                 PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
    png_write_info(png, info);
    png_write_image(png, rows.data());
    png_write_end(png, nullptr);
  } else {
    ok = false;
  }
  png_destroy_write_struct(&png, &info);
  const bool closed = std::fclose(f) == 0;
  if (!ok || !closed)
    throw io_error(path, "libpng failed to write the picture" + (message.empty() ? std::string() : " (" + message + ")") +
                             (closed ? "" : " (disk full?)"));
#else
  (void)pic;
  throw io_error(path, "PNG output needs libpng (not available in this build)");
#endif
}

}  // namespace geovoronoi::io

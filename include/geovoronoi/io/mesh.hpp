#pragma once
/// @file io/mesh.hpp
/// @brief Reads a triangle mesh by file extension: .stl (ASCII or binary) or .obj.

#include <geovoronoi/io/common.hpp>
#include <geovoronoi/io/obj.hpp>
#include <geovoronoi/io/stl.hpp>
#include <geovoronoi/mesh.hpp>

#include <string>

namespace geovoronoi::io {

/**
 * @brief Reads @p path as STL or OBJ, chosen by its extension (case-insensitive).
 * @throws io_error naming the file for an unknown extension or anything read_stl() / read_obj()
 *         reject.
 *
 * @code
 * geovoronoi::triangle_mesh blade = geovoronoi::io::read_mesh("blade.stl");
 * @endcode
 */
inline triangle_mesh read_mesh(const std::string& path) {
  const std::string ext = detail::extension(path);
  if (ext == ".stl") return read_stl(path);
  if (ext == ".obj") return read_obj(path);
  throw io_error(path, "unknown mesh format \"" + ext + "\" (expected .stl or .obj)");
}

}  // namespace geovoronoi::io

#pragma once
/// @file error.hpp
/// @brief The exceptions the library throws.
///
/// Invalid arguments (bad extents, seeds, field sizes, options) throw std::invalid_argument with a
/// message that names the problem. A user metric that returns a negative or NaN weight throws
/// geovoronoi::metric_error when a backend can detect it; distances that overflow the distance type
/// throw geovoronoi::overflow_error; a progress callback that asks to stop makes the call throw
/// geovoronoi::cancelled. Backends with their own failure modes
/// (CUDA) derive their exceptions from geovoronoi::error.

#include <stdexcept>
#include <string>

namespace geovoronoi {

/// Base of the library's own runtime errors (not of std::invalid_argument, which it also throws).
class error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A metric produced an edge weight that is negative or NaN, which breaks every shortest-path solver.
class metric_error : public error {
 public:
  using error::error;
};

/// A path sum (or an edge weight) overflowed the distance type: a voxel that a finite path reaches
/// would come out unreachable. The message names the voxel and the value; computing in double or
/// rescaling the field or the spacing avoids it (docs/errors.md, "Overflow").
class overflow_error : public error {
 public:
  using error::error;
};

/// A long computation was cancelled by its progress callback.
class cancelled : public error {
 public:
  cancelled() : error("geovoronoi: cancelled by the progress callback") {}
};

}  // namespace geovoronoi

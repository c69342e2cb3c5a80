#pragma once
// The backends of the geovoronoi tool: ONE table (backends.cpp) says which exist, which are built
// into this binary, how each describes itself, whether it can run here, and how it solves.

#include "arguments.hpp"
#include "solve.hpp"

#include <string>
#include <vector>

namespace gvcli {

struct backend {
  const char* name;  ///< as given to --backend
  bool built;        ///< compiled into this binary
  /// What `geovoronoi backends` says after "built, " (e.g. "sequential Dijkstra").
  std::string (*describe)();
  /// Why it cannot run here; empty when it can.
  std::string (*unavailable)();
  /// Whether it is worth choosing by default when it can run (see default_backend()).
  bool (*worth_default)();
  gv::diagram<float, 3> (*voronoi)(const problem_spec&);
  gv::shape_weights<float, 3> (*shape)(const problem_spec&, const gv::diagram<float, 3>&, const gv::shape_options&);
  gv::point_weights<float> (*shape_at)(const problem_spec&, const gv::diagram<float, 3>&, const point_spec&,
                                       const gv::shape_options&);
};

/// Every backend the tool knows, slowest first: seq, thrust, cuda.
const std::vector<backend>& backends();

/// The names of the built backends, comma-separated.
std::string built_backend_names();

/// The default backend (docs/cli.md): the last one in the table (the fastest) that is built, can
/// run here and is worth it: cuda when a device answers; else thrust when the machine has more
/// than one hardware thread; else seq.
const backend& default_backend();

/// The backend named by --backend, or the default; a usage_error when it is unknown, not built or
/// cannot run here.
const backend& pick_backend(const arguments& a);

/// `--threads N`: how many OpenMP threads the thrust backend uses, 1 to max_threads() (4 x the
/// hardware threads, errors.hpp); overrides OMP_NUM_THREADS. No effect on seq (one thread) or cuda.
/// A usage_error when N is out of range.
void use_threads(const arguments& a);

}  // namespace gvcli

#pragma once
// The backends of the geovoronoi tool: ONE table (backends.cpp) says which exist, which are built
// into this binary, how each describes itself, whether it can run here, and how it solves.

#include "arguments.hpp"
#include "solve.hpp"

#include <string>
#include <type_traits>
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
  /// How it solves, in float and in double (`--precision`).
  solver_fns<float> in_float;
  solver_fns<double> in_double;
  template <class T>
  const solver_fns<T>& fns() const noexcept {
    if constexpr (std::is_same_v<T, float>)
      return in_float;
    else
      return in_double;
  }
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

/// The threads a thrust run would use now: OpenMP's thread limit (`--threads N` once use_threads()
/// has set it, else OMP_NUM_THREADS, else the hardware threads); the hardware threads without OpenMP.
unsigned thrust_threads();

/// `--threads N`: how many threads the thrust backend uses, 1 to max_threads() (4 x the hardware
/// threads, errors.hpp); overrides OMP_NUM_THREADS. Returns N (0 without the option), which the
/// solves pass on as solve_options::threads / shape_options::threads; also sets the OpenMP default.
/// No effect on seq (one thread) or cuda. A usage_error when N is out of range.
unsigned use_threads(const arguments& a);

}  // namespace gvcli

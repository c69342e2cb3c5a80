#pragma once
// The backends of the front end (the geovoronoi tool and the Python extension): ONE table
// (backends.cpp) says which exist, which are built into this binary (those whose typed problems
// registered, typed_problem.hpp), how each describes itself and whether it can run here; ONE rule
// (choose_backend()) says which runs a problem when none is named.

#include "arguments.hpp"
#include "kinds.hpp"

#include <geovoronoi/image.hpp>

#include <string>
#include <vector>

namespace gvcli {

struct backend {
  backend_id id;
  const char* name;  ///< as given to --backend (backend= in Python)
  /// Compiled into this binary.
  bool built() const noexcept;
  /// What `geovoronoi backends` says after "built, " (e.g. "sequential Dijkstra").
  std::string describe() const;
  /// Why it cannot run here; empty when it can (or when it is not built).
  std::string unavailable() const;
};

/// Every backend the front end knows, slowest first: seq, thrust, cuda.
const std::vector<backend>& backends();
const backend& find_backend(backend_id b);

/// The names of the built backends, comma-separated.
std::string built_backend_names();

/// The backend named @p name, checked: a usage_error when it is unknown, not built or cannot run
/// here. With @p allow_auto, "auto" is accepted too and gives null (choose_backend() decides per problem).
const backend* parse_backend(const std::string& name, bool allow_auto = false);

/// The machine-level default (what `geovoronoi backends` and the demo use, and what choose_backend()
/// falls back to): the last backend in the table (the fastest) that is built, can run here and is
/// worth it: cuda when a device answers; else thrust when the machine has more than one hardware
/// thread; else seq.
const backend& default_backend();

/**
 * The backend that runs a problem when none is named (the tool without --backend, the Python API's
 * backend="auto"): the library's rule (backend/choose.hpp, docs/backends.md "Choosing a backend"),
 * recommended_shape_backend() for a run that computes shape functions, recommended_backend()
 * otherwise, asked with the threads the run may use (@p threads, else thrust_threads()) and whether a
 * CUDA device answers; the recommended backend when it is built and can run here, else
 * default_backend(). One pass over the field.
 * @throws std::invalid_argument from make_problem() for a grid it refuses (as make_typed_problem()).
 */
template <class T, int Dim>
backend_id choose_backend(metric_id metric, int connectivity, gv::image_view<const T, Dim> field, unsigned threads,
                          bool shape_functions);

/// The threads a thrust run would use now: OpenMP's thread limit (`--threads N` once use_threads()
/// has set it, else OMP_NUM_THREADS, else the hardware threads); the hardware threads without OpenMP.
unsigned thrust_threads();

/// The backend named by --backend, or default_backend() without it (the final choice per problem is
/// choose_backend()'s); a usage_error when it is unknown, not built or cannot run here.
const backend& pick_backend(const arguments& a);

/// `--threads N`: how many threads the thrust backend uses, 1 to max_threads() (4 x the hardware
/// threads, errors.hpp); overrides OMP_NUM_THREADS. Returns N (0 without the option), which the
/// solves pass on as solve_options::threads / shape_options::threads; also sets the OpenMP default.
/// No effect on seq (one thread) or cuda. A usage_error when N is out of range.
unsigned use_threads(const arguments& a);

}  // namespace gvcli

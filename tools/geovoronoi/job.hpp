#pragma once
// What `voronoi`, `shape-functions` and `cut` share: the options, loading the field (a stiffness file,
// or meshes voxelized: --mesh) and the seeds,
// choosing the backend, the run's typed problem (made once, typed_problem.hpp), solving the diagram
// with seed errors reported by file and line, writing the outputs.

#include "arguments.hpp"
#include "backends.hpp"
#include "output_dir.hpp"
#include "outputs.hpp"
#include "progress_bar.hpp"
#include "typed_problem.hpp"

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace gvcli {

/// Everything a solve needs, parsed, and the run's problem (the seeds are checked by the library when
/// solving).
struct job {
  std::string stiffness_path, seeds_path, out;
  /// What the field came from, for messages: the --stiffness file, or the --mesh files (comma-separated).
  std::string field_name;
  metric_id metric = metric_id::min_stiffness;
  int connectivity = 26;
  const backend* solver = nullptr;
  /// `--threads N`, 0 without it (solve_options::threads, shape_options::threads).
  unsigned threads = 0;
  /// `--precision`: whether the whole pipeline runs in double (then field_double holds the field,
  /// else field does).
  bool in_double = false;
  gv::image<float, 3> field;
  gv::image<double, 3> field_double;
  std::vector<gv::coord<3>> seeds;
  std::vector<int> seed_lines;  ///< the seed file's line of each seed
  /// `--cut MESH` files, in order, and the cut edges of all of them (null without --cut).
  std::vector<std::string> cut_paths;
  std::shared_ptr<const gv::cut_table> cuts;
  std::shared_ptr<const gv::cut_set<3>> cut_set;  ///< the same edges as a cut_set (for `cut`'s update)
  std::size_t cut_edges = 0;
  /// `--coarsen N`: the field is the fine image of a branching grid of factor N (0 without it: a regular
  /// run); `--reduction`, the copies' stiffness. Such a run makes no regular problem (problem_float and
  /// problem_double stay null).
  int coarsen = 0;
  gv::stiffness_reduction reduction = gv::stiffness_reduction::mean;
  /// Warnings found while loading (a --cut mesh that cuts no edge), printed by the command as notes.
  std::vector<std::string> notes;
  /// The problem of the run (field, metric, connectivity, cuts) on its backend, in its precision.
  std::unique_ptr<const typed_problem<float, 3>> problem_float;
  std::unique_ptr<const typed_problem<double, 3>> problem_double;

  const gv::grid<3>& geometry() const noexcept { return in_double ? field_double.geometry() : field.geometry(); }
  const char* precision_name() const noexcept { return in_double ? "double" : "float"; }
  template <class T>
  const gv::image<T, 3>& field_in() const noexcept {
    if constexpr (std::is_same_v<T, float>)
      return field;
    else
      return field_double;
  }
  template <class T>
  const typed_problem<T, 3>& problem() const noexcept {
    if constexpr (std::is_same_v<T, float>)
      return *problem_float;
    else
      return *problem_double;
  }
  /// The run's problem on another field @p f (of the run's grid), with the run's cuts or without any:
  /// `cut` solves the problem before and after its change. A grid the library refuses is a usage_error.
  template <class T>
  std::unique_ptr<const typed_problem<T, 3>> problem_on(const gv::image<T, 3>& f, bool with_cuts) const;
  /// The options of a solve of this run (threads; the caller adds progress, parents).
  gv::solve_options options() const {
    gv::solve_options o;
    o.threads = threads;
    return o;
  }
  /// How its pictures are titled (metric, neighbours; lengths in the volume's unit).
  picture_context pictures() const { return {metric_name(metric), "LENGTH", connectivity}; }
};

/// The options of voronoi plus @p extra (shape-functions adds its own).
std::set<std::string> solve_options(std::set<std::string> extra = {});
/// The flags (options without a value) of voronoi and shape-functions.
std::set<std::string> solve_flags();
/// The options of voronoi and shape-functions that may be repeated (--cut).
std::set<std::string> solve_repeatable();

/// The job of @p a for the command @p command ("voronoi", "shape-functions", "cut"); with --coarsen
/// (--reduction: only with it) no regular problem is made, the branching grid is built when solving.
job load_job(const arguments& a, const std::string& command);

/// What `shape-functions` and `cut --method` read about the shape functions.
struct shape_args {
  gv::shape_method method = gv::shape_method::distance_ratio;
  int k = 4;             ///< `--nodes-per-voxel K`, 1..64 (default 4)
  int picture_node = 0;  ///< `--picture-node N` (default 0), checked against the nodes by check_picture_node()
  /// The library's options for them in the run @p j (threads; progress left to the caller).
  gv::shape_options options(const job& j) const {
    gv::shape_options o;
    o.method = method;
    o.max_nodes_per_voxel = k;
    o.threads = j.threads;
    return o;
  }
};
/// The options of shape_args: --method, --nodes-per-voxel, --picture-node.
std::set<std::string> shape_arg_options();
/// --method (required), --nodes-per-voxel and --picture-node of @p a; a usage_error when one is bad.
shape_args parse_shape_args(const arguments& a);
/// A usage_error when --picture-node names no node of @p j.
void check_picture_node(const shape_args& s, const job& j);

/// The diagram of @p j on its backend, in T, on the problem @p p (the run's own, or one of
/// job::problem_on()); the library's seed errors (outside, masked, duplicate) come back as a
/// usage_error naming the seed file and line, and so does a seed at geodesic distance 0 from another
/// (a zero-cost path joins them), which would have no cell of its own, and a distance that overflows
/// T (geovoronoi::overflow_error: exit 2, suggesting --precision double).
template <class T>
gv::diagram<T, 3> solve_diagram(const job& j, const typed_problem<T, 3>& p, const gv::solve_options& opt);

/// Called in a catch block around a library solve of @p j (a branching run's): rethrows the library's
/// std::invalid_argument as a usage_error naming the seed file and line (a seed outside, in empty
/// material, two seeds in one copy), and gv::overflow_error as a usage_error suggesting --precision
/// double; anything else as it is.
[[noreturn]] void rethrow_solve_error(const job& j);

/// What `shape-functions --coarsen N` asks of a branching run: its shape arguments and, when not null
/// and not empty, the fine voxels of --at (filled by the command's check, before the solve).
struct branching_shapes {
  const shape_args* shape = nullptr;
  const std::vector<gv::coord<3>>* at = nullptr;
};

/// What a command does after the diagram (the shape functions), in T.
template <class T>
using after_diagram = std::function<void(const job&, const gv::diagram<T, 3>&, output_dir&, progress_bar&)>;

/// Loads the job, runs `check(job)` (a command's own checks that need the job, before any work; may
/// be empty), solves the diagram, writes the voronoi outputs, then `more(job, diagram, out, bar)`
/// (the shape functions; more_float or more_double by the job's precision), moves the outputs into
/// place and prints the summary line. A branching run (--coarsen) solves on the branching grid instead
/// and, with @p bs's shape arguments, computes the shape functions there (`more` is not called).
int solve_and_write(const char* command, const arguments& a, const std::function<void(const job&)>& check,
                    const after_diagram<float>& more_float, const after_diagram<double>& more_double,
                    const branching_shapes& bs = {});

}  // namespace gvcli

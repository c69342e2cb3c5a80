#pragma once
// What `voronoi` and `shape-functions` share: the options, loading the field and the seeds, picking
// the backend, solving the diagram with seed errors reported by file and line, writing the outputs.

#include "arguments.hpp"
#include "backends.hpp"
#include "output_dir.hpp"
#include "outputs.hpp"
#include "progress_bar.hpp"
#include "solve.hpp"

#include <functional>
#include <memory>
#include <set>
#include <string>
#include <type_traits>
#include <vector>

namespace gvcli {

/// Everything a solve needs, parsed (the seeds are checked by the library when solving).
struct job {
  std::string stiffness_path, seeds_path, metric = "min_stiffness", out;
  int connectivity = 26;
  const backend* solver = nullptr;
  /// `--threads N`, 0 without it (solve_options::threads).
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
  problem_spec<T> spec() const {
    return {field_in<T>(), seeds, metric, connectivity, threads, nullptr, cuts.get()};
  }
  /// How its pictures are titled (metric, neighbours; lengths in the volume's unit).
  picture_context pictures() const { return {metric, "LENGTH", connectivity}; }
};

/// The options of voronoi plus @p extra (shape-functions adds its own).
std::set<std::string> solve_options(std::set<std::string> extra = {});
/// The flags (options without a value) of voronoi and shape-functions.
std::set<std::string> solve_flags();
/// The options of voronoi and shape-functions that may be repeated (--cut).
std::set<std::string> solve_repeatable();

job load_job(const arguments& a);

/// What `shape-functions` and `cut --method` read about the shape functions.
struct shape_args {
  gv::shape_method method = gv::shape_method::distance_ratio;
  int k = 4;             ///< `--nodes-per-voxel K`, 1..64 (default 4)
  int picture_node = 0;  ///< `--picture-node N` (default 0), checked against the nodes by check_picture_node()
  /// The library's options for them (progress and threads left to the caller).
  gv::shape_options options() const {
    gv::shape_options o;
    o.method = method;
    o.max_nodes_per_voxel = k;
    return o;
  }
};
/// The options of shape_args: --method, --nodes-per-voxel, --picture-node.
std::set<std::string> shape_arg_options();
/// `--method M`: distance-ratio (or distance_ratio), sibson or laplace; else a usage_error.
gv::shape_method parse_method(const std::string& m);
/// --method (required), --nodes-per-voxel and --picture-node of @p a; a usage_error when one is bad.
shape_args parse_shape_args(const arguments& a);
/// A usage_error when --picture-node names no node of @p j.
void check_picture_node(const shape_args& s, const job& j);

/// Calls f(T{}) with T = double when @p j runs in double, else float.
template <class F>
decltype(auto) with_precision(const job& j, F&& f) {
  if (j.in_double) return f(double{});
  return f(float{});
}

/// The diagram of @p j on its backend, in T; the library's seed errors (outside, masked, duplicate)
/// come back as a usage_error naming the seed file and line, and so does a seed at geodesic distance 0
/// from another (a zero-cost path joins them), which would have no cell of its own, and a distance
/// that overflows T (geovoronoi::overflow_error: exit 2, suggesting --precision double).
/// @p progress (may be empty) receives the solve's fraction done.
template <class T>
gv::diagram<T, 3> solve_diagram(const job& j, const std::function<bool(double)>& progress = nullptr);
/// The same for the problem @p s (a variant of j.spec<T>(): `cut` solves the problem before and after
/// its change), with the job's seed file named in errors.
template <class T>
gv::diagram<T, 3> solve_diagram(const job& j, const problem_spec<T>& s);

/// What a command does after the diagram (the shape functions), in T.
template <class T>
using after_diagram = std::function<void(const job&, const gv::diagram<T, 3>&, output_dir&, progress_bar&)>;

/// Loads the job, runs `check(job)` (a command's own checks that need the job, before any work; may
/// be empty), solves the diagram, writes the voronoi outputs, then `more(job, diagram, out, bar)`
/// (the shape functions; more_float or more_double by the job's precision), moves the outputs into
/// place and prints the summary line.
int solve_and_write(const char* command, const arguments& a, const std::function<void(const job&)>& check,
                    const after_diagram<float>& more_float, const after_diagram<double>& more_double);

}  // namespace gvcli

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
#include <set>
#include <string>
#include <vector>

namespace gvcli {

/// Everything a solve needs, parsed (the seeds are checked by the library when solving).
struct job {
  std::string stiffness_path, seeds_path, metric = "min_stiffness", out;
  int connectivity = 26;
  const backend* solver = nullptr;
  gv::image<float, 3> field;
  std::vector<gv::coord<3>> seeds;
  std::vector<int> seed_lines;  ///< the seed file's line of each seed
  problem_spec spec() const { return {field, seeds, metric, connectivity}; }
  /// How its pictures are titled (metric, neighbours; lengths in the volume's unit).
  picture_context pictures() const { return {metric, "LENGTH", connectivity}; }
};

/// The options of voronoi plus @p extra (shape-functions adds its own).
std::set<std::string> solve_options(std::set<std::string> extra = {});
/// The flags (options without a value) of voronoi and shape-functions.
std::set<std::string> solve_flags();

job load_job(const arguments& a);

/// The diagram of @p j on its backend; the library's seed errors (outside, masked, duplicate) come
/// back as a usage_error naming the seed file and line, and so does a seed at geodesic distance 0
/// from another (a zero-cost path joins them), which would have no cell of its own.
gv::diagram<float, 3> solve_diagram(const job& j);

/// Loads the job, runs `check(job)` (a command's own checks that need the job, before any work; may
/// be empty), solves the diagram, writes the voronoi outputs, then `more(job, diagram, out, bar)`
/// (the shape functions), moves the outputs into place and prints the summary line.
int solve_and_write(const char* command, const arguments& a, const std::function<void(const job&)>& check,
                    const std::function<void(const job&, const gv::diagram<float, 3>&, output_dir&, progress_bar&)>& more);

}  // namespace gvcli

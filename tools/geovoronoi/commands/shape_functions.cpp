// geovoronoi shape-functions: Distance Ratio, Sibson or Laplace weights of the seeds (nodes).
#include "../command.hpp"
#include "../job.hpp"
#include "../outputs.hpp"
#include "../seed_file.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <type_traits>

namespace gvcli {

namespace {

/// The points of --at FILE as voxels of @p g: CSV rows like the seed file's, voxel indices, or world
/// coordinates rounded to the nearest voxel centre with --world (grid::nearest_voxel, as the seeds and
/// the library's shape_functions_at for world points). A point outside the grid is a usage error
/// naming its line.
std::vector<gv::coord<3>> read_points(const std::string& path, bool world, const gv::grid<3>& g) {
  const std::vector<seed_row> rows = read_seed_rows(path, !world, "points file");
  std::vector<gv::coord<3>> out;
  out.reserve(rows.size());
  for (const auto& r : rows) {
    const std::string where = path + ":" + std::to_string(r.line) + ": point ";
    if (r.count == 2 && g.extent(2) != 1)
      throw usage_error(where + "has 2 values but the volume has " + std::to_string(g.extent(2)) + " slices");
    gv::coord<3> c;
    if (world) {
      try {  // the point as given, not a voxel it would round to
        c = g.checked_nearest_voxel({r.x[0], r.x[1], r.x[2]});
      } catch (const std::invalid_argument& e) {
        throw usage_error(path + ":" + std::to_string(r.line) + ": the point at " + e.what());
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(r.x[k]) > 9e15) throw usage_error(where + "coordinate out of range");
        c[k] = gv::index_t(r.x[k]);
      }
    }
    if (!g.contains(c))
      throw usage_error(where + "(" + std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]) +
                        ") lies outside the grid " + std::to_string(g.extent(0)) + "x" + std::to_string(g.extent(1)) +
                        "x" + std::to_string(g.extent(2)));
    out.push_back(c);
  }
  return out;
}

/// "7 min", "1 h 05 min", "40 s".
std::string duration_text(double s) {
  char buf[48];
  if (s < 90) std::snprintf(buf, sizeof buf, "%.0f s", s);
  else if (s < 5400) std::snprintf(buf, sizeof buf, "%.0f min", s / 60);
  else std::snprintf(buf, sizeof buf, "%d h %02d min", int(s / 3600), int(s / 60) % 60);
  return buf;
}

/// Sibson and Laplace search a new cell per voxel; where the field is not constant (no distance-table
/// shortcut) that is minutes to hours on a large volume. Before the full run, time the same queries on
/// two samples (with the run's options @p opt) and, when the extrapolation to every voxel on the run's
/// @p threads passes a minute, say so in one line up front. A sample is whole 4x4x2 blocks of voxels
/// around evenly spread queries: the full run searches such blocks together (32 queries per search
/// where the library's lane search applies), and scattered single voxels would time one search per
/// query, several times the cost per query of the run (8x on the steak). The larger sample holds the
/// smaller one and as many blocks again; their difference cancels the fixed set-up cost.
template <class T>
void warn_if_long(const typed_problem<T, 3>& p, const gv::diagram<T, 3>& d, gv::shape_options opt, const char* method,
                  unsigned threads, progress_bar& bar) {
  auto is_query = [&](gv::index_t v) {  // its weights come from a search: reached, not a node
    return d.distance[v] > T(0) && d.distance[v] < std::numeric_limits<T>::infinity();
  };
  std::vector<gv::index_t> queries;
  for (gv::index_t v = 0; v < d.distance.size(); ++v)
    if (is_query(v)) queries.push_back(v);
  if (queries.size() < 2000) return;  // a few thousand queries: seconds at most
  constexpr std::size_t blocks = 24;  // in the smaller sample; the larger has twice as many
  const auto& g = d.distance.geometry();
  std::vector<gv::coord<3>> at;
  auto add_blocks = [&](std::size_t first) {  // the blocks of anchors first, first + 2, ... of 2 x blocks
    for (std::size_t i = first; i < 2 * blocks; i += 2) {
      const auto c = g.coords(queries[(2 * i + 1) * queries.size() / (4 * blocks)]);
      const gv::index_t x0 = c[0] & ~gv::index_t(3), y0 = c[1] & ~gv::index_t(3), z0 = c[2] & ~gv::index_t(1);
      for (gv::index_t z = z0; z < std::min(z0 + 2, g.extent(2)); ++z)
        for (gv::index_t y = y0; y < std::min(y0 + 4, g.extent(1)); ++y)
          for (gv::index_t x = x0; x < std::min(x0 + 4, g.extent(0)); ++x)
            if (is_query(g.index({x, y, z}))) at.push_back({x, y, z});
    }
  };
  auto time_sample = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    (void)p.shape_functions_at(d, at, opt);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  opt.progress = nullptr;
  opt.stats = nullptr;
  add_blocks(0);
  const std::size_t n_small = at.size();
  const double t_small = time_sample();
  add_blocks(1);
  const std::size_t n_large = at.size();
  const double t_large = time_sample();
  const double per_query = n_large > n_small && t_large > t_small ? (t_large - t_small) / double(n_large - n_small)
                                                                   : t_large / double(n_large);
  const double estimate = per_query * double(queries.size()) / double(std::max(1u, threads));
  if (estimate < 60.0) return;
  // Sibson writes the rows of queries whose new cell stays in their own node's cell without a search
  // (shape_options::skip_single_owner_rows), which these small samples do not trigger (the library
  // does that for 1/64 of the grid or more): for Sibson the estimate is an upper bound (2.5x on the steak)
  const bool upper = std::strcmp(method, "sibson") == 0 && opt.skip_single_owner_rows;
  bar.note("geovoronoi shape-functions: note: " + std::string(method) + " on " + std::to_string(queries.size()) +
           (upper ? " voxels is estimated at up to about " : " voxels is estimated at about ") +
           duration_text(estimate) +
           " here (timed on a sample; the field is not constant, so every voxel's new cell is a geodesic "
           "search); --at FILE computes chosen points only, distance-ratio is much cheaper");
}

/// The same for --at runs of Sibson and Laplace: their cost is one search per point (points scattered
/// over a volume share no search), so time two evenly spread samples of the points themselves (16 and
/// 32, the larger holding the smaller: their difference cancels the set-up cost) and extrapolate the
/// time per point to all of them on the run's @p threads; a note up front when that passes a minute.
template <class T>
void warn_if_long_at(const typed_problem<T, 3>& p, const gv::diagram<T, 3>& d, gv::shape_options opt,
                     const char* method, const std::vector<gv::coord<3>>& points, unsigned threads, progress_bar& bar) {
  if (points.size() < 2000) return;  // a few thousand points: seconds to a minute
  opt.progress = nullptr;
  opt.stats = nullptr;
  std::vector<gv::coord<3>> at;
  auto add = [&](std::size_t first) {  // points (2i + 1) / 64 of the list for i = first, first + 2, ...
    for (std::size_t i = first; i < 32; i += 2) at.push_back(points[(2 * i + 1) * points.size() / 64]);
  };
  auto time_sample = [&] {
    const auto t0 = std::chrono::steady_clock::now();
    (void)p.shape_functions_at(d, at, opt);
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  };
  add(0);
  const std::size_t n_small = at.size();
  const double t_small = time_sample();
  add(1);
  const std::size_t n_large = at.size();
  const double t_large = time_sample();
  const double per_point = t_large > t_small ? (t_large - t_small) / double(n_large - n_small) : t_large / double(n_large);
  const double estimate = per_point * double(points.size()) / double(std::max(1u, threads));
  if (estimate < 60.0) return;
  bar.note("geovoronoi shape-functions: note: " + std::string(method) + " at " + std::to_string(points.size()) +
           " points is estimated at about " + duration_text(estimate) +
           " here (timed on a sample of the points: one geodesic search per point)");
}

int run(const std::vector<std::string>& args) {
  auto names = shape_arg_options();
  names.insert("--at");
  const arguments a(args, solve_options(names), solve_flags(), solve_repeatable());
  const shape_args sa = parse_shape_args(a);
  const auto method = sa.method;
  const std::string at_path = a.get("--at", "");
  std::vector<gv::coord<3>> at;
  // checked before any work: the node must exist, the points must parse and lie in the grid
  auto check = [&](const job& j) {
    if (!at_path.empty()) at = read_points(at_path, a.has("--world"), j.geometry());
    check_picture_node(sa, j);
  };
  auto more = [&](const job& j, const auto& d, output_dir& out, progress_bar& bar) {
    bar.update(method_name(method), 0.0);
    gv::shape_options opt = sa.options(j);
    opt.progress = [&](double f) {
      bar.set_fraction(f);
      return true;
    };
    using T = typename std::decay_t<decltype(d.distance)>::value_type;
    const auto& p = j.problem<T>();
    if (!at.empty()) {  // only the chosen points' rows
      if (method != gv::shape_method::distance_ratio) {
        bar.update("estimating the work");
        const unsigned threads = std::string(j.solver->name) == "thrust" ? thrust_threads() : 1u;
        warn_if_long_at(p, d, opt, method_name(method), at, threads, bar);
        bar.update(method_name(method), 0.0);
      }
      const auto w = p.shape_functions_at(d, at, opt);
      bar.update("writing");
      write_shape_at(out.subdir("."), w);
      return;
    }
    if (method != gv::shape_method::distance_ratio) {
      bar.update("estimating the work");
      const unsigned threads = std::string(j.solver->name) == "thrust" ? thrust_threads() : 1u;
      warn_if_long(p, d, opt, method_name(method), threads, bar);
      bar.update(method_name(method), 0.0);
    }
    const auto w = p.shape_functions(d, opt);
    bar.update("writing");
    write_shape(out.subdir("."), w, d, sa.picture_node, j.pictures(), method_name(method));
  };
  // --coarsen: the branching run computes the weights itself, at the copies or at the points (fine voxels)
  return solve_and_write("shape-functions", a, check, more, more, branching_shapes{&sa, &at});
}

}  // namespace

const command shape_functions_command = {
    "shape-functions", "Distance Ratio, Sibson or Laplace shape functions of the seeds (nodes)",
    "usage: geovoronoi shape-functions (--stiffness FILE | --mesh MESH... --voxel-size S) --seeds FILE\n"
    "                                  --method M --out DIR [options]\n"
    "\n"
    "The Voronoi shape functions of the nodes (the seeds): for every voxel, at most K (node, weight)\n"
    "pairs, weights >= 0 summing to 1 inside the object.\n"
    "\n"
    "options: those of `geovoronoi voronoi` (see `geovoronoi help voronoi`), and\n"
    "  --method M          distance-ratio, sibson or laplace (required)\n"
    "  --nodes-per-voxel K the most nodes a voxel keeps, 1..64 (default: 4)\n"
    "  --picture-node N    the node whose weight weight_node<N>.png shows, 0 to nodes - 1 (default: 0)\n"
    "  --at FILE           weights only at the points of FILE (CSV, one point per line: voxel indices\n"
    "                      i,j,k, or world coordinates with --world, rounded to the nearest voxel\n"
    "                      centre); writes the weights_at files below instead of the per-voxel ones\n"
    "  --stiffness FILE, --seeds FILE, --out DIR (required); --metric M (default: min_stiffness),\n"
    "  --connectivity N (default: 26), --backend B (default: the fastest built one that runs here),\n"
    "  --threads N (default: OMP_NUM_THREADS), --precision P (default: float; double computes\n"
    "  and writes the distance and the weights in double),\n"
    "  --world, --extrude N (default: 1), --cut MESH (repeatable; no path crosses the cut), --help,\n"
    "  --mesh MESH[:VALUE[:LABEL]]... with --voxel-size S or --voxels NX,NY,NZ (instead of --stiffness;\n"
    "  --pad N, --rotate, --winding)\n"
    "  --coarsen N         the weights on the branching grid of the field coarsened by N (see `geovoronoi\n"
    "                      help voronoi`): one row per copy, painted on the fine grid; seeds and --at\n"
    "                      points are fine voxels (world points with --world); --reduction R; backends\n"
    "                      seq (the default) and thrust; --cut MESH splits the copies it crosses\n"
    "\n"
    "writes, in DIR: the files of `geovoronoi voronoi`, and\n"
    "  indices.mhd/.raw    K interleaved channels (ITK, ParaView, Slicer): node index + 1, 0 for an\n"
    "                      empty slot\n"
    "  weights.mhd/.raw    K interleaved channels: the weight of that node\n"
    "  indices_sofa_planar.mhd/.raw, weights_sofa_planar.mhd/.raw\n"
    "                      the same values in SOFA's planar layout (each channel's volume in turn)\n"
    "  weights.vti         label, and K-component arrays weights and nodes (0-based, -1 empty) for\n"
    "                      ParaView\n"
    "  weights_indptr.npy, weights_indices.npy, weights_data.npy\n"
    "                      the voxels x nodes matrix in CSR form (scipy.sparse.csr_matrix)\n"
    "  weight_node<N>.png  node N's weight (--picture-node) on the three mid-slices\n"
    "with --coarsen, also copies.npz (see `geovoronoi help voronoi`) and\n"
    "  copy_weights.npz    the weights per copy: node (int32) and weight, shape (copies, K), copy_cell,\n"
    "                      copy_voxel, voxel_count, fine_copy, seed_copy, k, nodes, coarse_shape,\n"
    "                      factor; the files above hold them painted at the fine resolution\n"
    "with --at FILE, instead of the per-voxel weight files:\n"
    "  weights_at_indptr.npy, weights_at_indices.npy, weights_at_data.npy\n"
    "                      the points x nodes matrix in CSR form (row i: line i of FILE's points)\n"
    "  weights_at.csv      point,node,weight per line (point: 0-based row of FILE's points)\n"
    "\n"
    "example:\n"
    "  geovoronoi shape-functions --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv \\\n"
    "             --method sibson --nodes-per-voxel 4 --out weights\n",
    run};

}  // namespace gvcli

// geovoronoi cut: the diagram before and after a change (cut surfaces, a carved box); the one after
// comes from the library's incremental update (update.hpp) and is checked, bit for bit, against a
// full recompute of the changed problem, and both times are printed.
#include "../change.hpp"
#include "../command.hpp"
#include "../job.hpp"
#include "../outputs.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace gvcli {

namespace {

using geovoronoi::index_t;

/// `--carve BOX`: the voxels it removes (sorted) and their index bounding box.
struct carve_box {
  std::vector<index_t> voxels;
  gv::coord<3> lo{}, hi{};
};

/// Parses `x0:x1,y0:y1,z0:z1`: voxel indices, both ends included (0 <= x0 <= x1 < extent); with
/// @p world, world coordinates of a closed axis-aligned box, which takes every voxel whose centre
/// (grid::world) lies in it. A box that is malformed, leaves the grid or takes no voxel is a usage error.
carve_box parse_carve(const std::string& text, bool world, const gv::grid<3>& g) {
  const std::string what = "--carve '" + text + "'";
  const char* axis_name[3] = {"x", "y", "z"};
  std::array<std::array<double, 2>, 3> r{};
  std::size_t pos = 0;
  for (int a = 0; a < 3; ++a) {
    const std::size_t comma = text.find(',', pos);
    if ((a < 2) != (comma != std::string::npos))
      throw usage_error(what + ": expected three ranges " + (world ? "X0:X1,Y0:Y1,Z0:Z1 (world coordinates)"
                                                                   : "x0:x1,y0:y1,z0:z1 (voxel indices)"));
    const std::string part = text.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    const std::size_t colon = part.find(':');
    if (colon == std::string::npos || part.find(':', colon + 1) != std::string::npos)
      throw usage_error(what + ": the " + axis_name[a] + " range '" + part + "' is not FROM:TO");
    for (int e = 0; e < 2; ++e) {
      const std::string num = e == 0 ? part.substr(0, colon) : part.substr(colon + 1);
      char* end = nullptr;
      double x = 0;
      if (world) {
        x = std::strtod(num.c_str(), &end);
        if (num.empty() || *end != '\0' || !std::isfinite(x))
          throw usage_error(what + ": '" + num + "' in the " + axis_name[a] + " range is not a finite number");
      } else {
        const long long i = std::strtoll(num.c_str(), &end, 10);
        if (num.empty() || *end != '\0')
          throw usage_error(what + ": '" + num + "' in the " + axis_name[a] + " range is not a voxel index (integer; "
                                   "world coordinates need --world)");
        x = double(i);
      }
      r[std::size_t(a)][std::size_t(e)] = x;
    }
    if (r[std::size_t(a)][0] > r[std::size_t(a)][1])
      throw usage_error(what + ": the " + axis_name[a] + " range runs backwards (FROM must be <= TO)");
    if (!world && (r[std::size_t(a)][0] < 0 || r[std::size_t(a)][1] >= double(g.extent(a))))
      throw usage_error(what + ": the " + axis_name[a] + " range leaves the grid (indices 0 to " +
                        std::to_string(g.extent(a) - 1) + ")");
    pos = comma + 1;
  }
  carve_box b;
  b.lo = {g.extent(0), g.extent(1), g.extent(2)};
  b.hi = {-1, -1, -1};
  for (index_t v = 0; v < g.size(); ++v) {
    const auto c = g.coords(v);
    bool in = true;
    if (world) {
      const auto p = g.world(c);
      for (int a = 0; a < 3 && in; ++a) in = p[a] >= r[std::size_t(a)][0] && p[a] <= r[std::size_t(a)][1];
    } else {
      for (int a = 0; a < 3 && in; ++a) in = double(c[a]) >= r[std::size_t(a)][0] && double(c[a]) <= r[std::size_t(a)][1];
    }
    if (!in) continue;
    b.voxels.push_back(v);
    for (int a = 0; a < 3; ++a) b.lo[a] = std::min(b.lo[a], c[a]), b.hi[a] = std::max(b.hi[a], c[a]);
  }
  if (b.voxels.empty()) throw usage_error(what + ": the box holds no voxel centre of the grid");
  return b;
}

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

template <class T>
void cut_in(const job& j, const carve_box* carve, output_dir& out, progress_bar& bar) {
  const auto& field = j.field_in<T>();
  gv::image<T, 3> carved_field;
  if (carve) {  // -1 is outside under every metric's domain rule (stiffness > 0, cost >= 0)
    carved_field = field;
    for (const index_t v : carve->voxels) carved_field[v] = T(-1);
  }
  const gv::image<T, 3>& after_field = carve ? carved_field : field;
  const problem_spec<T> before_spec{field, j.seeds, j.metric, j.connectivity, j.threads, nullptr, nullptr, true};
  const problem_spec<T> cut_spec{field, j.seeds, j.metric, j.connectivity, j.threads, nullptr, j.cuts.get(), true};
  const problem_spec<T> after_spec{after_field, j.seeds, j.metric, j.connectivity, j.threads, nullptr, j.cuts.get(), true};

  bar.update("before");
  const auto before = solve_diagram(j, before_spec);
  bar.update("full recompute");
  auto t0 = std::chrono::steady_clock::now();
  const auto full = solve_diagram(j, after_spec);
  const double t_full = since(t0);
  bar.update("update");
  auto upd = before;
  std::size_t invalidated = 0;
  t0 = std::chrono::steady_clock::now();
  try {
    if (j.cut_set) invalidated += update_cuts(cut_spec, *j.cut_set, upd).invalidated;
    if (carve) invalidated += update_carving(after_spec, carve->voxels, upd).invalidated;
  } catch (const std::invalid_argument& e) {  // checked before: would be a bug in the tool or the library
    throw runtime_failure(std::string("internal error in the incremental update: ") + e.what());
  }
  const double t_update = since(t0);
  require_equal(upd, full);

  bar.update("writing");
  const auto pc = j.pictures();
  write_voronoi(out.subdir("before"), before, field, pc);
  write_voronoi(out.subdir("after"), upd, after_field, pc);
  const gv::coord<3> none{-1, -1, -1};
  const std::size_t n_changed = write_change(out.subdir("."), before, upd, field, after_field, j.cut_set.get(),
                                             carve ? carve->lo : none, carve ? carve->hi : none, pc);
  std::printf("geovoronoi cut: %zu cut edges from %zu mesh(es), %zu carved voxels; %zu voxels changed\n",
              j.cut_edges, j.cut_paths.size(), carve ? carve->voxels.size() : std::size_t(0), n_changed);
  std::printf("  incremental update %9.4f s  (library update(), host; %zu voxels re-solved)\n", t_update, invalidated);
  std::printf("  full recompute     %9.4f s  (backend %s, with parents)  %.1fx; identical bit for bit "
              "(distance, label, parent)\n",
              t_full, j.solver->name, t_update > 0 ? t_full / t_update : 0.0);
  std::fflush(stdout);
}

int run(const std::vector<std::string>& args) {
  const arguments a(args, solve_options({"--carve"}), solve_flags(), solve_repeatable());
  if (!a.has("--cut") && !a.has("--carve")) throw usage_error("cut needs a change: --cut MESH and/or --carve BOX");
  progress_bar bar("geovoronoi cut");
  bar.update("reading");
  const job j = load_job(a);
  carve_box carve;
  if (a.has("--carve")) {
    carve = parse_carve(a.get("--carve"), a.has("--world"), j.geometry());
    const auto& g = j.geometry();
    for (std::size_t i = 0; i < j.seeds.size(); ++i)
      if (g.contains(j.seeds[i]) && std::binary_search(carve.voxels.begin(), carve.voxels.end(), g.index(j.seeds[i])))
        throw usage_error("--carve '" + a.get("--carve") + "' removes the seed on line " +
                          std::to_string(j.seed_lines[i]) + " of " + j.seeds_path +
                          " (a node cannot be carved; remove it from the seed file)");
  }
  std::vector<std::string> inputs{j.stiffness_path, j.seeds_path};
  inputs.insert(inputs.end(), j.cut_paths.begin(), j.cut_paths.end());
  output_dir out(j.out, inputs, "geovoronoi cut");
  const carve_box* c = a.has("--carve") ? &carve : nullptr;
  if (j.in_double)
    cut_in<double>(j, c, out, bar);
  else
    cut_in<float>(j, c, out, bar);
  out.commit();
  bar.finish();
  summary("cut", j.geometry(), j.seeds.size(), j.solver->name, bar.seconds(), j.out);
  return 0;
}

}  // namespace

const command cut_command = {
    "cut", "a diagram before and after a cut or carving: incremental update vs full recompute",
    "usage: geovoronoi cut --stiffness FILE --seeds FILE (--cut MESH | --carve BOX)... --out DIR [options]\n"
    "\n"
    "Solves the Voronoi diagram, applies a change (cut surfaces and/or a carved box), updates the\n"
    "diagram incrementally (only the voxels whose shortest path crossed the change are re-solved),\n"
    "recomputes the changed problem from scratch on --backend, checks that both agree bit for bit\n"
    "(distance, label and parent; exit 1 if not) and prints both times.\n"
    "\n"
    "options:\n"
    "  --stiffness FILE    the field: .mhd/.mha (MetaImage), .npy, or .pgm/.ppm (required)\n"
    "  --seeds FILE        CSV, one seed per line: i,j,k voxel indices (x,y,z with --world) (required)\n"
    "  --out DIR           output folder (required): written aside and swapped in as a whole\n"
    "  --cut MESH          a cut surface, .stl or .obj in world coordinates: the grid edges it meets\n"
    "                      are removed; repeatable (at least one --cut or a --carve is required)\n"
    "  --carve BOX         voxels removed from the domain: x0:x1,y0:y1,z0:z1, voxel indices with both\n"
    "                      ends included (0 <= x0 <= x1 < size along x, ...); with --world, world\n"
    "                      coordinates of a closed box, taking every voxel whose centre lies in it.\n"
    "                      Carved voxels get the field value -1 (outside); the box may hold no seed\n"
    "  --metric M          min_stiffness, mean_stiffness, mean_cost or uniform (default: min_stiffness)\n"
    "  --connectivity N    6, 18 or 26 neighbours (default: 26)\n"
    "  --backend B         seq, thrust or cuda: runs the two full solves (default: the fastest built one\n"
    "                      that runs here); the incremental update is the library's host algorithm\n"
    "  --threads N         OpenMP threads of the thrust backend, 1 to 4 x the hardware threads\n"
    "  --world             seeds and --carve are physical x,y,z coordinates (default: voxel indices)\n"
    "  --extrude N         repeat a .pgm/.ppm picture into N slices along z (default: 1)\n"
    "  --precision P       float, double or auto (default: float), as for voronoi\n"
    "  --help              this text\n"
    "\n"
    "writes, in DIR:\n"
    "  before/             the files of `geovoronoi voronoi` on the problem without the change\n"
    "  after/              the same after the change (the updated diagram; equal to `voronoi --cut`)\n"
    "  changed.mhd/.raw    1 where the distance or the label changed, else 0 (MET_UCHAR)\n"
    "  cut.png             cells before | after on the slices through the middle of the change, the\n"
    "                      cut drawn in red, changed voxels outlined in white\n"
    "  .geovoronoi-output  the marker that lets the next run with this --out replace the folder\n"
    "\n"
    "example:\n"
    "  geovoronoi cut --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv --cut demo-out/cut/blade.obj\n"
    "                 --out cut-out\n",
    run};

}  // namespace gvcli

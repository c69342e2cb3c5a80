// geovoronoi cut: the diagram before and after a change (cut surfaces, a carved box); the one after
// comes from the library's incremental update (update.hpp) and is checked, bit for bit, against a
// full recompute of the changed problem, and both times are printed. With --method, the same for the
// shape functions (shape_update.hpp).
#include "../branching.hpp"
#include "../change.hpp"
#include "../command.hpp"
#include "../job.hpp"
#include "../meshes.hpp"
#include "../outputs.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iterator>
#include <cstring>
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

/// The shape functions before and after the change (cut --method): the ones after from the library's
/// update, checked against a full recompute on the backend; writes before/, after/ and
/// changed_weights.mhd and prints both times. @p before_p and @p after_p are the problems without and
/// with the change.
template <class T>
void cut_shape(const job& j, const shape_args& sa, const typed_problem<T, 3>& before_p,
               const typed_problem<T, 3>& after_p, const gv::diagram<T, 3>& before, const gv::diagram<T, 3>& after,
               const gv::change<3>& change, output_dir& out, progress_bar& bar) {
  const char* method = method_name(sa.method);
  gv::shape_options opt = sa.options(j);
  opt.progress = [&](double f) {
    bar.set_fraction(f);
    return true;
  };
  bar.update(std::string(method) + " before", 0.0);
  const auto w_before = before_p.shape_functions(before, opt);
  bar.update(std::string(method) + " full recompute", 0.0);
  auto t0 = std::chrono::steady_clock::now();
  const auto w_full = after_p.shape_functions(after, opt);
  const double t_full = since(t0);
  bar.update(std::string(method) + " update", 0.0);
  auto w_after = w_before;
  gv::shape_update_stats st;
  t0 = std::chrono::steady_clock::now();
  try {
    st = after_p.update_shape_functions_in_place(before, after, w_after, change, opt);
  } catch (const std::invalid_argument& e) {  // the inputs were checked: a bug in the tool or the library
    throw runtime_failure(std::string("internal error in the shape functions' update: ") + e.what());
  }
  const double t_update = since(t0);
  require_equal(w_after, w_full);

  bar.update("writing");
  const auto pc = j.pictures();
  write_shape(out.subdir("before"), w_before, before, sa.picture_node, pc, method);
  write_shape(out.subdir("after"), w_after, after, sa.picture_node, pc, method);
  const std::size_t n_changed = write_changed_weights(out.subdir("."), w_before, w_after);
  std::printf("  weights update     %9.4f s  (%s, library update_shape_functions() on backend %s; %zu of %zu rows "
              "recomputed%s, %zu changed)\n",
              t_update, method, backend_name(after_p.shape_update_backend()), st.recomputed, st.rows,
              st.full ? " (all: no smaller set is proven)" : "", n_changed);
  std::printf("  weights recompute  %9.4f s  (%s, shape_functions() on backend %s)  %.1fx; identical bit for bit "
              "(node and weight of every slot)\n",
              t_full, method, j.solver->name, t_update > 0 ? t_full / t_update : 0.0);
  std::fflush(stdout);
}

template <class T>
void cut_in(const job& j, const carve_box* carve, const shape_args* shape, output_dir& out, progress_bar& bar) {
  const auto& field = j.field_in<T>();
  gv::image<T, 3> carved_field;
  if (carve) {  // -1 is outside under every metric's domain rule (stiffness > 0, cost >= 0)
    carved_field = field;
    for (const index_t v : carve->voxels) carved_field[v] = T(-1);
  }
  const gv::image<T, 3>& after_field = carve ? carved_field : field;
  // the problem without the change, with the cuts on the field before (the first update's), and
  // with the whole change
  const auto before_p = j.problem_on<T>(field, false);
  const auto cut_p = j.problem_on<T>(field, true);
  const auto after_p = j.problem_on<T>(after_field, true);
  gv::solve_options opt = j.options();
  opt.with_parent = true;

  bar.update("before");
  const auto before = solve_diagram(j, *before_p, opt);
  bar.update("full recompute");
  auto t0 = std::chrono::steady_clock::now();
  const auto full = solve_diagram(j, *after_p, opt);
  const double t_full = since(t0);
  bar.update("update");
  auto upd = before;
  std::size_t invalidated = 0;
  t0 = std::chrono::steady_clock::now();
  try {  // the cut edges, then the carving: one update each
    if (j.cut_set) {
      gv::change<3> c;
      c.cut = *j.cut_set;
      invalidated += cut_p->update_in_place(upd, c).invalidated;
    }
    if (carve) {
      gv::change<3> c;
      c.carved = carve->voxels;
      invalidated += after_p->update_in_place(upd, c).invalidated;
    }
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
  if (shape) {
    gv::change<3> change;
    if (j.cut_set) change.cut = *j.cut_set;
    if (carve) change.carved = carve->voxels;
    cut_shape(j, *shape, *before_p, *after_p, before, upd, change, out, bar);
  }
}

/// The promise of the branching updates: @p upd equals the full recompute @p full bit for bit (per
/// copy distance, label and parent; with weights, node and weight of every slot). A difference is a
/// bug in the library: runtime_failure (exit 1).
template <class T>
void require_equal_copies(const branching_solution<T>& upd, const branching_solution<T>& full) {
  const auto fail = [](const std::string& what) {
    throw runtime_failure("internal error: the incremental update on the branching grid differs from the full "
                          "recompute in " + what + "; please report this with the inputs");
  };
  const auto& a = upd.copies;
  const auto& b = full.copies;
  if (a.distance.size() != b.distance.size() || a.label != b.label || a.parent != b.parent || a.seeds != b.seeds)
    fail("the copies' labels, parents or seeds");
  if (std::memcmp(a.distance.data(), b.distance.data(), a.distance.size() * sizeof(T)) != 0)
    fail("the copies' distances");
  if (upd.has_weights != full.has_weights) fail("whether it has weights");
  if (!full.has_weights) return;
  const auto& u = upd.weights;
  const auto& f = full.weights;
  if (u.copies != f.copies || u.k != f.k || u.nodes != f.nodes || u.node != f.node || u.weight.size() != f.weight.size() ||
      std::memcmp(u.weight.data(), f.weight.data(), u.weight.size() * sizeof(T)) != 0)
    fail("the weights (node or weight of a slot)");
}

/// `cut --coarsen N`: the branching grid's diagram (and with --method its weights) before and after
/// the cut edges of --cut on the fine image: the update from the library's update() and
/// update_shape_functions(), checked bit for bit against a full recompute on the cut grid; before/,
/// after/ (fine-resolution files, copies.npz, copy_weights.npz), changed.mhd, cut.png,
/// changed_weights.mhd. Returns the copies after the cut.
template <class T>
std::size_t cut_branching_in(const job& j, const shape_args* shape, output_dir& out, progress_bar& bar) {
  const auto& field = j.field_in<T>();
  const branching_key key{j.solver->id, j.metric, j.connectivity, j.coarsen, j.reduction};
  gv::shape_options so;
  if (shape) so = shape->options(j);
  bar.update("before, full recompute, update");
  const auto r = [&] {
    try {
      return cut_branching<T>(key, gv::image_view<const T, 3>(field.geometry(), field.data()), j.seeds, j.options(),
                              *j.cut_set, shape ? &so : nullptr);
    } catch (...) {
      rethrow_solve_error(j);
    }
  }();
  require_equal_copies(r.updated, r.full);

  bar.update("writing");
  const auto pc = j.pictures();
  for (const auto& [dir, s] : {std::pair<const char*, const branching_solution<T>*>{"before", &r.before},
                               std::pair<const char*, const branching_solution<T>*>{"after", &r.updated}}) {
    write_voronoi(out.subdir(dir), s->fine, field, pc);
    write_copies(out.subdir(dir) + "/copies.npz", *s);
    if (shape) {
      write_shape(out.subdir(dir), s->fine_weights, s->fine, shape->picture_node, pc, method_name(shape->method));
      write_copy_weights(out.subdir(dir) + "/copy_weights.npz", *s);
    }
  }
  const gv::coord<3> none{-1, -1, -1};
  const std::size_t n_changed =
      write_change(out.subdir("."), r.before.fine, r.updated.fine, field, field, j.cut_set.get(), none, none, pc);
  std::printf("geovoronoi cut: %zu cut edges from %zu mesh(es) on the fine grid; the branching grid (factor %d) goes "
              "from %zu to %zu copies; %zu fine voxels changed\n",
              j.cut_edges, j.cut_paths.size(), j.coarsen, r.copies_before, r.copies_after, n_changed);
  std::printf("  cut grid           %9.4f s  (make_branching_grid() with the cut)\n", r.grid_seconds);
  std::printf("  incremental update %9.4f s  (library update() on backend %s; %zu copies changed by the cut, %zu "
              "below them invalidated, %zu of %zu settled again)\n",
              r.update_seconds, j.solver->name, r.stats.cut_tree_edges, r.stats.invalidated, r.stats.settled,
              r.copies_after);
  std::printf("  full recompute     %9.4f s  (voronoi() on the cut grid, backend %s, with parents)  %.1fx; identical "
              "bit for bit (distance, label, parent of every copy)\n",
              r.recompute_seconds, j.solver->name, r.update_seconds > 0 ? r.recompute_seconds / r.update_seconds : 0.0);
  if (shape) {
    const char* method = method_name(shape->method);
    const std::size_t n_weights = write_changed_weights(out.subdir("."), r.before.fine_weights, r.updated.fine_weights);
    std::printf("  weights update     %9.4f s  (%s, library update_shape_functions() on backend %s; %zu fine voxels "
                "changed)\n",
                r.shape_update_seconds, method, j.solver->name, n_weights);
    std::printf("  weights recompute  %9.4f s  (%s, shape_functions() on the cut grid, backend %s)  %.1fx; identical "
                "bit for bit (node and weight of every copy's slots)\n",
                r.shape_recompute_seconds, method, j.solver->name,
                r.shape_update_seconds > 0 ? r.shape_recompute_seconds / r.shape_update_seconds : 0.0);
  }
  std::fflush(stdout);
  return r.copies_after;
}

int run(const std::vector<std::string>& args) {
  auto names = shape_arg_options();
  names.insert("--carve");
  auto repeatable = solve_repeatable();
  repeatable.insert("--carve");
  const arguments a(args, solve_options(names), solve_flags(), repeatable);
  if (!a.has("--cut") && !a.has("--carve")) throw usage_error("cut needs a change: --cut MESH and/or --carve BOX");
  shape_args shape;
  if (a.has("--method"))
    shape = parse_shape_args(a);
  else if (a.has("--nodes-per-voxel") || a.has("--picture-node"))
    throw usage_error(std::string(a.has("--nodes-per-voxel") ? "--nodes-per-voxel" : "--picture-node") +
                      " needs --method (the shape functions before and after the change)");
  progress_bar bar("geovoronoi cut");
  bar.update("reading");
  const geovoronoi::io::read_log reads;  // every file the run reads: none may lie inside --out
  const job j = load_job(a, "cut");
  for (const auto& n : j.notes) bar.note("geovoronoi cut: " + n);
  if (a.has("--method")) check_picture_node(shape, j);
  if (j.coarsen > 0) {  // a branching grid: the fine image's cut edges (--carve is refused by load_job)
    output_dir out(j.out, reads, "geovoronoi cut");
    const shape_args* sp = a.has("--method") ? &shape : nullptr;
    const std::size_t copies =
        j.in_double ? cut_branching_in<double>(j, sp, out, bar) : cut_branching_in<float>(j, sp, out, bar);
    out.commit();
    bar.finish();
    branching_summary("cut", j.geometry(), j.coarsen, copies, j.seeds.size(), j.solver->name, bar.seconds(), j.out);
    return 0;
  }
  carve_box carve;  // the union of every --carve box
  carve.lo = {j.geometry().extent(0), j.geometry().extent(1), j.geometry().extent(2)};
  carve.hi = {-1, -1, -1};
  for (const auto& text : a.all("--carve")) {
    const carve_box box = parse_carve(text, a.has("--world"), j.geometry());
    const auto& g = j.geometry();
    for (std::size_t i = 0; i < j.seeds.size(); ++i)
      if (g.contains(j.seeds[i]) && std::binary_search(box.voxels.begin(), box.voxels.end(), g.index(j.seeds[i])))
        throw usage_error("--carve '" + text + "' removes the seed on line " + std::to_string(j.seed_lines[i]) + " of " +
                          j.seeds_path + " (a node cannot be carved; remove it from the seed file)");
    std::vector<index_t> both;
    std::set_union(carve.voxels.begin(), carve.voxels.end(), box.voxels.begin(), box.voxels.end(),
                   std::back_inserter(both));
    carve.voxels = std::move(both);
    for (int k = 0; k < 3; ++k) carve.lo[k] = std::min(carve.lo[k], box.lo[k]), carve.hi[k] = std::max(carve.hi[k], box.hi[k]);
  }
  output_dir out(j.out, reads, "geovoronoi cut");
  const carve_box* c = a.has("--carve") ? &carve : nullptr;
  const shape_args* sa = a.has("--method") ? &shape : nullptr;
  if (j.in_double)
    cut_in<double>(j, c, sa, out, bar);
  else
    cut_in<float>(j, c, sa, out, bar);
  out.commit();
  bar.finish();
  summary("cut", j.geometry(), j.seeds.size(), j.solver->name, bar.seconds(), j.out);
  return 0;
}

}  // namespace

const command cut_command = {
    "cut", "a diagram before and after a cut or carving: incremental update vs full recompute",
    "usage: geovoronoi cut (--stiffness FILE | --mesh MESH... --voxel-size S) --seeds FILE\n"
    "                      (--cut MESH | --carve BOX)... --out DIR [options]\n"
    "\n"
    "Solves the Voronoi diagram, applies a change (cut surfaces and/or a carved box), updates the\n"
    "diagram incrementally (only the voxels whose shortest path crossed the change are re-solved),\n"
    "recomputes the changed problem from scratch on --backend, checks that both agree bit for bit\n"
    "(distance, label and parent; exit 1 if not) and prints both times. With --method, the same for\n"
    "the shape functions: those after the change come from the library's update (only the rows the\n"
    "change can reach are recomputed), are checked bit for bit against shape_functions() on the\n"
    "changed problem, and both times are printed.\n"
    "\n"
    "options:\n"
    "  --stiffness FILE    the field: .mhd/.mha (MetaImage), .npy, or .pgm/.ppm (required, or --mesh)\n"
    GEOVORONOI_CLI_MESH_HELP
    "  --seeds FILE        CSV, one seed per line: i,j,k voxel indices (x,y,z with --world) (required)\n"
    "  --out DIR           output folder (required): written aside and swapped in as a whole\n"
    "  --cut MESH          a cut surface, .stl or .obj in world coordinates: the grid edges it meets\n"
    "                      are removed; repeatable (at least one --cut or a --carve is required)\n"
    "  --carve BOX         voxels removed from the domain: x0:x1,y0:y1,z0:z1, voxel indices with both\n"
    "                      ends included (0 <= x0 <= x1 < size along x, ...); with --world, world\n"
    "                      coordinates of a closed box, taking every voxel whose centre lies in it.\n"
    "                      Carved voxels get the field value -1 (outside); the box may hold no seed;\n"
    "                      repeatable (the union of the boxes)\n"
    "  --metric M          min_stiffness, mean_stiffness, mean_cost or uniform (default: min_stiffness)\n"
    "  --connectivity N    6, 18 or 26 neighbours (default: 26)\n"
    "  --backend B         seq, thrust or cuda: runs the two full solves (default: the fastest built one\n"
    "                      that runs here); the incremental update is the library's host algorithm\n"
    "  --threads N         OpenMP threads of the thrust backend, 1 to 4 x the hardware threads\n"
    "  --world             seeds and --carve are physical x,y,z coordinates (default: voxel indices)\n"
    "  --extrude N         repeat a .pgm/.ppm picture into N slices along z (default: 1)\n"
    "  --precision P       float, double or auto (default: float), as for voronoi\n"
    "  --coarsen N         on the branching grid of the field coarsened by N (see `geovoronoi help\n"
    "                      voronoi`): the --cut edges of the fine image split the copies of the cells\n"
    "                      they cross; the library's update of the diagram (and with --method of the\n"
    "                      weights) is checked bit for bit against a recompute on the cut grid; the\n"
    "                      files are at the fine resolution, with copies.npz (and copy_weights.npz) in\n"
    "                      before/ and after/; --cut only (no --carve); --reduction R\n"
    "  --method M          also the shape functions, before and after: distance-ratio, sibson or laplace\n"
    "  --nodes-per-voxel K with --method: the most nodes a voxel keeps, 1..64 (default: 4)\n"
    "  --picture-node N    with --method: the node whose weight weight_node<N>.png shows (default: 0)\n"
    "  --help              this text\n"
    "\n"
    "writes, in DIR:\n"
    "  before/             the files of `geovoronoi voronoi` on the problem without the change\n"
    "  after/              the same after the change (the updated diagram; equal to `voronoi --cut`)\n"
    "  changed.mhd/.raw    1 where the distance or the label changed, else 0 (MET_UCHAR)\n"
    "  cut.png             cells before | after on the slices through the middle of the change, the\n"
    "                      cut drawn in red, changed voxels outlined in white\n"
    "  with --method, also the files of `geovoronoi shape-functions` in before/ and after/, and\n"
    "  changed_weights.mhd/.raw\n"
    "                      1 where any slot of the voxel's weights (node or weight) changed, else 0\n"
    "  .geovoronoi-output  the marker that lets the next run with this --out replace the folder\n"
    "\n"
    "example:\n"
    "  geovoronoi cut --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv --cut demo-out/cut/blade.obj\n"
    "                 --method distance-ratio --out cut-out\n",
    run};

}  // namespace gvcli

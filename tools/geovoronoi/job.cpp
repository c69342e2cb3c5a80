// See job.hpp.
#include "job.hpp"

#include "branching.hpp"
#include "errors.hpp"
#include "meshes.hpp"
#include "outputs.hpp"
#include "seed_file.hpp"

#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/mesh.hpp>
#include <geovoronoi/io/npy.hpp>
#include <geovoronoi/io/read.hpp>
#include <geovoronoi/precision.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <regex>
#include <thread>

namespace gvcli {

namespace gio = geovoronoi::io;
using geovoronoi::index_t;

namespace {

std::string lower_extension(const std::string& path) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  return e;
}

/// Rewrites the library's "seed I ..." / "seeds I and J ..." message with the seed file's lines:
/// "FILE:LINE: the seed on line LINE ..." (for two seeds, LINE is the later one's).
std::string locate_seed_error(std::string msg, const std::string& path, const std::vector<int>& lines) {
  const std::string prefix = "geovoronoi: ";
  if (msg.compare(0, prefix.size(), prefix) == 0) msg.erase(0, prefix.size());
  const auto line_of = [&](const std::string& index) {
    const auto i = std::stoull(index);
    return i < lines.size() ? lines[i] : -1;
  };
  std::smatch m;
  static const std::regex two("\\bseeds ([0-9]+) and ([0-9]+)\\b");
  static const std::regex one("\\bseed ([0-9]+)\\b");
  if (std::regex_search(msg, m, two)) {
    const int a = line_of(m[1]), b = line_of(m[2]);
    return path + ":" + std::to_string(std::max(a, b)) + ": " + m.prefix().str() + "the seeds on lines " +
           std::to_string(std::min(a, b)) + " and " + std::to_string(std::max(a, b)) + m.suffix().str();
  }
  if (std::regex_search(msg, m, one)) {
    const int a = line_of(m[1]);
    return path + ":" + std::to_string(a) + ": " + m.prefix().str() + "the seed on line " + std::to_string(a) +
           m.suffix().str();
  }
  return msg;
}

/// Every seed must own its voxel in the diagram @p d: seed i's voxel carries label i. It does not when
/// a path of zero-weight edges (cost 0 under mean_cost) joins two seeds: both are at distance 0 and the
/// lower index wins the tie, so the later seed has no cell and every result built on it is garbage.
/// That is an input problem (exit 2), reported before anything is written.
template <class T>
void require_own_voxels(const gv::diagram<T, 3>& d, const std::string& path, const std::vector<int>& lines) {
  const auto& g = d.geometry();
  const auto line_of = [&](std::size_t i) { return i < lines.size() ? std::to_string(lines[i]) : std::string("?"); };
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const long long l = d.label[d.seeds[i]];
    if (l == static_cast<long long>(i)) continue;
    const auto c = g.coords(d.seeds[i]);
    throw usage_error(path + ": seed " + std::to_string(i) + " (" + std::to_string(c[0]) + "," + std::to_string(c[1]) +
                      "," + std::to_string(c[2]) + ") is at geodesic distance 0 from seed " + std::to_string(l) +
                      " (lines " + line_of(i) + " and " + line_of(std::size_t(l)) +
                      " of the file; a path of zero-weight edges, e.g. cost 0 under mean_cost, joins them), so it has "
                      "no cell; give the voxels between them a positive value or use another metric");
  }
}

/// `--precision float|double|auto` (default float).
std::string precision_option(const arguments& a) {
  const std::string p = a.get("--precision", "float");
  if (p != "float" && p != "double" && p != "auto")
    throw usage_error("--precision must be float, double or auto, got '" + p + "'");
  return p;
}

/// @p x with the digits a double needs, for messages.
std::string value_text(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}

/// The field in float, refusing a value that float would turn into 0 or +-inf (a stiffness of 1e-50
/// would silently leave the object, 1e300 would become an infinitely stiff voxel).
gv::image<float, 3> to_float(const gv::image<double, 3>& f, const std::string& path) {
  gv::image<float, 3> out(f.geometry(), 0.0f);
  for (index_t v = 0; v < f.size(); ++v) {
    const double x = f[v];
    if (!gv::fits_in<float>(x)) {
      const auto c = f.geometry().coords(v);
      char value[32];
      std::snprintf(value, sizeof value, "%.9g", x);
      throw usage_error(path + ": the value " + value + " at voxel (" + std::to_string(c[0]) + "," +
                        std::to_string(c[1]) + "," + std::to_string(c[2]) + ") " +
                        (std::fabs(x) > 1 ? "is beyond float's range (it would become infinite)"
                                          : "is too small for float (it would become 0)") +
                        "; use --precision double (or auto), or rescale the field");
    }
    out[v] = static_cast<float>(x);
  }
  return out;
}

}  // namespace

std::set<std::string> solve_options(std::set<std::string> extra) {
  extra.insert({"--stiffness", "--seeds", "--metric", "--connectivity", "--backend", "--out", "--extrude", "--threads",
                "--precision", "--cut", "--mesh", "--coarsen", "--reduction"});
  for (const auto& o : mesh_grid_options()) extra.insert(o);
  return extra;
}

std::set<std::string> solve_flags() {
  auto f = mesh_grid_flags();
  f.insert("--world");
  return f;
}

std::set<std::string> solve_repeatable() { return {"--cut", "--mesh"}; }

namespace {
/// "x A to B, y C to D, z E to F" of a bounding box, for messages.
std::string bounds_text(const std::array<double, 3>& lo, const std::array<double, 3>& hi) {
  std::string s;
  char buf[80];
  for (std::size_t a = 0; a < 3; ++a) {
    std::snprintf(buf, sizeof buf, "%s%c %g to %g", a ? ", " : "", "xyz"[a], lo[a], hi[a]);
    s += buf;
  }
  return s;
}

/// The note for a mesh that cuts no grid edge: its bounds and the grid's (the voxel centres' box), so
/// that a mesh in other units (mm against m) or in another frame is seen at once.
std::string no_cut_note(const std::string& path, const gv::triangle_mesh& mesh, const gv::grid<3>& g) {
  std::array<double, 3> mlo, mhi, glo, ghi;
  mlo.fill(std::numeric_limits<double>::infinity());
  mhi.fill(-std::numeric_limits<double>::infinity());
  glo = mlo, ghi = mhi;
  for (const auto& v : mesh.vertices)
    for (std::size_t a = 0; a < 3; ++a) mlo[a] = std::min(mlo[a], v[a]), mhi[a] = std::max(mhi[a], v[a]);
  for (int corner = 0; corner < 8; ++corner) {
    gv::coord<3> c;
    for (int a = 0; a < 3; ++a) c[a] = ((corner >> a) & 1) ? g.extent(a) - 1 : 0;
    const auto w = g.world(c);
    for (std::size_t a = 0; a < 3; ++a) glo[a] = std::min(glo[a], w[a]), ghi[a] = std::max(ghi[a], w[a]);
  }
  return "warning: " + path + ": the mesh cuts no edge of the grid, so it changes nothing: the mesh spans " +
         bounds_text(mlo, mhi) + "; the grid's voxel centres span " + bounds_text(glo, ghi) +
         " (world coordinates: another unit or frame?)";
}

/// The cut edges of every `--cut MESH` (.stl or .obj, world coordinates) on grid @p g under
/// connectivity @p n: one cut_set per mesh, merged, then the solvers' hash table. A mesh that cuts no
/// edge adds a warning to @p notes.
std::shared_ptr<const gv::cut_table> load_cuts(const std::vector<std::string>& paths, const gv::grid<3>& g, int n,
                                               std::size_t& edges, std::shared_ptr<const gv::cut_set<3>>& set,
                                               std::vector<std::string>& notes) {
  std::shared_ptr<const gv::cut_table> table;
  with_connectivity<3>(n, [&](auto conn) {
    gv::cut_set<3> all(g, conn);
    for (const auto& path : paths) {
      const std::string ext = lower_extension(path);
      if (ext != ".stl" && ext != ".obj") throw usage_error(path + ": --cut takes a .stl or .obj mesh");
      require_regular_file(path, "a cut mesh");
      const auto mesh = gio::read_mesh(path);
      try {
        auto one = gv::cut_from_mesh(g, conn, mesh);
        if (one.size() == 0) notes.push_back(no_cut_note(path, mesh, g));
        all.merge(one);
      } catch (const std::invalid_argument& e) {
        throw usage_error(path + ": " + library_message(e));
      }
    }
    edges = all.size();
    table = std::make_shared<const gv::cut_table>(all);
    set = std::make_shared<const gv::cut_set<3>>(std::move(all));
  });
  return table;
}

/// An image_view of @p f, as the typed problems take their field.
template <class T>
gv::image_view<const T, 3> view(const gv::image<T, 3>& f) {
  return gv::image_view<const T, 3>(f.geometry(), f.data());
}

/// The library refuses a grid when making a problem (make_problem(): a spacing whose edge lengths are
/// 0 or infinite in T): the input's fault, exit 2.
template <class F>
decltype(auto) refusing_bad_grids(F&& f) {
  try {
    return f();
  } catch (const std::invalid_argument& e) {
    throw usage_error(library_message(e));
  }
}

}  // namespace

template <class T>
std::unique_ptr<const typed_problem<T, 3>> job::problem_on(const gv::image<T, 3>& f, bool with_cuts) const {
  const bool c = with_cuts && cuts;
  const problem_key key{solver->id, metric, connectivity, c};
  return refusing_bad_grids([&] { return make_typed_problem<T, 3>(key, view(f), c ? cuts.get() : nullptr); });
}

template std::unique_ptr<const typed_problem<float, 3>> job::problem_on(const gv::image<float, 3>&, bool) const;
template std::unique_ptr<const typed_problem<double, 3>> job::problem_on(const gv::image<double, 3>&, bool) const;

namespace {
/// The run's backend, when --backend names none: choose_backend() for this problem (shape functions,
/// as `shape-functions` and `cut --method` compute, share their searches among threads at any size);
/// then the run's problem on it.
template <class T>
void make_problem_of(job& j, const arguments& a) {
  if (!a.has("--backend"))
    j.solver = &find_backend(refusing_bad_grids([&] {
      return choose_backend<T, 3>(j.metric, j.connectivity, view(j.field_in<T>()), j.threads, a.has("--method"));
    }));
  auto p = j.problem_on<T>(j.field_in<T>(), true);
  if constexpr (std::is_same_v<T, float>)
    j.problem_float = std::move(p);
  else
    j.problem_double = std::move(p);
}
}  // namespace

namespace {

/// The field of the run in j.field_double (to be checked for --precision auto and converted), or in
/// j.field already when the meshes are voxelized in float: read from `--stiffness FILE`, or
/// voxelized from `--mesh MESH[:VALUE[:LABEL]]...` on the grid of --voxel-size / --voxels (the one
/// place where a solve's field comes from). Returns whether j.field holds it.
/// Exactly one of --stiffness and --mesh (checked first, before the other required options).
void check_field_options(const arguments& a) {
  const bool file = a.has("--stiffness"), meshes = a.has("--mesh");
  if (file && meshes) throw usage_error("give --stiffness FILE or --mesh MESH..., not both");
  if (!file && !meshes)
    throw usage_error("missing required option --stiffness FILE (or --mesh MESH[:VALUE[:LABEL]] with --voxel-size)");
}

bool load_field(job& j, const arguments& a, const std::string& precision) {
  if (a.has("--stiffness")) {
    for (const auto& o : mesh_grid_options())
      if (a.has(o)) throw usage_error(o + " applies to --mesh only (a --stiffness file has its own grid)");
    for (const auto& o : mesh_grid_flags())
      if (a.has(o)) throw usage_error(o + " applies to --mesh only (a --stiffness file has its own grid)");
    j.stiffness_path = j.field_name = a.get("--stiffness");
    const std::string ext = lower_extension(j.stiffness_path);
    const bool picture = ext == ".pgm" || ext == ".ppm" || ext == ".pnm";
    if (a.has("--extrude") && !picture) throw usage_error("--extrude applies to .pgm/.ppm pictures only");
    gio::read_options ro;
    ro.extrude = index_t(a.integer("--extrude", 1, 1, 100000));
    require_regular_file(j.stiffness_path, "a stiffness file");
    // read in double, so that float's limits are checked here rather than met silently in the reader
    auto vol = gio::read_volume<double>(j.stiffness_path, ro);
    if (vol.channels != 1)
      throw usage_error(j.stiffness_path + ": has " + std::to_string(vol.channels) + " channels; a stiffness image needs 1");
    j.field_double = vol.channel<3>(0);
    return false;
  }
  if (a.has("--extrude")) throw usage_error("--extrude applies to .pgm/.ppm pictures only, not to --mesh");
  std::vector<mesh_spec> specs;
  for (const auto& m : a.all("--mesh")) {
    specs.push_back(parse_mesh_spec(m));
    j.field_name += (j.field_name.empty() ? "" : ", ") + specs.back().path;
  }
  const gv::voxelize_options o = parse_voxelize_options(a);
  const auto parts = read_mesh_parts(specs);
  std::string summary;
  bool in_float = false;
  if (precision == "float") {  // voxelized in float: every value must be one
    for (std::size_t i = 0; i < parts.size(); ++i)
      if (!gv::fits_in<float>(parts[i].value))
        throw usage_error("--mesh " + a.all("--mesh")[i] + ": the value " + value_text(parts[i].value) + " " +
                          (std::fabs(parts[i].value) > 1 ? "is beyond float's range (it would become infinite)"
                                                         : "is too small for float (it would become 0)") +
                          "; use --precision double (or auto), or rescale the values");
    auto v = voxelize_parts<float>(parts, o);
    summary = voxelize_summary(parts, v.label, v.stats);
    j.field = std::move(v.stiffness);
    in_float = true;
  } else {
    auto v = voxelize_parts<double>(parts, o);
    summary = voxelize_summary(parts, v.label, v.stats);
    j.field_double = std::move(v.stiffness);
  }
  const auto& g = in_float ? j.field.geometry() : j.field_double.geometry();
  j.notes.push_back("voxelized the meshes: " + std::to_string(g.extent(0)) + "x" + std::to_string(g.extent(1)) + "x" +
                    std::to_string(g.extent(2)) + " voxels, " + summary);
  return in_float;
}

}  // namespace

job load_job(const arguments& a, const std::string& command) {
  job j;
  if (a.has("--coarsen") || a.has("--reduction")) {
    if (!a.has("--coarsen")) throw usage_error("--reduction applies with --coarsen N only");
    j.coarsen = int(a.integer("--coarsen", 1, 1, 1 << 20));
    j.reduction = parse_reduction(a.get("--reduction", "mean"));
    if (command == "cut" && a.has("--carve"))
      throw usage_error("--carve is not supported with --coarsen (branching grids); cut them with --cut MESH");
  }
  check_field_options(a);
  j.seeds_path = a.require("--seeds");
  j.out = a.require("--out");
  j.metric = parse_metric(a.get("--metric", "min_stiffness"));
  j.connectivity = check_connectivity(int(a.integer("--connectivity", 26, 0, 1000)), 3);
  if (j.coarsen > 0) {  // the branching solve runs on seq unless told; cuda has none (said before any probe)
    if (a.get("--backend", "") == "cuda")
      throw usage_error("--backend cuda is not available on branching grids (--coarsen); use seq or thrust");
    j.solver = a.has("--backend") ? &pick_backend(a) : &find_backend(backend_id::seq);
  } else {
    j.solver = &pick_backend(a);
  }
  j.threads = use_threads(a);
  const std::string precision = precision_option(a);
  const bool in_float = load_field(j, a, precision);
  if (precision == "double") {
    j.in_double = true;
  } else if (precision == "auto") {  // double only when float could overflow or lose a value
    with_metric(j.metric, [&](auto metric) {
      with_connectivity<3>(j.connectivity, [&](auto conn) {
        j.in_double = gv::needs_double(j.field_double.geometry(), j.field_double.data(),
                                       std::size_t(j.field_double.size()), metric, conn);
      });
    });
  }
#if defined(GEOVORONOI_CLI_LEAN)
  if (j.in_double)
    throw usage_error(std::string(precision == "double" ? "--precision double"
                                                        : "--precision auto chose double for this field, which") +
                      lean_note());
#endif
  if (!j.in_double && !in_float) {
    j.field = to_float(j.field_double, j.field_name);
    j.field_double = {};
  }
  const auto& g = j.geometry();
  j.cut_paths = a.all("--cut");
  if (!j.cut_paths.empty()) j.cuts = load_cuts(j.cut_paths, g, j.connectivity, j.cut_edges, j.cut_set, j.notes);
  const bool world = a.has("--world");
  for (const auto& r : read_seed_rows(j.seeds_path, !world)) {
    const std::string where = j.seeds_path + ":" + std::to_string(r.line) + ": seed ";
    if (r.count == 2 && g.extent(2) != 1)
      throw usage_error(where + "has 2 values but the volume has " + std::to_string(g.extent(2)) + " slices");
    gv::coord<3> c;
    if (world) {
      try {  // the point as given, not a voxel it would round to
        c = g.checked_nearest_voxel({r.x[0], r.x[1], r.x[2]});
      } catch (const std::invalid_argument& e) {
        throw usage_error(j.seeds_path + ":" + std::to_string(r.line) + ": the seed at " + e.what());
      }
    } else {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(r.x[k]) > 9e15) throw usage_error(where + "coordinate out of range");
        c[k] = index_t(r.x[k]);
      }
    }
    j.seeds.push_back(c);
    j.seed_lines.push_back(r.line);
  }
  if (j.coarsen > 0) return j;  // no regular problem: the branching grid is built when solving
  if (j.in_double)
    make_problem_of<double>(j, a);
  else
    make_problem_of<float>(j, a);
  return j;
}

std::set<std::string> shape_arg_options() { return {"--method", "--nodes-per-voxel", "--picture-node"}; }

shape_args parse_shape_args(const arguments& a) {
  shape_args s;
  s.method = parse_method(a.require("--method"));
  s.k = int(a.integer("--nodes-per-voxel", 4, 1, 64));
  s.picture_node = int(a.integer("--picture-node", 0, 0, 1 << 30));
  return s;
}

void check_picture_node(const shape_args& s, const job& j) {
  if (std::size_t(s.picture_node) >= j.seeds.size())
    throw usage_error("--picture-node " + std::to_string(s.picture_node) +
                      ": must be less than the number of nodes (" + std::to_string(j.seeds.size()) + ")");
}

template <class T>
gv::diagram<T, 3> solve_diagram(const job& j, const typed_problem<T, 3>& p, const gv::solve_options& opt) {
  auto d = [&] {
    try {
      return p.voronoi(j.seeds, opt);
    } catch (const std::invalid_argument& e) {
      throw usage_error(locate_seed_error(e.what(), j.seeds_path, j.seed_lines));
    } catch (const gv::overflow_error& e) {
      // in double the library's advice (rescale) is all there is; in float the flags come first
      throw usage_error(j.field_name + ": " + library_message(e) +
                        (std::is_same_v<T, float> ? " (on the command line: --precision double, or auto)" : ""));
    }
  }();
  require_own_voxels(d, j.seeds_path, j.seed_lines);
  return d;
}

template gv::diagram<float, 3> solve_diagram(const job&, const typed_problem<float, 3>&, const gv::solve_options&);
template gv::diagram<double, 3> solve_diagram(const job&, const typed_problem<double, 3>&, const gv::solve_options&);

void rethrow_solve_error(const job& j) {
  try {
    throw;
  } catch (const std::invalid_argument& e) {
    throw usage_error(locate_seed_error(e.what(), j.seeds_path, j.seed_lines));
  } catch (const gv::overflow_error& e) {
    throw usage_error(j.field_name + ": " + library_message(e) +
                      (j.in_double ? "" : " (on the command line: --precision double, or auto)"));
  }
}

namespace {

/// A branching run (`--coarsen N`): the branching grid (split by the run's cut edges) and its diagram,
/// painted on the fine grid for the regular outputs, and copies.npz; with @p bs's shape arguments the
/// shape functions too: per copy (copy_weights.npz) and painted on the fine grid (the regular
/// shape-function files), or at the points only. Returns the number of copies.
template <class T>
std::size_t branching_and_outputs(const job& j, output_dir& out, progress_bar& bar, const branching_shapes& bs) {
  bar.update("voronoi", 0.0);
  gv::solve_options opt = j.options();
  opt.progress = [&](double x) {
    bar.set_fraction(x);
    return true;
  };
  const branching_key key{j.solver->id, j.metric, j.connectivity, j.coarsen, j.reduction};
  gv::shape_options shape;
  branching_extras x;
  x.cut = j.cut_set.get();
  if (bs.shape) {
    shape = bs.shape->options(j);
    shape.progress = [&](double f) {
      bar.set_fraction(f);
      return true;
    };
    x.shape = &shape;
    x.at = bs.at && !bs.at->empty() ? bs.at : nullptr;
  }
  const auto s = [&] {
    try {
      return bs.shape ? solve_branching_shapes<T>(key, view(j.field_in<T>()), j.seeds, opt, x)
                      : solve_branching<T>(key, view(j.field_in<T>()), j.seeds, opt, x.cut);
    } catch (...) {
      rethrow_solve_error(j);
    }
  }();
  require_own_voxels(s.fine, j.seeds_path, j.seed_lines);
  bar.update("writing");
  write_voronoi(out, s.fine, j.field_in<T>(), j.pictures());
  write_copies(out.subdir(".") + "/copies.npz", s);
  if (s.has_weights) {
    write_shape(out.subdir("."), s.fine_weights, s.fine, bs.shape->picture_node, j.pictures(),
                method_name(bs.shape->method));
    write_copy_weights(out.subdir(".") + "/copy_weights.npz", s);
  }
  if (s.has_at) write_shape_at(out.subdir("."), s.at_weights);
  return std::size_t(s.grid.copies());
}

template <class T>
void diagram_and_outputs(const job& j, output_dir& out, progress_bar& bar, const after_diagram<T>& more) {
  bar.update("voronoi", 0.0);
  gv::solve_options opt = j.options();
  opt.progress = [&](double x) {
    bar.set_fraction(x);
    return true;
  };
  const auto d = solve_diagram(j, j.problem<T>(), opt);
  bar.update("writing");
  write_voronoi(out, d, j.field_in<T>(), j.pictures());
  if (more) more(j, d, out, bar);
}
}  // namespace

int solve_and_write(const char* command, const arguments& a, const std::function<void(const job&)>& check,
                    const after_diagram<float>& more_float, const after_diagram<double>& more_double,
                    const branching_shapes& bs) {
  progress_bar bar(std::string("geovoronoi ") + command);
  bar.update("reading");
  const gio::read_log reads;  // every file the run reads: none may lie inside --out
  const job j = load_job(a, command);
  for (const auto& n : j.notes) bar.note(std::string("geovoronoi ") + command + ": " + n);
  if (check) check(j);
  output_dir out(j.out, reads, std::string("geovoronoi ") + command);
  if (j.coarsen > 0) {
    const std::size_t copies = j.in_double ? branching_and_outputs<double>(j, out, bar, bs)
                                           : branching_and_outputs<float>(j, out, bar, bs);
    out.commit();
    bar.finish();
    branching_summary(command, j.geometry(), j.coarsen, copies, j.seeds.size(), j.solver->name, bar.seconds(), j.out);
    return 0;
  }
  if (j.in_double)
    diagram_and_outputs<double>(j, out, bar, more_double);
  else
    diagram_and_outputs<float>(j, out, bar, more_float);
  out.commit();
  bar.finish();
  summary(command, j.geometry(), j.seeds.size(), j.solver->name, bar.seconds(), j.out);
  return 0;
}

}  // namespace gvcli

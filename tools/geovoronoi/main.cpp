// geovoronoi: the command-line tool (see docs/cli.md).
//
//   geovoronoi voronoi --stiffness F --seeds S.csv [--metric M] [--connectivity 6|18|26]
//                      [--backend seq|thrust|cuda] [--threads N] [--world] [--extrude N] --out DIR
//   geovoronoi shape-functions --stiffness F --seeds S.csv --method distance-ratio|sibson|laplace
//                      [--nodes-per-voxel K] [same options] --out DIR
//   geovoronoi demo [--out DIR] [--backend B]
//   geovoronoi backends
//
// Exit codes (errors.hpp): 0 success, 2 usage or bad input, 1 runtime failure; one line on stderr.

#include "cli.hpp"
#include "errors.hpp"
#include "output_dir.hpp"
#include "solve.hpp"

#include <geovoronoi.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>
#include <geovoronoi/io/read.hpp>
#include <geovoronoi/shape_functions.hpp>

#if defined(GEOVORONOI_CLI_THRUST) && __has_include(<geovoronoi/backend/thrust.hpp>)
#include <geovoronoi/backend/thrust.hpp>
#define GV_CLI_HAVE_THRUST 1
#else
#define GV_CLI_HAVE_THRUST 0
#endif
// The CUDA backend lives in cuda.cu (nvcc); this file only calls the functions declared in solve.hpp.
#if defined(GEOVORONOI_CLI_CUDA)
#define GV_CLI_HAVE_CUDA 1
#else
#define GV_CLI_HAVE_CUDA 0
#endif

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <thread>

namespace gv = geovoronoi;
namespace gio = geovoronoi::io;
using gvcli::usage_error;
using geovoronoi::index_t;

namespace {

const char* const usage_text =
    "usage:\n"
    "  geovoronoi voronoi --stiffness F --seeds S.csv [--metric min_stiffness|mean_stiffness|mean_cost|uniform]\n"
    "                     [--connectivity 6|18|26] [--backend seq|thrust|cuda] [--threads N] [--world] [--extrude N]\n"
    "                     --out DIR\n"
    "  geovoronoi shape-functions --stiffness F --seeds S.csv --method distance-ratio|sibson|laplace\n"
    "                     [--nodes-per-voxel K] [--picture-node N] [same options] --out DIR\n"
    "  geovoronoi demo [--out DIR] [--backend B] [--threads N]\n"
    "  geovoronoi backends      (which backends this binary has, and the default)\n"
    "F: .mhd, .mha, .npy, or .pgm/.ppm (with --extrude N for N slices). S.csv: one seed per line, i,j,k.\n";

/// The backends this tool knows, in the order they are listed.
const char* const known_backends[] = {"seq", "thrust", "cuda"};

bool is_built(const std::string& b) {
  return b == "seq" || (b == "thrust" && GV_CLI_HAVE_THRUST) || (b == "cuda" && GV_CLI_HAVE_CUDA);
}

std::vector<std::string> built_backends() {
  std::vector<std::string> v;
  for (const char* b : known_backends)
    if (is_built(b)) v.push_back(b);
  return v;
}

std::string join(const std::vector<std::string>& v) {
  std::string s;
  for (const auto& x : v) s += (s.empty() ? "" : ", ") + x;
  return s;
}

/// Why the CUDA backend cannot run here (empty when it can); asks the CUDA runtime once.
const std::string& cuda_problem() {
#if GV_CLI_HAVE_CUDA
  static const std::string why = gvcli::cuda_unavailable_reason();
#else
  static const std::string why = "not built into this geovoronoi";
#endif
  return why;
}

/// The default backend, the fastest one built that can run here (docs/cli.md): cuda when it is
/// built and a CUDA device answers; else thrust (OpenMP host threads) when it is built and the
/// machine has more than one hardware thread; else seq. Measured on a 2-core machine
/// (docs/benchmarks.md, 2026-11-23): thrust_omp with 2 threads solves the 128^3 gradient case in
/// 173 ms against 340 ms for seq, Table 1 Sibson in 0.85 s against 1.51 s.
std::string default_backend() {
  if (GV_CLI_HAVE_CUDA && cuda_problem().empty()) return "cuda";
  if (GV_CLI_HAVE_THRUST && std::thread::hardware_concurrency() > 1) return "thrust";
  return "seq";
}

std::string pick_backend(const gvcli::arguments& a) {
  if (!a.has("--backend")) return default_backend();
  const std::string b = a.get("--backend");
  bool known = false;
  for (const char* k : known_backends) known = known || b == k;
  if (!known) throw usage_error("unknown backend '" + b + "' (seq, thrust or cuda)");
  if (!is_built(b))
    throw usage_error("backend '" + b + "' is not built into this geovoronoi (built: " + join(built_backends()) + ")");
  if (b == "cuda" && !cuda_problem().empty()) throw usage_error("backend 'cuda': " + cuda_problem());
  return b;
}

/// The Voronoi diagram of @p s on the backend named @p backend (one of built_backends()).
gv::diagram<float, 3> run_voronoi(const std::string& backend, const gvcli::problem_spec& s) {
#if GV_CLI_HAVE_CUDA
  if (backend == "cuda") return gvcli::cuda_voronoi(s);
#endif
#if GV_CLI_HAVE_THRUST
  if (backend == "thrust") return gvcli::solve_voronoi(gv::thrust::par, s);
#endif
  if (backend == "seq") return gvcli::solve_voronoi(gv::seq, s);
  throw usage_error("backend '" + backend + "' is not built into this geovoronoi");
}

/// The shape functions of @p s (diagram @p d) on the backend named @p backend.
gv::shape_weights<float, 3> run_shape(const std::string& backend, const gvcli::problem_spec& s,
                                      const gv::diagram<float, 3>& d, const gv::shape_options& opt) {
#if GV_CLI_HAVE_CUDA
  if (backend == "cuda") return gvcli::cuda_shape(s, d, opt);
#endif
#if GV_CLI_HAVE_THRUST
  if (backend == "thrust") return gvcli::solve_shape(gv::thrust::par, s, d, opt);
#endif
  if (backend == "seq") return gvcli::solve_shape(gv::seq, s, d, opt);
  throw usage_error("backend '" + backend + "' is not built into this geovoronoi");
}

bool inside_by_name(const std::string& metric, float v) {
  bool r = false;
  gvcli::with_metric(metric, [&](auto m) { r = gv::detail::inside<decltype(m)>(v); });
  return r;
}

/// How the pictures of a run are titled: the metric and neighbourhood, the distance's unit.
struct picture_context {
  std::string metric = "min_stiffness", length = "LENGTH";
  int connectivity = 26;
  std::string setting() const { return "METRIC " + metric + ", " + std::to_string(connectivity) + " NEIGHBOURS"; }
  std::string distance_unit() const {
    if (metric == "uniform") return length;
    if (metric == "mean_cost") return length + " X COST";
    return length + "/STIFFNESS";
  }
  gio::picture_options options(const std::string& what) const {
    gio::picture_options o;
    o.title = {what + " - " + setting()};
    return o;
  }
};

/// Everything a solve needs, validated.
struct job {
  std::string stiffness_path, seeds_path, backend, metric = "min_stiffness", out;
  int connectivity = 26;
  gv::image<float, 3> field;
  std::vector<gv::coord<3>> seeds;
  gvcli::problem_spec spec() const { return {field, seeds, metric, connectivity}; }
  picture_context pictures() const { return {metric, "LENGTH", connectivity}; }
};

job load_job(const gvcli::arguments& a) {
  job j;
  j.stiffness_path = a.require("--stiffness");
  const std::string seeds_path = j.seeds_path = a.require("--seeds");
  j.out = a.require("--out");
  j.metric = a.get("--metric", "min_stiffness");
  gvcli::with_metric(j.metric, [](auto) {});
  j.connectivity = int(a.integer("--connectivity", 26, 0, 1000));
  gvcli::with_connectivity(j.connectivity, [](auto) {});
  j.backend = pick_backend(a);
  gvcli::use_threads(a);
  const std::string ext = gio::detail::extension(j.stiffness_path);
  const bool picture = ext == ".pgm" || ext == ".ppm" || ext == ".pnm";
  if (a.has("--extrude") && !picture) throw usage_error("--extrude applies to .pgm/.ppm pictures only");
  gio::read_options ro;
  ro.extrude = index_t(a.integer("--extrude", 1, 1, 100000));
  gvcli::require_regular_file(j.stiffness_path, "a stiffness file");
  auto vol = gio::read_volume<float>(j.stiffness_path, ro);
  if (vol.channels != 1)
    throw usage_error(j.stiffness_path + ": has " + std::to_string(vol.channels) + " channels; a stiffness image needs 1");
  j.field = vol.channel<3>(0);
  const auto& g = j.field.geometry();
  const bool world = a.has("--world");
  const auto rows = gvcli::read_seed_rows(seeds_path, !world);
  std::map<index_t, int> used;
  for (const auto& r : rows) {
    const std::string where = seeds_path + ":" + std::to_string(r.line) + ": seed ";
    if (r.count == 2 && g.extent(2) != 1)
      throw usage_error(where + "has 2 values but the volume has " + std::to_string(g.extent(2)) + " slices");
    gv::coord<3> c;
    if (world) {
      c = g.nearest_voxel({r.x[0], r.x[1], r.x[2]});
    } else {
      for (int k = 0; k < 3; ++k) {
        if (std::abs(r.x[k]) > 9e15) throw usage_error(where + "coordinate out of range");
        c[k] = index_t(r.x[k]);
      }
    }
    const std::string text = std::to_string(c[0]) + "," + std::to_string(c[1]) + "," + std::to_string(c[2]);
    if (!g.contains(c))
      throw usage_error(where + "(" + text + ") is outside the " + std::to_string(g.extent(0)) + "x" +
                        std::to_string(g.extent(1)) + "x" + std::to_string(g.extent(2)) + " volume");
    const index_t v = g.index(c);
    if (!inside_by_name(j.metric, j.field[v]))
      throw usage_error(where + "(" + text + ") lies on a masked voxel (stiffness " + std::to_string(j.field[v]) + ")");
    if (auto it = used.find(v); it != used.end())
      throw usage_error(where + "(" + text + ") is the same voxel as the seed on line " + std::to_string(it->second));
    used[v] = r.line;
    j.seeds.push_back(c);
  }
  return j;
}

template <class T>
gio::volume<T> planar_volume(const gv::grid<3>& g, int channels) {
  gio::volume<T> v;
  v.dims = 3;
  v.extents = g.extents();
  v.spacing = g.spacing();
  v.origin = g.origin();
  v.channels = channels;
  v.data.assign(std::size_t(g.size()) * std::size_t(channels), T(0));
  return v;
}

/// distance.mhd, label.mhd, labels.png, distance.png, voronoi.vti
void write_voronoi(const gvcli::output_dir& out, const gv::diagram<float, 3>& d, const gv::image<float, 3>& field,
                   const picture_context& pc) {
  gio::write_metaimage(out.file("distance.mhd"), d.distance);
  gio::write_metaimage(out.file("label.mhd"), d.label);
  gio::write_png(out.file("labels.png"), gio::label_picture(d.label, d.seeds, &field, pc.options("VORONOI CELLS")));
  gio::write_png(out.file("distance.png"),
                 gio::distance_picture(d.distance, d.seeds, pc.distance_unit(), pc.options("GEODESIC DISTANCE")));
  gio::vti_writer<3> w(d.geometry());
  w.add("label", d.label).add("distance", d.distance).add("stiffness", field);
  w.write(out.file("voronoi.vti"));
}

/// indices.mhd, weights.mhd (K interleaved channels: ITK, ParaView, Slicer), indices_sofa_planar.mhd,
/// weights_sofa_planar.mhd (K planar channels, SOFA's layout), weights.vti, weights_*.npy (CSR),
/// weight_node<N>.png.
void write_shape(const std::string& dir, const gv::shape_weights<float, 3>& w, const gv::diagram<float, 3>& d,
                 int png_node, const picture_context& pc, const std::string& method) {
  const auto& g = w.geometry;
  const std::size_t n = std::size_t(g.size()), k = std::size_t(w.k);
  auto idx = planar_volume<std::uint32_t>(g, w.k);
  auto wt = planar_volume<float>(g, w.k);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t s = 0; s < k; ++s) {
      const auto node = w.node[v * k + s];
      idx.data[s * n + v] = node < 0 ? 0u : std::uint32_t(node) + 1u;
      wt.data[s * n + v] = node < 0 ? 0.0f : float(w.weight[v * k + s]);
    }
  gio::metaimage_write_options planar;
  planar.layout = gio::channel_layout::planar;
  gio::write_metaimage(dir + "/indices_sofa_planar.mhd", idx, planar);
  gio::write_metaimage(dir + "/weights_sofa_planar.mhd", wt, planar);
  gio::write_metaimage(dir + "/indices.mhd", idx);  // interleaved: what every MetaImage reader expects
  gio::write_metaimage(dir + "/weights.mhd", wt);
  {
    // ParaView: weights and node indices as K-component arrays (node index 0-based, -1 empty)
    std::vector<std::int32_t> nodes(n * k);
    for (std::size_t i = 0; i < n * k; ++i) nodes[i] = w.node[i] < 0 ? -1 : std::int32_t(w.node[i]);
    std::vector<float> weights(n * k);
    for (std::size_t i = 0; i < n * k; ++i) weights[i] = w.node[i] < 0 ? 0.0f : float(w.weight[i]);
    gio::vti_writer<3> vw(g);
    vw.add("label", d.label).add("weights", weights.data(), weights.size(), w.k).add("nodes", nodes.data(), nodes.size(), w.k);
    vw.write(dir + "/weights.vti");
  }
  auto m = w.to_sparse_matrix();
  m.makeCompressed();
  std::vector<std::int64_t> indptr(std::size_t(m.rows()) + 1);
  for (std::size_t r = 0; r < indptr.size(); ++r) indptr[r] = m.outerIndexPtr()[r];
  std::vector<std::int32_t> indices(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
  std::vector<float> data(m.valuePtr(), m.valuePtr() + m.nonZeros());
  gio::write_npy(dir + "/weights_indptr.npy", indptr);
  gio::write_npy(dir + "/weights_indices.npy", indices);
  gio::write_npy(dir + "/weights_data.npy", data);
  // the pictured weight; NaN (drawn as outside) where a voxel has no weights at all
  gv::image<float, 3> one(g, 0.0f);
  for (std::size_t v = 0; v < n; ++v) {
    bool any = false;
    for (std::size_t s = 0; s < k; ++s) any = any || w.node[v * k + s] >= 0;
    if (!any) one[index_t(v)] = std::numeric_limits<float>::quiet_NaN();
  }
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t s = 0; s < k; ++s)
      if (w.node[v * k + s] == png_node) one[index_t(v)] = float(w.weight[v * k + s]);
  gio::write_png(dir + "/weight_node" + std::to_string(png_node) + ".png",
                 gio::weight_picture(one, png_node, d.seeds, pc.options(method + " SHAPE FUNCTION")));
}

gv::shape_method parse_method(const std::string& m) {
  if (m == "distance-ratio" || m == "distance_ratio") return gv::shape_method::distance_ratio;
  if (m == "sibson") return gv::shape_method::sibson;
  if (m == "laplace") return gv::shape_method::laplace;
  throw usage_error("unknown method '" + m + "' (distance-ratio, sibson or laplace)");
}

const char* method_name(gv::shape_method m) {
  return m == gv::shape_method::distance_ratio ? "distance-ratio" : m == gv::shape_method::sibson ? "sibson" : "laplace";
}

void summary(const char* what, const gv::grid<3>& g, std::size_t seeds, const std::string& backend, double seconds,
             const std::string& out) {
  std::printf("geovoronoi %s: %lld voxels, %zu seeds, backend %s, %.2f s, outputs in %s\n", what, (long long)g.size(),
              seeds, backend.c_str(), seconds, out.c_str());
  std::fflush(stdout);
}

/// The options of voronoi; shape-functions adds its own.
std::set<std::string> solve_options(std::set<std::string> extra = {}) {
  extra.insert({"--stiffness", "--seeds", "--metric", "--connectivity", "--backend", "--out", "--extrude", "--threads"});
  return extra;
}

/// What voronoi and shape-functions share: load and check the job, solve the diagram, write the
/// voronoi outputs, then `more(job, diagram, out, bar)` (the shape functions), commit, summary line.
template <class Check, class More>
int solve_and_write(const char* command, const gvcli::arguments& a, Check&& check, More&& more) {
  gvcli::progress_bar bar(std::string("geovoronoi ") + command);
  bar.update("reading");
  const job j = load_job(a);
  check(j);
  gvcli::output_dir out(j.out, {j.stiffness_path, j.seeds_path}, std::string("geovoronoi ") + command);
  bar.update("voronoi");
  const auto d = run_voronoi(j.backend, j.spec());
  gvcli::require_own_voxels(d, j.seeds_path);
  bar.update("writing");
  write_voronoi(out, d, j.field, j.pictures());
  more(j, d, out, bar);
  out.commit();
  bar.finish();
  summary(command, j.field.geometry(), j.seeds.size(), j.backend, bar.seconds(), j.out);
  return 0;
}

int cmd_voronoi(const std::vector<std::string>& args) {
  const gvcli::arguments a(args, solve_options(), {"--world"});
  return solve_and_write("voronoi", a, [](const job&) {}, [](auto&&...) {});
}

int cmd_shape(const std::vector<std::string>& args) {
  const gvcli::arguments a(args, solve_options({"--method", "--nodes-per-voxel", "--picture-node"}), {"--world"});
  const auto method = parse_method(a.require("--method"));
  const int k = int(a.integer("--nodes-per-voxel", 4, 1, 64));
  const int picture_node = int(a.integer("--picture-node", 0, 0, 1 << 30));
  auto check = [&](const job& j) {
    if (std::size_t(picture_node) >= j.seeds.size())
      throw usage_error("--picture-node " + std::to_string(picture_node) + ": must be less than the number of nodes (" +
                        std::to_string(j.seeds.size()) + ")");
  };
  return solve_and_write("shape-functions", a, check,
                         [&](const job& j, const gv::diagram<float, 3>& d, gvcli::output_dir& out,
                             gvcli::progress_bar& bar) {
                           bar.update(method_name(method), 0.0);
                           gv::shape_options opt;
                           opt.method = method;
                           opt.max_nodes_per_voxel = k;
                           opt.progress = [&](double f) { bar.set_fraction(f); return true; };
                           const auto w = run_shape(j.backend, j.spec(), d, opt);
                           bar.update("writing");
                           write_shape(out.subdir("."), w, d, picture_node, j.pictures(), method_name(method));
                         });
}

/// Lists the backends: whether each is built into this binary and can run here, and the default.
int cmd_backends(const std::vector<std::string>& args) {
  const gvcli::arguments a(args, {}, {});
  for (const char* b : known_backends) {
    std::string state = is_built(b) ? "built" : "not built";
    if (std::string(b) == "seq") state += ", sequential Dijkstra";
    if (std::string(b) == "thrust" && is_built(b))
      state += ", OpenMP on " + std::to_string(std::thread::hardware_concurrency()) + " hardware threads";
    if (std::string(b) == "cuda" && is_built(b))
      state += cuda_problem().empty() ? ", device present" : ", unusable here: " + cuda_problem();
    std::printf("%-7s %s\n", b, state.c_str());
  }
  std::printf("default %s\n", default_backend().c_str());
  return 0;
}

/// A dozen nodes spread over the steak's middle slice (z = nz/2), so the mid-slice pictures show them all.
std::vector<gv::coord<3>> mid_slice_seeds(const gv::image<float, 3>& field, int count) {
  auto plane = field;
  const auto& g = field.geometry();
  for (index_t v = 0; v < g.size(); ++v)
    if (g.coords(v)[2] != g.extent(2) / 2) plane[v] = 0.0f;
  return gv::phantom::spread_seeds(plane, count);
}

/// The same nodes on a coarser grid of the same object: each moves to the voxel whose centre is
/// nearest to its world position (or, if that voxel is outside the object, to the nearest inside
/// voxel of its slice), so node i keeps its place, its index and its colour in every picture.
std::vector<gv::coord<3>> resample_seeds(const gv::grid<3>& from, const std::vector<gv::coord<3>>& seeds,
                                         const gv::image<float, 3>& field) {
  const auto& g = field.geometry();
  std::vector<gv::coord<3>> out;
  std::set<index_t> used;
  for (std::size_t i = 0; i < seeds.size(); ++i) {
    const auto c = g.nearest_voxel(from.world(seeds[i]));
    index_t best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (index_t dy = -2; dy <= 2; ++dy)
      for (index_t dx = -2; dx <= 2; ++dx) {
        const gv::coord<3> q{c[0] + dx, c[1] + dy, c[2]};
        if (!g.contains(q) || !(field[g.index(q)] > 0) || used.count(g.index(q))) continue;
        const double d = double(dx * dx + dy * dy);
        if (d < best_d) best_d = d, best = g.index(q);
      }
    if (best < 0) throw std::runtime_error("demo: node " + std::to_string(i) + " has no place on the coarse grid");
    used.insert(best);
    out.push_back(g.coords(best));
  }
  return out;
}

void write_seeds(const std::string& path, const std::vector<gv::coord<3>>& seeds, const std::string& volume) {
  std::ofstream s(path);
  s << "# i,j,k voxel indices of the demo's nodes (x, y, z) in " << volume << "; line n is node n - 1\n";
  for (const auto& c : seeds) s << c[0] << "," << c[1] << "," << c[2] << "\n";
  if (!s) throw gio::io_error(path, "write error");
}

int cmd_demo(const std::vector<std::string>& args) {
  gvcli::arguments a(args, {"--out", "--backend", "--threads"}, {});
  const std::string dir = a.get("--out", "demo-out");
  const std::string backend = pick_backend(a);
  gvcli::use_threads(a);
  gvcli::progress_bar bar("geovoronoi demo");
  bar.update("phantom");
  // The T-bone steak phantom: meat 2e4, fat 5e3, bone 1.5e10 (the paper's contrast), 1 mm voxels.
  const gv::grid<3> g({128, 96, 32}, {1.0, 1.0, 1.0});
  const auto field = gv::phantom::steak(g);
  const auto seeds = mid_slice_seeds(field, 12);
  // Sibson inserts every voxel as a query and searches its new cell (cost ~ voxels^2 / nodes; the
  // steak is not translation invariant, so no shortcut applies): on CPU backends it runs on the same
  // steak at half the resolution (same physical size, 1/8 of the voxels, 1/64 of the work), on a GPU
  // backend at full resolution. The nodes are the same ones, moved to the coarse grid.
  const bool full_sibson = backend == "cuda";
  const gv::grid<3> gh = full_sibson ? g : gv::grid<3>({64, 48, 16}, {2.0, 2.0, 2.0});
  const auto field_h = gv::phantom::steak(gh);
  const auto seeds_h = full_sibson ? seeds : resample_seeds(g, seeds, field_h);
  gvcli::output_dir out(dir, {}, "geovoronoi demo");
  gio::write_metaimage(out.file("stiffness.mhd"), field);
  write_seeds(out.file("seeds.csv"), seeds, "stiffness.mhd");
  std::printf("demo: steak phantom %lldx%lldx%lld (Sibson: %lldx%lldx%lld), %zu nodes, backend %s\n",
              (long long)g.extent(0), (long long)g.extent(1), (long long)g.extent(2), (long long)gh.extent(0),
              (long long)gh.extent(1), (long long)gh.extent(2), seeds.size(), backend.c_str());
  std::fflush(stdout);
  const gvcli::problem_spec p{field, seeds, "min_stiffness", 26};
  const picture_context pc{"min_stiffness", "MM", 26}, pcu{"uniform", "MM", 26};
  bar.update("voronoi");
  auto t0 = bar.seconds();
  const auto d = run_voronoi(backend, p);
  std::printf("  voronoi          %7.2f s\n", bar.seconds() - t0);
  write_voronoi(out, d, field, pc);
  // the same seeds under the uniform metric, to show what the stiffness changes
  const auto du = run_voronoi(backend, {field, seeds, "uniform", 26});
  gio::write_png(out.file("labels_uniform.png"), gio::label_picture(du.label, du.seeds, &field, pcu.options("VORONOI CELLS")));
  // side by side: the XY mid-slice under the uniform metric (left) and under min_stiffness (right)
  auto left = pcu.options("UNIFORM METRIC: CELLS IGNORE THE BONE"), right = pc.options("MIN_STIFFNESS: CELLS FOLLOW IT");
  left.title = {left.title[0].substr(0, left.title[0].find(" - "))};
  right.title = {right.title[0].substr(0, right.title[0].find(" - "))};
  left.xy_only = right.xy_only = true;
  left.legend = false;
  gio::write_png(out.file("labels_compare.png"),
                 gio::hstack(gio::label_picture(du.label, du.seeds, &field, left),
                             gio::label_picture(d.label, d.seeds, &field, right), gio::picture_background));
  auto shape = [&](const gvcli::problem_spec& prob, const gv::diagram<float, 3>& diag, gv::shape_method method) {
    bar.update(method_name(method), 0.0);
    t0 = bar.seconds();
    gv::shape_options opt;
    opt.method = method;
    opt.max_nodes_per_voxel = 4;
    opt.progress = [&](double x) { bar.set_fraction(x); return true; };
    const auto w = run_shape(backend, prob, diag, opt);
    std::printf("  %-16s %7.2f s (%lld voxels)\n", method_name(method), bar.seconds() - t0,
                (long long)prob.field.geometry().size());
    std::fflush(stdout);
    const std::string sub = out.subdir(method_name(method));
    write_shape(sub, w, diag, 0, pc, method_name(method));
    if (method == gv::shape_method::sibson) {
      gio::write_metaimage(sub + "/stiffness.mhd", prob.field);
      write_seeds(sub + "/seeds.csv", prob.seeds, "sibson/stiffness.mhd");
      gio::write_metaimage(sub + "/label.mhd", diag.label);
      gio::write_png(sub + "/labels.png", gio::label_picture(diag.label, diag.seeds, &prob.field, pc.options("VORONOI CELLS")));
    }
  };
  shape(p, d, gv::shape_method::distance_ratio);
  const gvcli::problem_spec ph{field_h, seeds_h, "min_stiffness", 26};
  shape(ph, run_voronoi(backend, ph), gv::shape_method::sibson);
  bar.update("writing");
  out.commit();
  bar.finish();
  summary("demo", g, seeds.size(), backend, bar.seconds(), dir);
  std::printf("pictures: %s/labels_compare.png (uniform | min_stiffness), %s/labels.png, %s/labels_uniform.png,\n"
              "          %s/distance.png, %s/distance-ratio/weight_node0.png, %s/sibson/weight_node0.png\n",
              dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  try {
    gvcli::clamp_thread_count();
    if (args.empty()) throw usage_error("missing command (voronoi, shape-functions, demo or backends; --help for usage)");
    const std::string cmd = args.front();
    args.erase(args.begin());
    if (cmd == "--version" || cmd == "-V") {
      std::printf("geovoronoi %s\n", GEOVORONOI_TOOL_VERSION);
      return 0;
    }
    if (cmd == "--help" || cmd == "-h" || cmd == "help") {
      std::fputs(usage_text, stdout);
      return 0;
    }
    if (cmd == "voronoi") return cmd_voronoi(args);
    if (cmd == "shape-functions") return cmd_shape(args);
    if (cmd == "demo") return cmd_demo(args);
    if (cmd == "backends") return cmd_backends(args);
    throw usage_error("unknown command '" + cmd + "' (voronoi, shape-functions, demo or backends; --help for usage)");
  } catch (...) {
    return gvcli::report_current_exception();  // one line, exit 1 or 2 (errors.hpp)
  }
}

// geovoronoi demo: the built-in T-bone steak phantom, its Voronoi diagram under two metrics and two
// kinds of shape functions, as pictures and volumes.
#include "../backends.hpp"
#include "../command.hpp"
#include "../output_dir.hpp"
#include "../outputs.hpp"
#include "../progress_bar.hpp"

#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>
#include <geovoronoi/phantom.hpp>

#include <cstdio>
#include <fstream>
#include <limits>
#include <set>
#include <stdexcept>

namespace gvcli {

namespace {

namespace gio = geovoronoi::io;
using geovoronoi::index_t;

/// A dozen nodes spread over the steak's middle slice (z = nz/2), so the mid-slice pictures show them all.
std::vector<gv::coord<3>> mid_slice_seeds(const gv::image<float, 3>& field, int count) {
  auto plane = field;
  const auto& g = field.geometry();
  for (index_t v = 0; v < g.size(); ++v)
    if (g.coords(v)[2] != g.extent(2) / 2) plane[v] = 0.0f;
  return gv::phantom::spread_seeds(plane, count);
}

/// The same nodes on a coarser grid of the same object: each moves to the voxel whose centre is
/// nearest to its world position (or, if that voxel is outside the object or taken, to the nearest
/// free inside voxel of its slice within two voxels), so node i keeps its place, its index and its
/// colour in every picture.
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
        const double dist = double(dx * dx + dy * dy);
        if (dist < best_d) best_d = dist, best = g.index(q);
      }
    if (best < 0) throw std::runtime_error("demo: node " + std::to_string(i) + " has no place on the coarse grid");
    used.insert(best);
    out.push_back(g.coords(best));
  }
  return out;
}

/// A seed file (valid for --seeds) of @p seeds, voxel indices in @p volume.
void write_seeds(const std::string& path, const std::vector<gv::coord<3>>& seeds, const std::string& volume) {
  std::ofstream s(path);
  s << "# i,j,k voxel indices of the demo's nodes (x, y, z) in " << volume << "; line n is node n - 1\n";
  for (const auto& c : seeds) s << c[0] << "," << c[1] << "," << c[2] << "\n";
  if (!s) throw gio::io_error(path, "write error");
}

int run(const std::vector<std::string>& args) {
  const arguments a(args, {"--out", "--backend", "--threads"}, {});
  const std::string dir = a.get("--out", "demo-out");
  const backend& solver = pick_backend(a);
  const unsigned threads = use_threads(a);
  const std::string backend_name = solver.name;
  progress_bar bar("geovoronoi demo");
  bar.update("phantom");
  // The T-bone steak phantom: meat 2e4, fat 5e3, bone 1.5e10 (the paper's contrast), 1 mm voxels.
  const gv::grid<3> g({128, 96, 32}, {1.0, 1.0, 1.0});
  const auto field = gv::phantom::steak(g);
  const auto seeds = mid_slice_seeds(field, 12);
  // Sibson inserts every voxel as a query and searches its new cell (cost ~ voxels^2 / nodes; the
  // steak is not translation invariant, so no shortcut applies): on CPU backends it runs on the same
  // steak at half the resolution (same physical size, 1/8 of the voxels, 1/64 of the work), on a GPU
  // backend at full resolution. The nodes are the same ones, moved to the coarse grid.
  const bool full_sibson = backend_name == "cuda";
  const gv::grid<3> gh = full_sibson ? g : gv::grid<3>({64, 48, 16}, {2.0, 2.0, 2.0});
  const auto field_h = gv::phantom::steak(gh);
  const auto seeds_h = full_sibson ? seeds : resample_seeds(g, seeds, field_h);
  output_dir out(dir, {}, "geovoronoi demo");
  gio::write_metaimage(out.file("stiffness.mhd"), field);
  write_seeds(out.file("seeds.csv"), seeds, "stiffness.mhd");
  std::printf("demo: steak phantom %lldx%lldx%lld (Sibson: %lldx%lldx%lld), %zu nodes, backend %s\n",
              (long long)g.extent(0), (long long)g.extent(1), (long long)g.extent(2), (long long)gh.extent(0),
              (long long)gh.extent(1), (long long)gh.extent(2), seeds.size(), backend_name.c_str());
  std::fflush(stdout);
  const problem_spec<float> p{field, seeds, "min_stiffness", 26, threads};
  const picture_context pc{"min_stiffness", "MM", 26}, pcu{"uniform", "MM", 26};
  bar.update("voronoi");
  auto t0 = bar.seconds();
  const auto d = solver.in_float.voronoi(p);
  std::printf("  voronoi          %7.2f s\n", bar.seconds() - t0);
  write_voronoi(out, d, field, pc);
  // the same seeds under the uniform metric, to show what the stiffness changes
  const auto du = solver.in_float.voronoi({field, seeds, "uniform", 26, threads});
  gio::write_png(out.file("labels_uniform.png"),
                 gio::label_picture(du.label, du.seeds, &field, pcu.options("VORONOI CELLS")));
  // side by side: the XY mid-slice under the uniform metric (left) and under min_stiffness (right),
  // each titled by its metric alone, one legend (on the right) for both
  auto left = pcu.options("UNIFORM METRIC: CELLS IGNORE THE BONE");
  auto right = pc.options("MIN_STIFFNESS: CELLS FOLLOW IT");
  left.title = {left.title[0].substr(0, left.title[0].find(" - "))};
  right.title = {right.title[0].substr(0, right.title[0].find(" - "))};
  left.xy_only = right.xy_only = true;
  left.legend = false;
  gio::write_png(out.file("labels_compare.png"),
                 gio::hstack(gio::label_picture(du.label, du.seeds, &field, left),
                             gio::label_picture(d.label, d.seeds, &field, right), gio::picture_background));
  auto shape = [&](const problem_spec<float>& prob, const gv::diagram<float, 3>& diag, gv::shape_method method) {
    bar.update(method_name(method), 0.0);
    t0 = bar.seconds();
    gv::shape_options opt;
    opt.method = method;
    opt.max_nodes_per_voxel = 4;
    opt.progress = [&](double x) { bar.set_fraction(x); return true; };
    const auto w = solver.in_float.shape(prob, diag, opt);
    std::printf("  %-16s %7.2f s (%lld voxels)\n", method_name(method), bar.seconds() - t0,
                (long long)prob.field.geometry().size());
    std::fflush(stdout);
    const std::string sub = out.subdir(method_name(method));
    write_shape(sub, w, diag, 0, pc, method_name(method));
    if (method == gv::shape_method::sibson) {
      gio::write_metaimage(sub + "/stiffness.mhd", prob.field);
      write_seeds(sub + "/seeds.csv", prob.seeds, "sibson/stiffness.mhd");
      gio::write_metaimage(sub + "/label.mhd", diag.label);
      gio::write_png(sub + "/labels.png",
                     gio::label_picture(diag.label, diag.seeds, &prob.field, pc.options("VORONOI CELLS")));
    }
  };
  shape(p, d, gv::shape_method::distance_ratio);
  const problem_spec<float> ph{field_h, seeds_h, "min_stiffness", 26, threads};
  shape(ph, solver.in_float.voronoi(ph), gv::shape_method::sibson);
  bar.update("writing");
  out.commit();
  bar.finish();
  summary("demo", g, seeds.size(), backend_name, bar.seconds(), dir);
  std::printf("pictures: %s/labels_compare.png (uniform | min_stiffness), %s/labels.png, %s/labels_uniform.png,\n"
              "          %s/distance.png, %s/distance-ratio/weight_node0.png, %s/sibson/weight_node0.png\n",
              dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str());
  return 0;
}

}  // namespace

const command demo_command = {
    "demo", "the built-in T-bone steak phantom: cells under two metrics, Distance Ratio and Sibson",
    "usage: geovoronoi demo [--out DIR] [--backend B] [--threads N]\n"
    "\n"
    "Builds the T-bone steak phantom (128 x 96 x 32 voxels of 1 mm: meat, fat, bone) with 12 nodes on\n"
    "its middle slice, and computes its Voronoi diagram under min_stiffness and uniform, Distance Ratio\n"
    "weights, and Sibson weights (at half resolution on CPU backends).\n"
    "\n"
    "options:\n"
    "  --out DIR           output folder, replaced as a whole when the run succeeded (default: demo-out)\n"
    "  --backend B         seq, thrust or cuda (default: the fastest built one that runs here)\n"
    "  --threads N         OpenMP threads of the thrust backend, 1 to 4 x the hardware threads\n"
    "                      (default: OMP_NUM_THREADS, else the runtime's default)\n"
    "  --help              this text\n"
    "\n"
    "writes, in DIR:\n"
    "  stiffness.mhd, seeds.csv   the inputs (valid for `geovoronoi voronoi --stiffness --seeds`)\n"
    "  the files of `geovoronoi voronoi` (min_stiffness, 26 neighbours)\n"
    "  labels_uniform.png  the cells under the uniform metric\n"
    "  labels_compare.png  the middle slice under uniform (left) and min_stiffness (right)\n"
    "  distance-ratio/     the files of `geovoronoi shape-functions --method distance-ratio`\n"
    "  sibson/             the same for Sibson, with its own stiffness.mhd, seeds.csv (the same 12\n"
    "                      nodes, each moved to the nearest inside voxel of the half-resolution grid on\n"
    "                      CPU backends), label.mhd, labels.png\n"
    "\n"
    "example:\n"
    "  geovoronoi demo --out demo-out\n",
    run};

}  // namespace gvcli

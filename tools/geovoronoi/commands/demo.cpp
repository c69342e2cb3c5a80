// geovoronoi demo: the built-in T-bone steak phantom, its Voronoi diagram under two metrics and two
// kinds of shape functions, as pictures and volumes; and the limb phantom's meshes, voxelized.
#include "../backends.hpp"
#include "../change.hpp"
#include "../command.hpp"
#include "../meshes.hpp"
#include "../output_dir.hpp"
#include "../outputs.hpp"
#include "../progress_bar.hpp"
#include "../typed_problem.hpp"

#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>
#include <geovoronoi/io/stl.hpp>
#include <geovoronoi/phantom.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
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

/// A seed file (valid for --seeds) of @p seeds, voxel indices in @p volume.
void write_seeds(const std::string& path, const std::vector<gv::coord<3>>& seeds, const std::string& volume) {
  std::ofstream s(path);
  s << "# i,j,k voxel indices of the demo's nodes (x, y, z) in " << volume << "; line n is node n - 1\n";
  for (const auto& c : seeds) s << c[0] << "," << c[1] << "," << c[2] << "\n";
  if (!s) throw gio::io_error(path, "write error");
}

/// The voxel of row @p r of weights at points, or of weights on the whole grid.
index_t row_voxel(const gv::point_weights<float>& w, std::size_t r) { return w.voxel[r]; }
index_t row_voxel(const gv::shape_weights<float, 3>&, std::size_t r) { return index_t(r); }

/// Node @p n's weight in the rows of @p w (0 where a row names other nodes only); NaN, drawn as
/// outside, where no row is or a row is empty.
template <class W>
gv::image<float, 3> node_weight(const gv::grid<3>& g, const W& w, gv::label_t n) {
  gv::image<float, 3> one(g, std::numeric_limits<float>::quiet_NaN());
  const std::size_t k = std::size_t(w.k);
  for (std::size_t r = 0; r < w.node.size() / k; ++r)
    for (std::size_t s = 0; s < k; ++s) {
      if (w.node[r * k + s] < 0) continue;
      const index_t v = row_voxel(w, r);
      if (std::isnan(one[v])) one[v] = 0.0f;
      if (w.node[r * k + s] == n) one[v] = w.weight[r * k + s];
    }
  return one;
}

/// The node whose weight changes most from @p before to @p after (the sum over the rows of the
/// absolute differences; lowest index on a tie).
template <class W>
gv::label_t most_changed_node(const W& before, const W& after) {
  std::vector<double> change(after.nodes, 0.0), d(after.nodes, 0.0);
  const std::size_t k = std::size_t(after.k);
  for (std::size_t r = 0; r < after.node.size() / k; ++r) {
    std::fill(d.begin(), d.end(), 0.0);
    for (std::size_t s = 0; s < k; ++s) {
      if (before.node[r * k + s] >= 0) d[std::size_t(before.node[r * k + s])] -= double(before.weight[r * k + s]);
      if (after.node[r * k + s] >= 0) d[std::size_t(after.node[r * k + s])] += double(after.weight[r * k + s]);
    }
    for (std::size_t m = 0; m < d.size(); ++m) change[m] += std::abs(d[m]);
  }
  gv::label_t best = 0;
  for (std::size_t m = 1; m < change.size(); ++m)
    if (change[m] > change[std::size_t(best)]) best = gv::label_t(m);
  return best;
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
  const geovoronoi::io::read_log reads;  // (the demo reads no file)
  output_dir out(dir, reads, "geovoronoi demo");
  gio::write_metaimage(out.file("stiffness.mhd"), field);
  write_seeds(out.file("seeds.csv"), seeds, "stiffness.mhd");
  std::printf("demo: steak phantom %lldx%lldx%lld, %zu nodes, backend %s\n", (long long)g.extent(0),
              (long long)g.extent(1), (long long)g.extent(2), seeds.size(), backend_name.c_str());
  std::fflush(stdout);
  const gv::image_view<const float, 3> fv(g, field.data());
  const auto p = make_typed_problem<float, 3>({solver.id, metric_id::min_stiffness, 26, false}, fv);
  const picture_context pc{"min_stiffness", "MM", 26}, pcu{"uniform", "MM", 26};
  gv::solve_options with_parents;
  with_parents.threads = threads;
  with_parents.with_parent = true;  // the cut step updates this diagram incrementally (update.hpp follows its tree)
  bar.update("voronoi");
  auto t0 = bar.seconds();
  const auto d = p->voronoi(seeds, with_parents);
  std::printf("  voronoi          %7.2f s\n", bar.seconds() - t0);
  write_voronoi(out, d, field, pc);
  // the same seeds under the uniform metric, to show what the stiffness changes
  gv::solve_options plain;
  plain.threads = threads;
  const auto du = make_typed_problem<float, 3>({solver.id, metric_id::uniform, 26, false}, fv)->voronoi(seeds, plain);
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
  // Distance Ratio on every voxel of the full grid
  bar.update(method_name(gv::shape_method::distance_ratio), 0.0);
  t0 = bar.seconds();
  gv::shape_options opt;
  opt.method = gv::shape_method::distance_ratio;
  opt.max_nodes_per_voxel = 4;
  opt.threads = threads;
  opt.progress = [&](double x) { bar.set_fraction(x); return true; };
  const gv::shape_options opt_dr = opt;
  const auto w_dr = p->shape_functions(d, opt);  // kept for the cut step, which updates it
  const double t_dr = bar.seconds() - t0;
  std::printf("  %-16s %7.2f s (%lld voxels)\n", method_name(opt.method), t_dr, (long long)g.size());
  std::fflush(stdout);
  write_shape(out.subdir(method_name(opt.method)), w_dr, d, 0, pc, method_name(opt.method));
  // Sibson at full resolution on the pictured slice only: every voxel is a query whose new cell is
  // searched (cost ~ voxels^2 / nodes, and the steak's stiffness varies, so no shortcut applies), so
  // all 393k voxels take minutes on a CPU; the XY slice z = nz/2 (128 x 96 voxels, where the nodes
  // lie) is what the picture shows, and shape_functions_at() gives exactly its rows of the full
  // computation. Points are the slice's voxels in row order: point r is voxel (r % nx, r / nx, nz/2).
  bar.update(method_name(gv::shape_method::sibson), 0.0);
  t0 = bar.seconds();
  opt.method = gv::shape_method::sibson;
  std::vector<gv::coord<3>> slice;
  for (index_t y = 0; y < g.extent(1); ++y)
    for (index_t x = 0; x < g.extent(0); ++x) slice.push_back({x, y, g.extent(2) / 2});
  {
    const auto w = p->shape_functions_at(d, slice, opt);
    std::printf("  %-16s %7.2f s (%zu voxels: the slice z=%lld at full resolution)\n", method_name(opt.method),
                bar.seconds() - t0, slice.size(), (long long)(g.extent(2) / 2));
    std::fflush(stdout);
    const std::string sub = out.subdir(method_name(opt.method));
    write_shape_at(sub, w);
    write_seeds(sub + "/points.csv", slice, "stiffness.mhd (the points of weights_at_*; --at of shape-functions)");
    // node 0's weight on the slice
    auto o = pc.options("SIBSON SHAPE FUNCTION, FULL RESOLUTION, THIS SLICE ONLY");
    o.xy_only = true;
    gio::write_png(sub + "/weight_node0.png", gio::weight_picture(node_weight(g, w, 0), 0, d.seeds, o));
  }
  // the cut: a planar 30 x 20 mm blade along the top of the bone's bar, right of node 0 (the plane
  // y = 49.5 mm, x 70..100, z 6..26). The bone carries node 0's cell across the steak; the meat above
  // the blade is now reached from the bone only around it, so the bone's cell loses it to node 9.
  // (bench/voronoi's cut20 blade, x = 70.5 beside the stem, does the opposite: node 10's cell loses
  // meat to the bone's.) Updated incrementally and checked against a full recompute (`geovoronoi cut`).
  bar.update("cut");
  gv::triangle_mesh blade;
  blade.vertices = {{70, 49.5, 6}, {100, 49.5, 6}, {100, 49.5, 26}, {70, 49.5, 26}};
  blade.triangles = {{0, 1, 2}, {0, 2, 3}};
  const auto blade_set = gv::cut_from_mesh(g, gv::connectivity<26>{}, blade);
  const gv::cut_table blade_table(blade_set);
  const auto p_cut = make_typed_problem<float, 3>({solver.id, metric_id::min_stiffness, 26, true}, fv, &blade_table);
  gv::change<3> blade_change;
  blade_change.cut = blade_set;
  t0 = bar.seconds();
  auto dc = d;
  p_cut->update_in_place(dc, blade_change);
  const double t_update = bar.seconds() - t0;
  t0 = bar.seconds();
  require_equal(dc, p_cut->voronoi(seeds, with_parents));
  const double t_full = bar.seconds() - t0;
  // Distance Ratio after the cut: the weights before, updated (only the rows the cut can reach are
  // recomputed; bit for bit a full recompute, which tests/ and `geovoronoi cut --method` check)
  bar.update("cut: distance-ratio update", 0.0);
  t0 = bar.seconds();
  auto w_cut = w_dr;
  const auto st = p_cut->update_shape_functions_in_place(d, dc, w_cut, blade_change, opt_dr);
  const double t_weights = bar.seconds() - t0;
  {
    const std::string sub = out.subdir("cut");
    std::ofstream obj(sub + "/blade.obj");
    obj << "# the demo's blade (world coordinates, mm): the plane y = 49.5, x 70..100, z 6..26\n";
    for (const auto& q : blade.vertices) obj << "v " << q[0] << " " << q[1] << " " << q[2] << "\n";
    obj << "f 1 2 3\nf 1 3 4\n";
    if (!obj) throw gio::io_error(sub + "/blade.obj", "write error");
    const gv::coord<3> none{-1, -1, -1};
    const std::size_t changed = write_change(sub, d, dc, field, field, &blade_set, none, none, pc);
    std::printf("  cut (update)     %7.3f s (%zu cut edges, %zu voxels changed; full recompute %.2f s, identical)\n",
                t_update, blade_set.size(), changed, t_full);
    // the node whose Distance Ratio weight the cut changes most, before | after, on the slice through
    // the middle of the blade (z = 16; weights 0..1)
    const gv::label_t n = most_changed_node(w_dr, w_cut);
    auto was = pc.options("DISTANCE RATIO WEIGHT OF NODE " + std::to_string(n) + " BEFORE THE CUT");
    auto now = pc.options("AFTER: " + std::to_string(st.changed) + " VOXELS' WEIGHTS CHANGED (UPDATED)");
    was.title = {was.title[0].substr(0, was.title[0].find(" - "))};
    now.title = {now.title[0].substr(0, now.title[0].find(" - "))};
    was.xy_only = now.xy_only = true;
    was.legend = false;
    gio::write_png(sub + "/cut_weights.png",
                   gio::hstack(gio::weight_picture(node_weight(g, w_dr, n), n, d.seeds, was),
                               gio::weight_picture(node_weight(g, w_cut, n), n, dc.seeds, now),
                               gio::picture_background));
    std::printf("  cut (weights)    %7.3f s (distance-ratio update: %zu of %zu rows recomputed, %zu changed; the full "
                "grid took %.2f s above; node %d pictured)\n",
                t_weights, st.recomputed, st.rows, st.changed, t_dr, int(n));
    std::fflush(stdout);
  }
  // meshes in: the limb phantom's surfaces (mm) written as STL, voxelized as `geovoronoi voxelize`
  // does (1 mm voxels, 2 voxels of padding), and the cells of 8 nodes on its middle slice
  bar.update("mesh");
  {
    t0 = bar.seconds();
    // the parts as `voxelize` reads them back from the files (binary STL holds float coordinates)
    const std::string sub = out.subdir("mesh");
    std::vector<mesh_spec> specs;
    for (const auto& part : gv::phantom::limb()) {
      gio::write_stl(sub + "/" + part.name + ".stl", part.mesh);
      specs.push_back({sub + "/" + part.name + ".stl", part.value, part.label});
    }
    const auto limb = read_mesh_parts(specs);
    gv::voxelize_options vo;
    vo.voxel_size = {1.0, 1.0, 1.0};
    vo.pad = 2;
    const auto vx = voxelize_parts<float>(limb, vo);
    const auto& mg = vx.stiffness.geometry();
    const auto mesh_seeds = mid_slice_seeds(vx.stiffness, 8);
    gio::write_metaimage(sub + "/stiffness.mhd", vx.stiffness);
    gio::write_metaimage(sub + "/label.mhd", vx.label);
    write_seeds(sub + "/seeds.csv", mesh_seeds, "stiffness.mhd");
    const gv::image_view<const float, 3> mv(mg, vx.stiffness.data());
    const auto dm = make_typed_problem<float, 3>({solver.id, metric_id::min_stiffness, 26, false}, mv)->voronoi(mesh_seeds, plain);
    gio::write_png(sub + "/materials.png", mesh_label_picture(vx.label, &vx.stiffness, "LIMB PHANTOM FROM MESHES: LABELS"));
    gio::write_png(sub + "/mesh_labels.png",
                   gio::label_picture(dm.label, dm.seeds, &vx.stiffness, pc.options("LIMB PHANTOM FROM MESHES: CELLS")));
    std::printf("  mesh             %7.2f s (limb phantom: %zu meshes voxelized to %lldx%lldx%lld; %s)\n",
                bar.seconds() - t0, limb.size(), (long long)mg.extent(0), (long long)mg.extent(1),
                (long long)mg.extent(2), voxelize_summary(limb, vx.label, vx.stats).c_str());
    std::fflush(stdout);
  }
  bar.update("writing");
  out.commit();
  bar.finish();
  summary("demo", g, seeds.size(), backend_name, bar.seconds(), dir);
  std::printf("pictures: %s/labels_compare.png (uniform | min_stiffness), %s/labels.png, %s/labels_uniform.png,\n"
              "          %s/distance.png, %s/distance-ratio/weight_node0.png, %s/sibson/weight_node0.png,\n"
              "          %s/cut/cut.png (before | after the cut), %s/cut/cut_weights.png (a weight before | after),\n"
              "          %s/mesh/mesh_labels.png (cells on the voxelized limb meshes)\n",
              dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(), dir.c_str(),
              dir.c_str());
  return 0;
}

}  // namespace

const command demo_command = {
    "demo", "the built-in T-bone steak phantom: cells under two metrics, Distance Ratio, Sibson, a cut",
    "usage: geovoronoi demo [--out DIR] [--backend B] [--threads N]\n"
    "\n"
    "Builds the T-bone steak phantom (128 x 96 x 32 voxels of 1 mm: meat, fat, bone) with 12 nodes on\n"
    "its middle slice, and computes its Voronoi diagram under min_stiffness and uniform, Distance Ratio\n"
    "weights on every voxel, Sibson weights at full resolution on the middle slice (z = 16), and the\n"
    "diagram after a cut beside the bone (incremental update, checked against a full recompute) with\n"
    "the Distance Ratio weights updated for it. Then the limb phantom's meshes (flesh and bone, mm)\n"
    "are written as STL, voxelized (1 mm voxels, as `geovoronoi voxelize` does) and their cells drawn.\n"
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
    "  sibson/             Sibson weights (K = 4) of the 12288 voxels of the slice z = 16, exactly the\n"
    "                      rows of a full-grid run: points.csv (the voxels, row order), weights_at_*.npy\n"
    "                      (points x nodes CSR), weights_at.csv, weight_node0.png (node 0's weight)\n"
    "  cut/                blade.obj (the plane y = 49.5 mm, x 70..100, z 6..26: along the top of the\n"
    "                      bone's bar), changed.mhd and cut.png (cells before | after the cut) as\n"
    "                      `geovoronoi cut` writes them, cut_weights.png (the Distance Ratio weight on\n"
    "                      the slice z = 16 of the node the cut changes most, before | after; the\n"
    "                      weights after come from update_shape_functions)\n"
    "  mesh/               flesh.stl, bone.stl (the limb phantom's surfaces, mm), the voxelized\n"
    "                      stiffness.mhd (flesh 2e4, bone 1.5e10) and label.mhd (1 flesh, 2 bone),\n"
    "                      seeds.csv (8 nodes), materials.png (the labels) and mesh_labels.png (the\n"
    "                      cells under min_stiffness): `geovoronoi voronoi --mesh mesh/flesh.stl:2e4:1\n"
    "                      --mesh mesh/bone.stl:1.5e10:2 --voxel-size 1 --pad 2 --seeds mesh/seeds.csv`\n"
    "                      gives the same cells\n"
    "\n"
    "example:\n"
    "  geovoronoi demo --out demo-out\n",
    run};

}  // namespace gvcli

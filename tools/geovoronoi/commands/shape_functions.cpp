// geovoronoi shape-functions: Distance Ratio, Sibson or Laplace weights of the seeds (nodes).
#include "../command.hpp"
#include "../job.hpp"
#include "../outputs.hpp"

namespace gvcli {

namespace {

gv::shape_method parse_method(const std::string& m) {
  if (m == "distance-ratio" || m == "distance_ratio") return gv::shape_method::distance_ratio;
  if (m == "sibson") return gv::shape_method::sibson;
  if (m == "laplace") return gv::shape_method::laplace;
  throw usage_error("unknown method '" + m + "' (distance-ratio, sibson or laplace)");
}

int run(const std::vector<std::string>& args) {
  const arguments a(args, solve_options({"--method", "--nodes-per-voxel", "--picture-node"}), solve_flags());
  const auto method = parse_method(a.require("--method"));
  const int k = int(a.integer("--nodes-per-voxel", 4, 1, 64));
  const int picture_node = int(a.integer("--picture-node", 0, 0, 1 << 30));
  // checked before any work: the node must exist
  auto check = [&](const job& j) {
    if (std::size_t(picture_node) >= j.seeds.size())
      throw usage_error("--picture-node " + std::to_string(picture_node) + ": must be less than the number of nodes (" +
                        std::to_string(j.seeds.size()) + ")");
  };
  return solve_and_write("shape-functions", a, check,
                         [&](const job& j, const gv::diagram<float, 3>& d, output_dir& out, progress_bar& bar) {
                           bar.update(method_name(method), 0.0);
                           gv::shape_options opt;
                           opt.method = method;
                           opt.max_nodes_per_voxel = k;
                           opt.progress = [&](double f) {
                             bar.set_fraction(f);
                             return true;
                           };
                           const auto w = j.solver->shape(j.spec(), d, opt);
                           bar.update("writing");
                           write_shape(out.subdir("."), w, d, picture_node, j.pictures(), method_name(method));
                         });
}

}  // namespace

const command shape_functions_command = {
    "shape-functions", "Distance Ratio, Sibson or Laplace shape functions of the seeds (nodes)",
    "usage: geovoronoi shape-functions --stiffness FILE --seeds FILE --method M --out DIR [options]\n"
    "\n"
    "The Voronoi shape functions of the nodes (the seeds): for every voxel, at most K (node, weight)\n"
    "pairs, weights >= 0 summing to 1 inside the object.\n"
    "\n"
    "options: those of `geovoronoi voronoi` (see `geovoronoi help voronoi`), and\n"
    "  --method M          distance-ratio, sibson or laplace (required)\n"
    "  --nodes-per-voxel K the most nodes a voxel keeps, 1..64 (default: 4)\n"
    "  --picture-node N    the node whose weight weight_node<N>.png shows, 0 to nodes - 1 (default: 0)\n"
    "  --stiffness FILE, --seeds FILE, --out DIR (required); --metric M (default: min_stiffness),\n"
    "  --connectivity N (default: 26), --backend B (default: the fastest built one that runs here),\n"
    "  --threads N (default: OMP_NUM_THREADS),\n"
    "  --world, --extrude N (default: 1), --help\n"
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
    "\n"
    "example:\n"
    "  geovoronoi shape-functions --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv \\\n"
    "             --method sibson --nodes-per-voxel 4 --out weights\n",
    run};

}  // namespace gvcli

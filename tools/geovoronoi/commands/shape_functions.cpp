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
  const arguments a(args, solve_options({"--method", "--nodes-per-voxel"}), solve_flags());
  const auto method = parse_method(a.require("--method"));
  const int k = int(a.integer("--nodes-per-voxel", 4, 1, 64));
  return solve_and_write("shape-functions", a,
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
                           write_shape(out.subdir("."), w, d, 0);
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
    "  --stiffness FILE, --seeds FILE, --out DIR (required); --metric M (default: min_stiffness),\n"
    "  --connectivity N (default: 26), --backend B (default: the fastest built one that runs here),\n"
    "  --world, --extrude N (default: 1), --help\n"
    "\n"
    "writes, in DIR: the files of `geovoronoi voronoi`, and\n"
    "  indices.mhd/.raw    K channels, SOFA's planar layout: node index + 1, 0 for an empty slot\n"
    "  weights.mhd/.raw    K channels, the same layout: the weight of that node\n"
    "  weights_indptr.npy, weights_indices.npy, weights_data.npy\n"
    "                      the voxels x nodes matrix in CSR form (scipy.sparse.csr_matrix)\n"
    "  weight_node0.png    node 0's weight on the three mid-slices\n"
    "\n"
    "example:\n"
    "  geovoronoi shape-functions --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv \\\n"
    "             --method sibson --nodes-per-voxel 4 --out weights\n",
    run};

}  // namespace gvcli

// geovoronoi voronoi: the geodesic Voronoi diagram of a seed file over a stiffness volume.
#include "../command.hpp"
#include "../job.hpp"
#include "../meshes.hpp"

namespace gvcli {

namespace {

int run(const std::vector<std::string>& args) {
  const arguments a(args, solve_options(), solve_flags(), solve_repeatable());
  return solve_and_write("voronoi", a, nullptr, nullptr, nullptr);
}

}  // namespace

const command voronoi_command = {
    "voronoi", "the geodesic Voronoi diagram of the seeds (distance and label volumes, pictures)",
    "usage: geovoronoi voronoi (--stiffness FILE | --mesh MESH... --voxel-size S) --seeds FILE --out DIR\n"
    "                          [options]\n"
    "\n"
    "The geodesic Voronoi diagram of the seeds over the stiffness volume: every voxel's distance to\n"
    "its nearest seed along paths inside the object, and that seed's index.\n"
    "\n"
    "options:\n"
    "  --stiffness FILE    the field: .mhd/.mha (MetaImage), .npy, or .pgm/.ppm (a picture, see --extrude)\n"
    "                      (required, or --mesh)\n"
    GEOVORONOI_CLI_MESH_HELP
    "  --seeds FILE        CSV, one seed per line: i,j,k voxel indices (x,y,z with --world); # comments\n"
    "                      (required)\n"
    "  --out DIR           output folder (required): written aside and swapped in as a whole when\n"
    "                      everything succeeded; an existing DIR must be empty or a geovoronoi output\n"
    "  --metric M          min_stiffness, mean_stiffness, mean_cost or uniform (default: min_stiffness)\n"
    "  --connectivity N    6, 18 or 26 neighbours (default: 26)\n"
    "  --backend B         seq, thrust or cuda (default: the fastest built one that runs here; see\n"
    "                      `geovoronoi backends`)\n"
    "  --threads N         OpenMP threads of the thrust backend, 1 to 4 x the hardware threads\n"
    "                      (default: OMP_NUM_THREADS, else the runtime's default)\n"
    "  --world             seeds are physical x,y,z coordinates, rounded to the nearest voxel centre\n"
    "                      (default: voxel indices)\n"
    "  --extrude N         repeat a .pgm/.ppm picture into N slices along z (default: 1)\n"
    "  --cut MESH          a cut surface, .stl or .obj in world coordinates: the grid edges it meets\n"
    "                      are removed (no path crosses it); repeatable (default: no cut)\n"
    "  --coarsen N         solve on a branching grid (docs/branching.md): coarse cells of N^3 voxels of\n"
    "                      the field (the fine image), one node (copy) per connected piece of material\n"
    "                      in a cell, so parts closer than a cell stay apart; seeds are fine voxels;\n"
    "                      backends seq (the default) and thrust; --cut MESH cuts the fine image,\n"
    "                      splitting the copies of the cells it crosses (default: off)\n"
    "  --reduction R       with --coarsen: a copy's stiffness from its fine values: mean, min, max or\n"
    "                      harmonic (default: mean)\n"
    "  --precision P       float, double or auto: the type distances (and weights) are computed and\n"
    "                      written in; auto takes double only when the field could overflow float or\n"
    "                      holds a value float cannot (default: float)\n"
    "  --help              this text\n"
    "\n"
    "writes, in DIR:\n"
    "  distance.mhd/.raw   geodesic distance to the nearest seed (float, or double with --precision\n"
    "                      double; +inf outside or unreachable)\n"
    "  label.mhd/.raw      0-based index of the nearest seed (int32; -1 outside or unreachable)\n"
    "  labels.png          the cells on the three mid-slices\n"
    "  distance.png        the distance on the three mid-slices\n"
    "  voronoi.vti         label, distance and stiffness for ParaView\n"
    "  copies.npz          with --coarsen: per copy its cell, distance, label, parent, stiffness,\n"
    "                      voxel_count, links (link_begin, link_copy, link_dir: CSR), and fine_copy\n"
    "                      (each fine voxel's copy, -1 outside); the volumes and pictures above are\n"
    "                      painted at the fine resolution\n"
    "  .geovoronoi-output  the marker that lets the next run with this --out replace the folder\n"
    "\n"
    "example:\n"
    "  geovoronoi voronoi --stiffness demo-out/stiffness.mhd --seeds demo-out/seeds.csv --out cells\n",
    run};

}  // namespace gvcli

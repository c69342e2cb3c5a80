// geovoronoi voxelize: closed triangle meshes to a stiffness image and a label image.
#include "../command.hpp"
#include "../errors.hpp"
#include "../meshes.hpp"
#include "../output_dir.hpp"
#include "../progress_bar.hpp"

#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/npy.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>
#include <geovoronoi/io/vti.hpp>

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

namespace gvcli {

namespace {

namespace gio = geovoronoi::io;

/// Writes @p img as DIR/NAME.EXT in the format @p format (mhd, vti or npy).
template <class T>
void write_image(const output_dir& out, const std::string& name, const std::string& format, const gv::image<T, 3>& img) {
  if (format == "mhd") {
    gio::write_metaimage(out.file(name + ".mhd"), img);
  } else if (format == "vti") {
    gio::vti_writer<3> w(img.geometry());
    w.add(name, img);
    w.write(out.file(name + ".vti"));
  } else {
    gio::write_npy(out.file(name + ".npy"), img);
  }
}

/// grid.json: the grid the images lie on (index order x, y, z; the direction row-major, column c the
/// world direction of index axis c), which a .npy file does not carry.
void write_grid(const std::string& path, const gv::grid<3>& g) {
  std::ofstream f(path);
  char buf[64];
  auto num = [&](double x) {
    std::snprintf(buf, sizeof buf, "%.17g", x);
    return std::string(buf);
  };
  f << "{\"extents\": [" << g.extent(0) << ", " << g.extent(1) << ", " << g.extent(2) << "], \"spacing\": ["
    << num(g.spacing(0)) << ", " << num(g.spacing(1)) << ", " << num(g.spacing(2)) << "], \"origin\": ["
    << num(g.origin()[0]) << ", " << num(g.origin()[1]) << ", " << num(g.origin()[2]) << "], \"direction\": [";
  for (std::size_t i = 0; i < 9; ++i) f << (i ? ", " : "") << num(g.direction()[i]);
  f << "]}\n";
  f.close();
  if (!f) throw gio::io_error(path, "write error");
}

template <class T>
void write_outputs(const output_dir& out, const std::string& format, const gv::voxelization<T>& v) {
  write_image(out, "stiffness", format, v.stiffness);
  write_image(out, "label", format, v.label);
  if (v.fraction.size() > 0) write_image(out, "fraction", format, v.fraction);
  write_grid(out.file("grid.json"), v.label.geometry());
  gio::write_png(out.file("labels.png"), mesh_label_picture(v.label, &v.stiffness, "VOXELIZED MESHES: LABELS"));
}

int run(const std::vector<std::string>& args) {
  auto with_value = mesh_grid_options(), flags = mesh_grid_flags();
  for (const auto& o : voxelize_only_options()) with_value.insert(o);
  for (const auto& f : voxelize_only_flags()) flags.insert(f);
  with_value.insert("--out");
  // the meshes are the arguments that are neither an option nor an option's value
  std::vector<std::string> specs, options;
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i].rfind("--", 0) != 0) {
      specs.push_back(args[i]);
      continue;
    }
    options.push_back(args[i]);
    if (with_value.count(args[i]) && i + 1 < args.size() && args[i + 1].rfind("--", 0) != 0)
      options.push_back(args[++i]);
  }
  const arguments a(options, with_value, flags);
  if (specs.empty()) throw usage_error("voxelize needs at least one mesh: MESH[:VALUE[:LABEL]]...");
  const std::string dir = a.require("--out");
  const std::string format = a.get("--format", "mhd");
  if (format != "mhd" && format != "vti" && format != "npy")
    throw usage_error("--format must be mhd, vti or npy, got '" + format + "'");
  const std::string precision = a.get("--precision", "float");
  if (precision != "float" && precision != "double")
    throw usage_error("--precision must be float or double, got '" + precision + "'");
  std::vector<mesh_spec> parsed;
  for (const auto& s : specs) parsed.push_back(parse_mesh_spec(s));
  const gv::voxelize_options o = parse_voxelize_options(a);
  progress_bar bar("geovoronoi voxelize");
  bar.update("reading");
  const gio::read_log reads;  // every mesh the run reads: none may lie inside --out
  const auto parts = read_mesh_parts(parsed);
  output_dir out(dir, reads, "geovoronoi voxelize");
  bar.update("voxelize");
  std::string line;
  gv::grid<3> g;
  auto go = [&](auto tag) {
    using T = decltype(tag);
    const auto v = voxelize_parts<T>(parts, o);
    bar.update("writing");
    write_outputs(out, format, v);
    line = voxelize_summary(parts, v.label, v.stats);
    g = v.label.geometry();
  };
  if (precision == "double")
    go(double{});
  else
    go(float{});
  out.commit();
  bar.finish();
  std::printf("geovoronoi voxelize: %lldx%lldx%lld voxels, %s; %.2f s, outputs in %s\n", (long long)g.extent(0),
              (long long)g.extent(1), (long long)g.extent(2), line.c_str(), bar.seconds(), dir.c_str());
  std::fflush(stdout);
  return 0;
}

}  // namespace

const command voxelize_command = {
    "voxelize", "closed triangle meshes to a stiffness image and a label image",
    "usage: geovoronoi voxelize MESH[:VALUE[:LABEL]]... (--voxel-size S | --voxels NX,NY,NZ) --out DIR\n"
    "                           [options]\n"
    "\n"
    "Voxelizes the meshes (.stl or .obj, world coordinates): a voxel belongs to a mesh when its centre\n"
    "is inside it, decided exactly (the library's voxelize()). Inside a mesh the stiffness is VALUE\n"
    "(default 1) and the label LABEL (default: the mesh's 1-based position in the list); elsewhere\n"
    "--outside-value and label 0. The grid spans the meshes' bounds.\n"
    "MESH:VALUE:LABEL is split at the last colon only when what follows is a number (a mesh file ends\n"
    "in .stl or .obj), so C:\\m\\liver.stl:3000 is the file C:\\m\\liver.stl with value 3000.\n"
    "\n"
    "options:\n"
    "  --voxel-size S      the voxel size, one value or SX,SY,SZ (world units); or:\n"
    "  --voxels NX,NY,NZ   the voxel counts across the meshes' bounds (exactly one of the two)\n"
    "  --pad N             voxels added outside the bounds on every side (default: 0)\n"
    "  --rotate            grid axes along the meshes' principal axes (a rotated grid; its direction\n"
    "                      is in every output) (default: the world axes)\n"
    "  --winding           any triangle soup: inside where the generalized winding number is >= 1/2\n"
    "                      (default: the mesh must be closed, consistently oriented and free of\n"
    "                      self-intersections; else an error naming the first bad edge or triangle)\n"
    "  --overlap R         a voxel inside several meshes takes the mesh listed last, first, the one\n"
    "                      with the max or min value, or is an error: last, first, max, min, error\n"
    "                      (default: last)\n"
    "  --surface-inside    voxels the surface passes through count as inside too (default: off)\n"
    "  --fraction K        also the occupied fraction of every voxel, from K^3 samples (1 to 64)\n"
    "                      (default: 0, none)\n"
    "  --outside-value V   the stiffness outside every mesh (default: 0, outside the object)\n"
    "  --format F          mhd, vti or npy: the format of the images (default: mhd)\n"
    "  --precision P       float or double: the stiffness image's type (default: float)\n"
    "  --out DIR           output folder (required): written aside and swapped in as a whole when\n"
    "                      everything succeeded; an existing DIR must be empty or a geovoronoi output\n"
    "  --help              this text\n"
    "\n"
    "writes, in DIR (EXT: the --format):\n"
    "  stiffness.EXT       the stiffness (float32, or float64 with --precision double)\n"
    "  label.EXT           the label of the mesh each voxel is inside (int32; 0 outside)\n"
    "  fraction.EXT        with --fraction: the occupied fraction, 0 to 1 (float32)\n"
    "  grid.json           extents, spacing, origin (x, y, z) and direction of the grid\n"
    "  labels.png          the labels on the three mid-slices (the stiffest material hatched)\n"
    "  .geovoronoi-output  the marker that lets the next run with this --out replace the folder\n"
    "\n"
    "prints one line: the grid, voxels inside each mesh, the meshes' volume against the voxels'.\n"
    "\n"
    "example:\n"
    "  geovoronoi voxelize demo-out/mesh/flesh.stl:2e4:1 demo-out/mesh/bone.stl:1.5e10:2 --voxel-size 1\n"
    "                      --pad 2 --out limb\n",
    run};

}  // namespace gvcli

// The geovoronoi tool's outputs (see outputs.hpp and docs/cli.md).
#include "outputs.hpp"

#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/npy.hpp>
#include <geovoronoi/io/picture.hpp>
#include <geovoronoi/io/png.hpp>
#include <geovoronoi/io/vti.hpp>

#include <cstdint>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace gvcli {

namespace gio = geovoronoi::io;
using geovoronoi::index_t;

namespace {

/// An empty K-channel volume on @p g, with its direction (so the outputs overlay the input).
template <class T>
gio::volume<T> planar_volume(const gv::grid<3>& g, int channels) {
  gio::volume<T> v;
  v.dims = 3;
  v.extents = g.extents();
  v.spacing = g.spacing();
  v.origin = g.origin();
  v.orientation = g.direction();
  v.channels = channels;
  v.data.assign(std::size_t(g.size()) * std::size_t(channels), T(0));
  return v;
}

}  // namespace

template <class T>
void write_voronoi(const std::string& dir, const gv::diagram<T, 3>& d, const gv::image<T, 3>& field,
                   const picture_context& pc) {
  gio::write_metaimage(dir + "/distance.mhd", d.distance);
  gio::write_metaimage(dir + "/label.mhd", d.label);
  gio::write_png(dir + "/labels.png", gio::label_picture(d.label, d.seeds, &field, pc.options("VORONOI CELLS")));
  gio::write_png(dir + "/distance.png",
                 gio::distance_picture(d.distance, d.seeds, pc.distance_unit(), pc.options("GEODESIC DISTANCE")));
  gio::vti_writer<3> w(d.geometry());
  w.add("label", d.label).add("distance", d.distance).add("stiffness", field);
  w.write(dir + "/voronoi.vti");
}

template <class T>
void write_shape(const std::string& dir, const gv::shape_weights<T, 3>& w, const gv::diagram<T, 3>& d, int png_node,
                 const picture_context& pc, const std::string& method) {
  const auto& g = w.geometry;
  const std::size_t n = std::size_t(g.size()), k = std::size_t(w.k);
  auto idx = planar_volume<std::uint32_t>(g, w.k);
  auto wt = planar_volume<T>(g, w.k);
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t s = 0; s < k; ++s) {
      const auto node = w.node[v * k + s];
      idx.data[s * n + v] = node < 0 ? 0u : std::uint32_t(node) + 1u;
      wt.data[s * n + v] = node < 0 ? T(0) : w.weight[v * k + s];
    }
  gio::metaimage_write_options planar;
  planar.layout = gio::channel_layout::planar;
  gio::write_metaimage(dir + "/indices_sofa_planar.mhd", idx, planar);
  gio::write_metaimage(dir + "/weights_sofa_planar.mhd", wt, planar);
  gio::write_metaimage(dir + "/indices.mhd", idx);  // interleaved: what every MetaImage reader expects
  gio::write_metaimage(dir + "/weights.mhd", wt);
  {
    // ParaView: the weights and node indices as K-component arrays (node index 0-based, -1 empty)
    std::vector<std::int32_t> nodes(n * k);
    std::vector<T> weights(n * k);
    for (std::size_t i = 0; i < n * k; ++i) {
      nodes[i] = w.node[i] < 0 ? -1 : std::int32_t(w.node[i]);
      weights[i] = w.node[i] < 0 ? T(0) : w.weight[i];
    }
    gio::vti_writer<3> vw(g);
    vw.add("label", d.label)
        .add("weights", weights.data(), weights.size(), w.k)
        .add("nodes", nodes.data(), nodes.size(), w.k);
    vw.write(dir + "/weights.vti");
  }
  auto m = w.to_sparse_matrix();
  m.makeCompressed();
  std::vector<std::int64_t> indptr(std::size_t(m.rows()) + 1);
  for (std::size_t r = 0; r < indptr.size(); ++r) indptr[r] = m.outerIndexPtr()[r];
  std::vector<std::int32_t> indices(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
  std::vector<T> data(m.valuePtr(), m.valuePtr() + m.nonZeros());
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

template <class T>
void write_shape_at(const std::string& dir, const gv::point_weights<T>& w) {
  auto m = w.to_sparse_matrix();
  m.makeCompressed();
  std::vector<std::int64_t> indptr(std::size_t(m.rows()) + 1);
  for (std::size_t r = 0; r < indptr.size(); ++r) indptr[r] = m.outerIndexPtr()[r];
  std::vector<std::int32_t> indices(m.innerIndexPtr(), m.innerIndexPtr() + m.nonZeros());
  std::vector<T> data(m.valuePtr(), m.valuePtr() + m.nonZeros());
  gio::write_npy(dir + "/weights_at_indptr.npy", indptr);
  gio::write_npy(dir + "/weights_at_indices.npy", indices);
  gio::write_npy(dir + "/weights_at_data.npy", data);
  const std::string path = dir + "/weights_at.csv";
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) throw std::runtime_error(path + ": cannot create the file");
  bool ok = std::fputs("point,node,weight\n", f) >= 0;
  for (std::size_t r = 0; ok && r + 1 < indptr.size(); ++r)
    for (auto e = indptr[r]; ok && e < indptr[r + 1]; ++e)
      if constexpr (std::is_same_v<T, float>)  // enough digits to read the value back exactly
        ok = std::fprintf(f, "%zu,%d,%.9g\n", r, int(indices[std::size_t(e)]), double(data[std::size_t(e)])) > 0;
      else
        ok = std::fprintf(f, "%zu,%d,%.17g\n", r, int(indices[std::size_t(e)]), double(data[std::size_t(e)])) > 0;
  ok = std::fclose(f) == 0 && ok;
  if (!ok) throw std::runtime_error(path + ": write failed");
}

namespace {
/// The coarse grid's shape (nz, ny, nx) and the factor, as copies.npz and copy_weights.npz hold them.
template <class T>
void add_coarse(gio::npz_entries& e, const branching_arrays<T>& g) {
  std::vector<std::int64_t> extent;
  for (int a = 2; a >= 0; --a) extent.push_back(g.coarse.extent(a));
  e.add("coarse_shape", extent).add("factor", std::vector<std::int64_t>{g.factor});
}
}  // namespace

template <class T>
void write_copies(const std::string& path, const branching_solution<T>& s) {
  const auto& g = s.grid;
  gio::npz_entries e;
  e.add("cell", g.copy_cell)
      .add("distance", s.copies.distance)
      .add("label", s.copies.label)
      .add("parent", s.copies.parent)
      .add("stiffness", g.stiffness)
      .add("voxel_count", g.voxel_count)
      .add("link_begin", g.link_begin)
      .add("link_copy", g.link_copy)
      .add("link_dir", g.link_dir)
      .add("fine_copy", g.fine_copy);
  add_coarse(e, g);
  gio::write_npz(path, e);
}

template <class T>
void write_copy_weights(const std::string& path, const branching_solution<T>& s) {
  const auto& g = s.grid;
  const auto& w = s.weights;
  gio::npz_entries e;
  const std::vector<index_t> rows{w.copies, index_t(w.k)};
  e.add("node", w.node.data(), rows)
      .add("weight", w.weight.data(), rows)
      .add("copy_cell", g.copy_cell)
      .add("copy_voxel", g.copy_voxel)
      .add("voxel_count", g.voxel_count)
      .add("fine_copy", g.fine_copy)
      .add("seed_copy", s.copies.seeds)
      .add("k", std::vector<std::int64_t>{w.k})
      .add("nodes", std::vector<std::int64_t>{std::int64_t(w.nodes)});
  add_coarse(e, g);
  gio::write_npz(path, e);
}

template void write_copies(const std::string&, const branching_solution<float>&);
template void write_copies(const std::string&, const branching_solution<double>&);
template void write_copy_weights(const std::string&, const branching_solution<float>&);
template void write_copy_weights(const std::string&, const branching_solution<double>&);

template void write_voronoi(const std::string&, const gv::diagram<float, 3>&, const gv::image<float, 3>&,
                            const picture_context&);
template void write_voronoi(const std::string&, const gv::diagram<double, 3>&, const gv::image<double, 3>&,
                            const picture_context&);
template void write_shape(const std::string&, const gv::shape_weights<float, 3>&, const gv::diagram<float, 3>&, int,
                          const picture_context&, const std::string&);
template void write_shape(const std::string&, const gv::shape_weights<double, 3>&, const gv::diagram<double, 3>&, int,
                          const picture_context&, const std::string&);
template void write_shape_at(const std::string&, const gv::point_weights<float>&);
template void write_shape_at(const std::string&, const gv::point_weights<double>&);

void summary(const char* what, const gv::grid<3>& g, std::size_t seeds, const std::string& backend, double seconds,
             const std::string& out) {
  std::printf("geovoronoi %s: %lld voxels, %zu seeds, backend %s, %.2f s, outputs in %s\n", what, (long long)g.size(),
              seeds, backend.c_str(), seconds, out.c_str());
  std::fflush(stdout);
}

void branching_summary(const char* what, const gv::grid<3>& fine, int factor, std::size_t copies, std::size_t seeds,
                       const std::string& backend, double seconds, const std::string& out) {
  std::printf("geovoronoi %s: %lld fine voxels, coarsened by %d into %zu copies (branching grid), %zu seeds, "
              "backend %s, %.2f s, outputs in %s\n",
              what, (long long)fine.size(), factor, copies, seeds, backend.c_str(), seconds, out.c_str());
  std::fflush(stdout);
}

}  // namespace gvcli

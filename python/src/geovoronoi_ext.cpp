// geovoronoi._geovoronoi: the nanobind extension behind the Python package.
//
// The Python layer (python/geovoronoi/__init__.py) normalises every argument (dtypes, axis order,
// defaults) and calls the private functions defined here, which only translate between NumPy
// buffers and the library's types (bindings.hpp; the solves are in solve.cpp, on the front end's
// typed problems). cli_main() runs the geovoronoi command line itself (`python -m geovoronoi`).

#include "bindings.hpp"
#include "run.hpp"

#include <cstdio>

#include <geovoronoi/cut_from_mesh.hpp>
#include <geovoronoi/io/mesh.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/vti.hpp>
#include <geovoronoi/voxelize.hpp>

using namespace gvpy;

namespace {
// ---- cuts -------------------------------------------------------------------------------------------

nb::dict cut_stats_dict(const gv::cut_stats& st) {
  nb::dict d;
  d["primitives"] = st.primitives;
  d["degenerate"] = st.degenerate;
  d["voxels_visited"] = st.voxels_visited;
  d["edges_tested"] = st.edges_tested;
  return d;
}

/// A mesh from (n, 3) float64 vertices in array-axis order (z, y, x) and (m, 3) int64 triangles.
gv::triangle_mesh mesh_from_arrays(const in_array& vertices, const in_array& triangles) {
  if (vertices.dtype() != nb::dtype<double>() || vertices.ndim() != 2 || vertices.shape(1) != 3)
    throw std::invalid_argument("geovoronoi: vertices must be an (n, 3) float64 array");
  if (triangles.dtype() != nb::dtype<std::int64_t>() || triangles.ndim() != 2 || triangles.shape(1) != 3)
    throw std::invalid_argument("geovoronoi: triangles must be an (m, 3) int64 array");
  gv::triangle_mesh mesh;
  const auto* vp = static_cast<const double*>(vertices.data());
  for (std::size_t i = 0; i < vertices.shape(0); ++i) mesh.vertices.push_back({vp[3 * i + 2], vp[3 * i + 1], vp[3 * i]});
  const auto* tp = static_cast<const std::int64_t*>(triangles.data());
  for (std::size_t t = 0; t < triangles.shape(0); ++t) {
    std::array<std::uint32_t, 3> tri{};
    for (int k = 0; k < 3; ++k) {
      const std::int64_t x = tp[3 * t + std::size_t(k)];
      if (x < 0 || std::uint64_t(x) >= vertices.shape(0))
        throw std::invalid_argument("geovoronoi: triangle " + std::to_string(t) + " refers to vertex " + std::to_string(x) +
                                    " of " + std::to_string(vertices.shape(0)));
      tri[std::size_t(k)] = std::uint32_t(x);
    }
    mesh.triangles.push_back(tri);
  }
  return mesh;
}

/// (cut, stats) of a triangle mesh whose vertices are world points in array-axis order (z, y, x).
nb::object cut_from_mesh_entry(in_array vertices, in_array triangles, std::vector<std::size_t> shape,
                               std::vector<double> spacing, std::vector<double> origin, std::vector<double> orientation,
                               int connectivity) {
  const gv::triangle_mesh mesh = mesh_from_arrays(vertices, triangles);
  const auto g = make_grid<3>(shape, spacing, origin, orientation);
  const auto plain = make_grid<3>(shape, spacing, origin);
  cut_handle h;
  h.connectivity = connectivity;
  gv::cut_stats st;
  {
    nb::gil_scoped_release release;
    gvcli::with_connectivity<3>(gvcli::check_connectivity(connectivity, 3), [&](auto conn) {
      h.s = std::make_shared<const std::variant<gv::cut_set<2>, gv::cut_set<3>>>(
          rehome(gv::cut_from_mesh(g, conn, mesh, &st), plain, conn));
    });
  }
  return nb::make_tuple(h, cut_stats_dict(st));
}

using voxelize_mesh = std::tuple<in_array, in_array, double, int, std::string>;  // vertices, triangles, value, label, name

/// The library's voxelize() of the parts @p meshes: (stiffness, label, fraction or None, spacing,
/// origin, orientation, stats) with arrays [z, y, x], spacing and origin in array-axis order and the
/// orientation's rows and columns too. @p voxel_size and @p voxels arrive in array-axis order (one of
/// them empty).
template <class T>
nb::object voxelize_typed(const std::vector<gv::voxelize_part>& parts, const gv::voxelize_options& o) {
  gv::voxelization<T> v;
  {
    nb::gil_scoped_release release;
    v = gv::voxelize<T>(parts, o);
  }
  const auto& g = v.label.geometry();
  const auto shape = array_shape(g);
  std::vector<double> spacing, origin, orient;
  for (int a = 2; a >= 0; --a) spacing.push_back(g.spacing(a)), origin.push_back(g.origin()[std::size_t(a)]);
  for (int r = 2; r >= 0; --r)
    for (int c = 2; c >= 0; --c) orient.push_back(g.direction()[std::size_t(3 * r + c)]);
  nb::dict st;
  st["triangles"] = v.stats.triangles;
  st["degenerate"] = v.stats.degenerate;
  st["crossings"] = v.stats.crossings;
  st["inside_voxels"] = v.stats.inside_voxels;
  st["mesh_volume"] = v.stats.mesh_volume;
  nb::object fraction = nb::none();
  if (v.fraction.size() > 0) fraction = vector_to_numpy(std::move(v.fraction.values()), shape);
  return nb::make_tuple(vector_to_numpy(std::move(v.stiffness.values()), shape),
                        vector_to_numpy(std::move(v.label.values()), shape), fraction, spacing, origin,
                        vector_to_numpy(std::move(orient), {3, 3}), st);
}

nb::object voxelize_entry(std::vector<voxelize_mesh> meshes, std::vector<double> voxel_size,
                          std::vector<std::int64_t> voxels, std::int64_t pad, bool rotate, bool winding,
                          const std::string& overlap, bool surface_inside, int fraction, double outside_value,
                          bool in_double) {
  std::vector<gv::voxelize_part> parts;
  for (const auto& m : meshes) {
    gv::voxelize_part p;
    p.mesh = mesh_from_arrays(std::get<0>(m), std::get<1>(m));
    p.value = std::get<2>(m);
    p.label = gv::label_t(std::get<3>(m));
    p.name = std::get<4>(m);
    parts.push_back(std::move(p));
  }
  gv::voxelize_options o;
  if (voxel_size.size() == 3)
    for (int a = 0; a < 3; ++a) o.voxel_size[a] = voxel_size[std::size_t(2 - a)];
  if (voxels.size() == 3)
    for (int a = 0; a < 3; ++a) o.voxels[a] = index_t(voxels[std::size_t(2 - a)]);
  o.pad = index_t(pad);
  o.principal_axes = rotate;
  o.rule = winding ? gv::inside_rule::winding : gv::inside_rule::closed;
  if (overlap == "last") o.overlap = gv::overlap_rule::last_wins;
  else if (overlap == "first") o.overlap = gv::overlap_rule::first_wins;
  else if (overlap == "max") o.overlap = gv::overlap_rule::max_value;
  else if (overlap == "min") o.overlap = gv::overlap_rule::min_value;
  else if (overlap == "error") o.overlap = gv::overlap_rule::error;
  else throw std::invalid_argument("geovoronoi: overlap must be last, first, max, min or error");
  o.surface_inside = surface_inside;
  o.fraction_samples = fraction;
  o.outside_value = outside_value;
  return in_double ? voxelize_typed<double>(parts, o) : voxelize_typed<float>(parts, o);
}

/// (cut, stats) of 2D polylines whose points are world points in array-axis order (y, x).
nb::object cut_from_polylines_entry(std::vector<in_array> lines, std::vector<std::size_t> shape,
                                    std::vector<double> spacing, std::vector<double> origin,
                                    std::vector<double> orientation, int connectivity) {
  std::vector<std::vector<gv::point<2>>> pl;
  for (std::size_t l = 0; l < lines.size(); ++l) {
    const auto& a = lines[l];
    if (a.dtype() != nb::dtype<double>() || a.ndim() != 2 || a.shape(1) != 2)
      throw std::invalid_argument("geovoronoi: polyline " + std::to_string(l) + " must be an (n, 2) float64 array");
    const auto* p = static_cast<const double*>(a.data());
    std::vector<gv::point<2>> line;
    for (std::size_t i = 0; i < a.shape(0); ++i) line.push_back({p[2 * i + 1], p[2 * i]});
    pl.push_back(std::move(line));
  }
  const auto g = make_grid<2>(shape, spacing, origin, orientation);
  const auto plain = make_grid<2>(shape, spacing, origin);
  cut_handle h;
  h.connectivity = connectivity;
  gv::cut_stats st;
  {
    nb::gil_scoped_release release;
    gvcli::with_connectivity<2>(gvcli::check_connectivity(connectivity, 2), [&](auto conn) {
      h.s = std::make_shared<const std::variant<gv::cut_set<2>, gv::cut_set<3>>>(
          rehome(gv::cut_from_polylines(g, conn, pl, &st), plain, conn));
    });
  }
  return nb::make_tuple(h, cut_stats_dict(st));
}

std::size_t cut_size(const cut_handle& h) {
  return h.s ? std::visit([](const auto& c) { return c.size(); }, *h.s) : 0;
}

cut_handle cut_merge(const cut_handle& a, const cut_handle& b) {
  if (!a.s) return b;
  if (!b.s) return a;
  if (a.s->index() != b.s->index() || a.connectivity != b.connectivity)
    throw std::invalid_argument("geovoronoi: the two cuts belong to grids of different dimensions or connectivities");
  cut_handle out;
  out.connectivity = a.connectivity;
  std::visit(
      [&](const auto& x) {
        using S = std::decay_t<decltype(x)>;
        S m = x;
        m.merge(std::get<S>(*b.s));
        out.s = std::make_shared<const std::variant<gv::cut_set<2>, gv::cut_set<3>>>(std::move(m));
      },
      *a.s);
  return out;
}

/// The cut edges as an (m, 2) array of flat C-order voxel indices (u, v), u < v, sorted.
nb::object cut_edges(const cut_handle& h) {
  std::vector<std::int64_t> e;
  if (h.s)
    std::visit(
        [&](const auto& c) {
          c.for_each_edge([&](index_t u, int d) {
            e.push_back(u);
            e.push_back(c.neighbour(u, d));
          });
        },
        *h.s);
  const std::size_t m = e.size() / 2;
  return vector_to_numpy(std::move(e), {m, 2});
}

bool cut_equal(const cut_handle& a, const cut_handle& b) {
  if (!a.s || !b.s) return cut_size(a) == 0 && cut_size(b) == 0;
  return *a.s == *b.s;
}

/// (vertices (n, 3) in array-axis order z, y, x, triangles (m, 3) int64) of an STL or OBJ file.
nb::object read_mesh_entry(const std::string& path) {
  const gv::triangle_mesh m = gio::read_mesh(path);
  std::vector<double> v;
  v.reserve(3 * m.vertices.size());
  for (const auto& p : m.vertices) {
    v.push_back(p[2]);
    v.push_back(p[1]);
    v.push_back(p[0]);
  }
  std::vector<std::int64_t> t;
  t.reserve(3 * m.triangles.size());
  for (const auto& tri : m.triangles)
    for (int k = 0; k < 3; ++k) t.push_back(tri[std::size_t(k)]);
  const std::size_t nv = m.vertices.size(), nt = m.triangles.size();
  return nb::make_tuple(vector_to_numpy(std::move(v), {nv, 3}), vector_to_numpy(std::move(t), {nt, 3}));
}

// ---- images ---------------------------------------------------------------------------------------

template <class T>
nb::object volume_to_numpy(gio::volume<T>&& v) {
  // planar channels [c][z][y][x] -> NumPy [z, y, x, c] (interleaved) when there are several
  std::vector<std::size_t> shape;
  for (int a = v.dims - 1; a >= 0; --a) shape.push_back(std::size_t(v.extents[std::size_t(a)]));
  if (v.channels > 1) {
    const std::size_t n = std::size_t(v.voxels()), c = std::size_t(v.channels);
    std::vector<T> inter(v.data.size());
    for (std::size_t ch = 0; ch < c; ++ch)
      for (std::size_t i = 0; i < n; ++i) inter[i * c + ch] = v.data[ch * n + i];
    shape.push_back(c);
    return vector_to_numpy(std::move(inter), shape);
  }
  return vector_to_numpy(std::move(v.data), shape);
}

/// (array, spacing, origin, orientation) with spacing/origin in array-axis order and the
/// orientation as a dims x dims matrix whose rows and columns are in array-axis order too.
template <class T>
nb::object read_typed(const std::string& path, int dims_hint) {
  (void)dims_hint;
  auto v = gio::read_metaimage<T>(path);
  const int d = std::max(1, v.dims);
  std::vector<double> spacing, origin, orient;
  for (int a = d - 1; a >= 0; --a) {
    spacing.push_back(v.spacing[std::size_t(a)]);
    origin.push_back(v.origin[std::size_t(a)]);
  }
  for (int r = d - 1; r >= 0; --r)
    for (int c = d - 1; c >= 0; --c) orient.push_back(v.orientation[std::size_t(3 * r + c)]);
  nb::object arr = volume_to_numpy(std::move(v));
  return nb::make_tuple(arr, spacing, origin, vector_to_numpy(std::move(orient), {std::size_t(d), std::size_t(d)}));
}

nb::object read_image(const std::string& path) {
  const auto h = gio::read_metaimage_header(path);
  switch (h.type) {
    case gio::element_type::int8: return read_typed<std::int8_t>(path, h.ndims);
    case gio::element_type::uint8: return read_typed<std::uint8_t>(path, h.ndims);
    case gio::element_type::int16: return read_typed<std::int16_t>(path, h.ndims);
    case gio::element_type::uint16: return read_typed<std::uint16_t>(path, h.ndims);
    case gio::element_type::int32: return read_typed<std::int32_t>(path, h.ndims);
    case gio::element_type::uint32: return read_typed<std::uint32_t>(path, h.ndims);
    case gio::element_type::int64: return read_typed<std::int64_t>(path, h.ndims);
    case gio::element_type::uint64: return read_typed<std::uint64_t>(path, h.ndims);
    case gio::element_type::float32: return read_typed<float>(path, h.ndims);
    case gio::element_type::float64: return read_typed<double>(path, h.ndims);
  }
  throw std::invalid_argument(path + ": unsupported element type");
}

template <class T>
void write_typed(const std::string& path, const in_array& a, int dims, int channels, const std::vector<double>& spacing,
                 const std::vector<double>& origin, const std::vector<double>& orientation, bool planar, bool compress) {
  gio::volume<T> v;
  v.dims = dims;
  for (int ax = 0; ax < dims; ++ax) {
    const std::size_t r = std::size_t(dims - 1 - ax);
    v.extents[std::size_t(ax)] = index_t(a.shape(r));
    v.spacing[std::size_t(ax)] = spacing[r];
    v.origin[std::size_t(ax)] = origin[r];
  }
  for (int r = 0; r < dims; ++r)
    for (int c = 0; c < dims; ++c)
      v.orientation[std::size_t(3 * r + c)] = orientation[std::size_t((dims - 1 - r) * dims + (dims - 1 - c))];
  v.channels = channels;
  const T* p = static_cast<const T*>(a.data());
  const std::size_t n = std::size_t(v.voxels()), c = std::size_t(channels);
  v.data.resize(n * c);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t ch = 0; ch < c; ++ch) v.data[ch * n + i] = p[i * c + ch];
  gio::metaimage_write_options opt;
  opt.compress = compress;
  opt.layout = planar ? gio::channel_layout::planar : gio::channel_layout::interleaved;
  gio::write_metaimage(path, v, opt);
}

void write_image(const std::string& path, in_array a, int channels, std::vector<double> spacing, std::vector<double> origin,
                 std::vector<double> orientation, bool planar, bool compress) {
  const int dims = int(a.ndim()) - (channels > 1 ? 1 : 0);
  if (dims < 1 || dims > 3) throw std::invalid_argument("geovoronoi: write_image needs a 1D, 2D or 3D array");
  if (spacing.size() != std::size_t(dims) || origin.size() != std::size_t(dims) ||
      orientation.size() != std::size_t(dims * dims))
    throw std::invalid_argument("geovoronoi: spacing/origin/orientation do not match the array's dimensions");
  const auto dt = a.dtype();
#define GV_WRITE(TYPE) \
  if (dt == nb::dtype<TYPE>()) return write_typed<TYPE>(path, a, dims, channels, spacing, origin, orientation, planar, compress);
  GV_WRITE(std::int8_t) GV_WRITE(std::uint8_t) GV_WRITE(std::int16_t) GV_WRITE(std::uint16_t) GV_WRITE(std::int32_t)
  GV_WRITE(std::uint32_t) GV_WRITE(std::int64_t) GV_WRITE(std::uint64_t) GV_WRITE(float) GV_WRITE(double)
#undef GV_WRITE
  throw nb::type_error("geovoronoi: write_image supports (u)int8/16/32/64, float32 and float64 arrays");
}

template <int Dim>
void write_vti_dim(const std::string& path, const std::vector<std::pair<std::string, in_array>>& arrays,
                   const std::vector<std::size_t>& shape, const std::vector<double>& spacing,
                   const std::vector<double>& origin, const std::vector<double>& orientation) {
  gio::vti_writer<Dim> w(make_grid<Dim>(shape, spacing, origin, orientation));
  for (const auto& [name, a] : arrays) {
    std::size_t count = 1;
    for (std::size_t i = 0; i < a.ndim(); ++i) count *= a.shape(i);
    const int comps = a.ndim() > std::size_t(Dim) ? int(a.shape(Dim)) : 1;
    const auto dt = a.dtype();
#define GV_ADD(TYPE) \
  if (dt == nb::dtype<TYPE>()) { w.add(name, static_cast<const TYPE*>(a.data()), count, comps); continue; }
    GV_ADD(std::int8_t) GV_ADD(std::uint8_t) GV_ADD(std::int16_t) GV_ADD(std::uint16_t) GV_ADD(std::int32_t)
    GV_ADD(std::uint32_t) GV_ADD(std::int64_t) GV_ADD(std::uint64_t) GV_ADD(float) GV_ADD(double)
#undef GV_ADD
    throw nb::type_error(("geovoronoi: write_vti: array '" + name + "' has an unsupported dtype").c_str());
  }
  w.write(path);
}

void write_vti(const std::string& path, std::vector<std::pair<std::string, in_array>> arrays,
               std::vector<std::size_t> shape, std::vector<double> spacing, std::vector<double> origin,
               std::vector<double> orientation) {
  if (shape.size() == 2) return write_vti_dim<2>(path, arrays, shape, spacing, origin, orientation);
  if (shape.size() == 3) return write_vti_dim<3>(path, arrays, shape, spacing, origin, orientation);
  throw std::invalid_argument("geovoronoi: write_vti needs 2D or 3D arrays");
}

/// The geovoronoi command line (the tool's gvcli::run()) on @p args, with the GIL released; its
/// output is flushed before returning, so that it comes before anything Python prints next.
int cli_main(const std::vector<std::string>& args) {
  nb::gil_scoped_release release;
  const int rc = gvcli::run(args);
  std::fflush(stdout);
  std::fflush(stderr);
  return rc;
}

}  // namespace

NB_MODULE(_geovoronoi, m) {
  m.doc() = "Private extension of the geovoronoi package; use the functions of `geovoronoi` instead.";

  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const gio::out_of_memory& e) {
      PyErr_SetString(PyExc_MemoryError, e.what());
    } catch (const gio::io_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const gv::cancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const gv::metric_error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    } catch (const gvcli::usage_error& e) {  // the front end's checks of names (metric, backend, ...)
      PyErr_SetString(PyExc_ValueError, (std::string("geovoronoi: ") + e.what()).c_str());
    }
  });

  nb::class_<diagram_handle>(m, "_DiagramHandle", "Owner of a diagram's memory (private).")
      .def("_cuts", [](const diagram_handle& h) { return h.cuts; });
  nb::class_<cut_handle>(m, "_CutHandle", "A set of cut grid edges (private; use geovoronoi.Cut).")
      .def("__len__", &cut_size)
      .def("_merge", &cut_merge)
      .def("_edges", &cut_edges)
      .def("_equal", &cut_equal)
      .def_ro("_connectivity", &cut_handle::connectivity);
  nb::class_<shape_state_handle>(m, "_ShapeStateHandle",
                                 "Distance Ratio's kept searches (private; use geovoronoi.ShapeState).")
      .def_ro("nbytes", &shape_state_handle::nbytes);

  m.def("_voronoi", &voronoi_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("metric"), nb::arg("connectivity"), nb::arg("backend"), nb::arg("threads"),
        nb::arg("seeds").noconvert(), nb::arg("world"), nb::arg("with_parent"),
        nb::arg("progress").none(), nb::arg("cut").none() = nb::none(),
        "Private: voronoi() after the Python layer normalised its arguments.");
  m.def("_branching_grid", &branching_grid_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("orientation"), nb::arg("factor"), nb::arg("connectivity"), nb::arg("reduction"),
        "Private: branching_grid() after the Python layer normalised its arguments.");
  m.def("_branching_voronoi", &branching_voronoi_entry, nb::arg("field").noconvert(), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"), nb::arg("factor"), nb::arg("connectivity"), nb::arg("reduction"),
        nb::arg("metric"), nb::arg("backend"), nb::arg("threads"), nb::arg("seeds").noconvert(),
        nb::arg("progress").none(), nb::arg("cut").none() = nb::none(),
        "Private: voronoi(..., coarsen=N) after the Python layer normalised its arguments.");
  m.def("_branching_update", &branching_update_entry, nb::arg("field").noconvert(), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"), nb::arg("factor"), nb::arg("connectivity"), nb::arg("reduction"),
        nb::arg("metric"), nb::arg("backend"), nb::arg("threads"), nb::arg("seeds").noconvert(),
        nb::arg("before_cut").none(), nb::arg("all"), nb::arg("distance").noconvert(), nb::arg("label").noconvert(),
        nb::arg("parent").noconvert(), nb::arg("seed_copies").noconvert(),
        "Private: update() of a BranchingDiagram after the Python layer normalised its arguments.");
  m.def("_branching_shape_functions", &branching_shape_entry, nb::arg("field").noconvert(), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"), nb::arg("factor"), nb::arg("connectivity"), nb::arg("reduction"),
        nb::arg("metric"), nb::arg("backend"), nb::arg("threads"), nb::arg("seeds").noconvert(), nb::arg("method"),
        nb::arg("k"), nb::arg("progress").none(), nb::arg("points").none(), nb::arg("cut").none(),
        "Private: shape_functions(..., coarsen=N) after the Python layer normalised its arguments.");
  m.def("_update", &update_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("metric"), nb::arg("connectivity"), nb::arg("before"), nb::arg("cut").none(), nb::arg("all").none(),
        nb::arg("carved").none(), nb::arg("added").none(), nb::arg("restiffened").none(), nb::arg("nodes"),
        "Private: update() after the Python layer normalised its arguments.");
  m.def("_update_shape_functions", &shape_update_entry, nb::arg("field").noconvert(), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("metric"), nb::arg("connectivity"), nb::arg("backend"), nb::arg("threads"),
        nb::arg("before"), nb::arg("after"), nb::arg("cut").none(), nb::arg("all").none(), nb::arg("carved").none(),
        nb::arg("added").none(), nb::arg("restiffened").none(), nb::arg("nodes"), nb::arg("method"), nb::arg("k"),
        nb::arg("batch_size"), nb::arg("progress").none(), nb::arg("old_node").noconvert(),
        nb::arg("old_weight").noconvert(), nb::arg("old_nodes"), nb::arg("points").none(), nb::arg("state").none(),
        "Private: update_shape_functions() after the Python layer normalised its arguments.");
  m.def("_cut_from_mesh", &cut_from_mesh_entry, nb::arg("vertices").noconvert(), nb::arg("triangles").noconvert(),
        nb::arg("shape"), nb::arg("spacing"), nb::arg("origin"), nb::arg("orientation"), nb::arg("connectivity"));
  m.def("_cut_from_polylines", &cut_from_polylines_entry, nb::arg("lines"), nb::arg("shape"), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"), nb::arg("connectivity"));
  m.def("_read_mesh", &read_mesh_entry, nb::arg("path"));
  m.def("_voxelize", &voxelize_entry, nb::arg("meshes"), nb::arg("voxel_size"), nb::arg("voxels"), nb::arg("pad"),
        nb::arg("rotate"), nb::arg("winding"), nb::arg("overlap"), nb::arg("surface_inside"), nb::arg("fraction"),
        nb::arg("outside_value"), nb::arg("double"));
  m.def("_shape_functions", &shape_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("metric"), nb::arg("connectivity"), nb::arg("backend"), nb::arg("threads"), nb::arg("diagram"),
        nb::arg("method"), nb::arg("k"), nb::arg("batch_size"), nb::arg("progress").none(),
        nb::arg("points").none(), nb::arg("keep"),
        "Private: shape_functions() after the Python layer normalised its arguments.");
  m.def("_read_image", &read_image, nb::arg("path"));
  m.def("_write_image", &write_image, nb::arg("path"), nb::arg("array").noconvert(), nb::arg("channels"),
        nb::arg("spacing"), nb::arg("origin"), nb::arg("orientation"), nb::arg("planar"), nb::arg("compress"));
  m.def("_write_vti", &write_vti, nb::arg("path"), nb::arg("arrays"), nb::arg("shape"), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"));
  m.def("_last_field_address", []() { return std::uintptr_t(last_field_address.load()); },
        "Test hook: address of the field buffer the last solve viewed.");
  m.def("_last_core_seconds", []() { return last_core_seconds.load(); },
        "Benchmark hook: wall time of the last library call alone.");
  m.def("_last_backend", []() -> std::string {
    const int b = last_backend.load();
    return b == 1 ? "thrust" : b == 0 ? "seq" : "";
  }, "Test hook: the backend the last solve or shape-function call ran on.");
  m.def("_backends", []() {
    std::vector<std::string> names;
    for (const auto& b : gvcli::backends())
      if (b.built()) names.push_back(b.name);
    return names;
  }, "The backends built into the package.");
  m.def("_default_backend", []() -> std::string { return gvcli::default_backend().name; },
        "The machine-level default backend (what backend=\"auto\" picks for a large problem).");
  m.def("cli_main", &cli_main, nb::arg("args"),
        "Runs the geovoronoi command line on args (without the program name) and returns its exit code: "
        "0 success, 2 usage or bad input, 1 runtime failure (docs/cli.md).");
  m.def("_metaimage_has_zlib", []() { return gio::metaimage_has_zlib; });
}

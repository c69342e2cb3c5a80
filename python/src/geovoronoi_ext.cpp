// geovoronoi._geovoronoi: the nanobind extension behind the Python package.
//
// The Python layer (python/geovoronoi/__init__.py) normalises every argument (dtypes, axis order,
// defaults) and calls the private functions defined here, which only translate between NumPy
// buffers and the library's types (bindings.hpp holds the translation and the solve wrappers; the
// wrappers are compiled per dtype in solve_float.cpp and solve_double.cpp).

#include "bindings.hpp"

#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/vti.hpp>

using namespace gvpy;

namespace {
nb::object voronoi_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                         int connectivity, std::string backend, int threads, in_array seeds, bool world,
                         bool with_parent, nb::object progress) {
  problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, std::move(backend), threads};
  const bool f32 = field.dtype() == nb::dtype<float>(), f64 = field.dtype() == nb::dtype<double>();
  if (!f32 && !f64) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  return f32 ? voronoi_typed<float>(a, seeds, world, with_parent, progress)
             : voronoi_typed<double>(a, seeds, world, with_parent, progress);
}

nb::object shape_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                       int connectivity, std::string backend, int threads, diagram_handle& h, std::string method, int k,
                       std::size_t batch_size, nb::object progress, std::optional<in_array> points) {
  problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, std::move(backend), threads};
  const bool f32 = field.dtype() == nb::dtype<float>(), f64 = field.dtype() == nb::dtype<double>();
  if (!f32 && !f64) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  return f32 ? shape_typed<float>(a, h, method, k, batch_size, progress, points)
             : shape_typed<double>(a, h, method, k, batch_size, progress, points);
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

}  // namespace

NB_MODULE(_geovoronoi, m) {
  m.doc() = "Private extension of the geovoronoi package; use the functions of `geovoronoi` instead.";

  nb::register_exception_translator([](const std::exception_ptr& p, void*) {
    try {
      std::rethrow_exception(p);
    } catch (const gio::io_error& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const gv::cancelled& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    } catch (const gv::metric_error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });

  nb::class_<diagram_handle>(m, "_DiagramHandle", "Owner of a diagram's memory (private).");

  m.def("_voronoi", &voronoi_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("metric"), nb::arg("connectivity"), nb::arg("backend"), nb::arg("threads"),
        nb::arg("seeds").noconvert(), nb::arg("world"), nb::arg("with_parent"),
        nb::arg("progress").none(), "Private: voronoi() after the Python layer normalised its arguments.");
  m.def("_shape_functions", &shape_entry, nb::arg("field").noconvert(), nb::arg("spacing"), nb::arg("origin"),
        nb::arg("metric"), nb::arg("connectivity"), nb::arg("backend"), nb::arg("threads"), nb::arg("diagram"),
        nb::arg("method"), nb::arg("k"), nb::arg("batch_size"), nb::arg("progress").none(),
        nb::arg("points").none(), "Private: shape_functions() after the Python layer normalised its arguments.");
  m.def("_read_image", &read_image, nb::arg("path"));
  m.def("_write_image", &write_image, nb::arg("path"), nb::arg("array").noconvert(), nb::arg("channels"),
        nb::arg("spacing"), nb::arg("origin"), nb::arg("orientation"), nb::arg("planar"), nb::arg("compress"));
  m.def("_write_vti", &write_vti, nb::arg("path"), nb::arg("arrays"), nb::arg("shape"), nb::arg("spacing"),
        nb::arg("origin"), nb::arg("orientation"));
  m.def("_last_field_address", []() { return std::uintptr_t(last_field_address.load()); },
        "Test hook: address of the field buffer the last solve viewed.");
  m.def("_last_core_seconds", []() { return last_core_seconds.load(); },
        "Benchmark hook: wall time of the last library call alone.");
  m.def("_backends", []() {
    std::vector<std::string> b{"seq"};
    if (thrust_built()) b.push_back("thrust");
    return b;
  });
  m.def("_resolve_backend", &resolve_backend, nb::arg("backend"));
  m.def("_metaimage_has_zlib", []() { return gio::metaimage_has_zlib; });
}

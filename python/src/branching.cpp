// The extension's branching grids (gv.branching_grid(), gv.voronoi(..., coarsen=N)) on the front end's
// branching unit (tools/geovoronoi/branching.hpp), which the command-line tool shares: this file only
// translates the arguments and hands the arrays to NumPy (axes [z, y, x]).

#include "bindings.hpp"
#include "branching.hpp"

namespace gvpy {

namespace {

/// The 3D grid of @p field with spacing, origin and orientation in array-axis order.
gv::grid<3> branching_field_grid(const in_array& field, const std::vector<double>& spacing,
                                 const std::vector<double>& origin, const std::vector<double>& orientation) {
  if (field.ndim() != 3)
    throw std::invalid_argument("geovoronoi: branching grids (coarsen=) need a 3D field, got " +
                                std::to_string(field.ndim()) + " dimensions");
  std::vector<std::size_t> shape(3);
  for (std::size_t i = 0; i < 3; ++i) shape[i] = field.shape(i);
  return make_grid<3>(shape, spacing, origin, orientation);
}

/// (x, y, z) values -> a tuple in array-axis order.
template <class V>
nb::tuple reversed3(const V& v) {
  return nb::make_tuple(v[2], v[1], v[0]);
}

/// The grid's arrays as a dict (names of gv.BranchingGrid).
template <class T>
nb::dict grid_dict(gvcli::branching_arrays<T>&& a, int connectivity, gv::stiffness_reduction r) {
  nb::dict d;
  const auto& c = a.coarse;
  const std::size_t copies = std::size_t(a.copies()), links = a.link_copy.size();
  d["factor"] = a.factor;
  d["connectivity"] = connectivity;
  d["reduction"] = std::string(gvcli::reduction_name(r));
  d["coarse_shape"] = nb::make_tuple(c.extent(2), c.extent(1), c.extent(0));
  d["coarse_spacing"] = reversed3(c.spacing());
  d["coarse_origin"] = reversed3(c.origin());
  const std::vector<std::size_t> fine_shape{std::size_t(a.fine_copy.geometry().extent(2)),
                                            std::size_t(a.fine_copy.geometry().extent(1)),
                                            std::size_t(a.fine_copy.geometry().extent(0))};
  const std::size_t cells = std::size_t(c.size());
  d["cell"] = vector_to_numpy(std::move(a.copy_cell), {copies});
  d["cell_begin"] = vector_to_numpy(std::move(a.cell_begin), {cells + 1});
  d["copy_voxel"] = vector_to_numpy(std::move(a.copy_voxel), {copies});
  d["voxel_count"] = vector_to_numpy(std::move(a.voxel_count), {copies});
  d["stiffness"] = vector_to_numpy(std::move(a.stiffness), {copies});
  d["link_begin"] = vector_to_numpy(std::move(a.link_begin), {copies + 1});
  d["link_copy"] = vector_to_numpy(std::move(a.link_copy), {links});
  d["link_dir"] = vector_to_numpy(std::move(a.link_dir), {links});
  d["fine_copy"] = vector_to_numpy(std::move(a.fine_copy.values()), fine_shape);
  return d;
}

template <class T>
gv::image_view<const T, 3> branching_view(const in_array& field, const gv::grid<3>& g) {
  const T* data = static_cast<const T*>(field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(data);
  return gv::image_view<const T, 3>(g, data);
}

}  // namespace

nb::object branching_grid_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                std::vector<double> orientation, int factor, int connectivity, std::string reduction) {
  const gv::grid<3> g = branching_field_grid(field, spacing, origin, orientation);
  const int conn = gvcli::check_connectivity(connectivity, 3);
  const auto r = gvcli::parse_reduction(reduction);
  const bool f32 = field.dtype() == nb::dtype<float>();
  if (!f32 && field.dtype() != nb::dtype<double>()) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  if (f32) {
    gvcli::branching_arrays<float> a;
    {
      nb::gil_scoped_release release;
      a = gvcli::build_branching<float>(branching_view<float>(field, g), factor, conn, r);
    }
    return grid_dict(std::move(a), conn, r);
  }
  gvcli::branching_arrays<double> a;
  {
    nb::gil_scoped_release release;
    a = gvcli::build_branching<double>(branching_view<double>(field, g), factor, conn, r);
  }
  return grid_dict(std::move(a), conn, r);
}

namespace {

/// What the Python layer asks beyond the diagram: the shape functions (method, K) and the points (fine
/// voxels), and the cut.
struct branching_request {
  bool shapes = false;
  gv::shape_options shape;
  std::vector<gv::coord<3>> points;
  bool at = false;
  std::optional<gv::cut_set<3>> cut;
};

/// The fine grid's copy of the cut of @p h (made on the grid without orientation) under @p connectivity.
std::optional<gv::cut_set<3>> fine_cut(const std::optional<cut_handle>& h, const gv::grid<3>& g, int connectivity) {
  if (!h || h->empty()) return std::nullopt;
  const gv::grid<3> plain(g.extents(), g.spacing(), g.origin());
  const auto& cs = cut_of<3>(*h, plain, connectivity);
  std::optional<gv::cut_set<3>> out;
  gvcli::with_connectivity<3>(connectivity, [&](auto conn) { out = rehome(cs, g, conn); });
  return out;
}

template <class T>
nb::object branching_impl(const in_array& field, const gv::grid<3>& g, const gvcli::branching_key& key, int threads,
                          const in_array& seeds, nb::object progress, const branching_request& req) {
  const auto coords = seeds_to_coords<3>(g, seeds, false);
  gv::solve_options opt;
  opt.threads = threads > 0 ? unsigned(threads) : 0u;
  progress_bridge bridge{progress, 0.0, std::nullopt};
  opt.progress = [&](double f) { return bridge(f); };
  gv::shape_options shape = req.shape;
  shape.progress = opt.progress;
  gvcli::branching_extras x;
  x.cut = req.cut ? &*req.cut : nullptr;
  x.shape = req.shapes ? &shape : nullptr;
  x.at = req.at ? &req.points : nullptr;
  gvcli::branching_solution<T> s;
  try {
    nb::gil_scoped_release release;
    thread_count_scope scope(threads);
    const auto t0 = std::chrono::steady_clock::now();
    s = req.shapes ? gvcli::solve_branching_shapes<T>(key, branching_view<T>(field, g), coords, opt, x)
                   : gvcli::solve_branching<T>(key, branching_view<T>(field, g), coords, opt, x.cut);
    last_core_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const gv::cancelled&) {
    if (bridge.error) throw std::move(*bridge.error);
    throw;
  }
  if (bridge.error) throw std::move(*bridge.error);
  bridge.finish();
  last_backend = key.backend == gvcli::backend_id::thrust ? 1 : 0;
  const std::size_t copies = std::size_t(s.grid.copies());
  const std::vector<std::size_t> fine_shape{std::size_t(g.extent(2)), std::size_t(g.extent(1)), std::size_t(g.extent(0))};
  nb::dict d;
  d["grid"] = grid_dict(std::move(s.grid), key.connectivity, key.reduction);
  d["distance"] = vector_to_numpy(std::move(s.copies.distance), {copies});
  d["label"] = vector_to_numpy(std::move(s.copies.label), {copies});
  d["parent"] = vector_to_numpy(std::move(s.copies.parent), {copies});
  d["seed_copies"] = vector_to_numpy(std::move(s.copies.seeds), {coords.size()});
  d["fine_distance"] = vector_to_numpy(std::move(s.fine.distance.values()), fine_shape);
  d["fine_label"] = vector_to_numpy(std::move(s.fine.label.values()), fine_shape);
  if (s.has_weights) {
    auto& w = s.weights;
    const std::size_t k = std::size_t(w.k), nodes = w.nodes;
    d["copy_weights"] = weights_to_python(std::move(w.node), std::move(w.weight), copies, k, nodes, {copies});
    auto& f = s.fine_weights;
    d["fine_weights"] = weights_to_python(std::move(f.node), std::move(f.weight), std::size_t(g.size()), k, nodes,
                                          fine_shape);
  }
  if (s.has_at) {
    auto& w = s.at_weights;
    const std::size_t n = w.points;
    d["at"] = weights_to_python(std::move(w.node), std::move(w.weight), n, std::size_t(w.k), w.nodes, {n});
  }
  return d;
}

/// The key of a branching run from the Python layer's (checked) names; backend "auto" runs seq.
gvcli::branching_key branching_key_of(int factor, int connectivity, const std::string& reduction,
                                      const std::string& metric, const std::string& backend, int threads) {
  gvcli::branching_key key;
  key.connectivity = gvcli::check_connectivity(connectivity, 3);
  key.reduction = gvcli::parse_reduction(reduction);
  key.metric = gvcli::parse_metric(metric);
  key.factor = factor;
  const gvcli::backend* b = gvcli::parse_backend(backend, true);
  key.backend = b ? b->id : gvcli::backend_id::seq;  // auto: seq (the branching solve's default)
  if (key.backend == gvcli::backend_id::seq && threads > 1)
    throw std::invalid_argument("geovoronoi: backend 'seq' runs on one thread; threads=" + std::to_string(threads) +
                                " needs backend 'thrust'");
  return key;
}

nb::object branching_run(const in_array& field, const gv::grid<3>& g, const gvcli::branching_key& key, int threads,
                         const in_array& seeds, nb::object progress, const branching_request& req) {
  const bool f32 = field.dtype() == nb::dtype<float>();
  if (!f32 && field.dtype() != nb::dtype<double>()) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  return f32 ? branching_impl<float>(field, g, key, threads, seeds, progress, req)
             : branching_impl<double>(field, g, key, threads, seeds, progress, req);
}

}  // namespace

nb::object branching_voronoi_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                   std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                   std::string metric, std::string backend, int threads, in_array seeds,
                                   nb::object progress, std::optional<cut_handle> cut) {
  const gv::grid<3> g = branching_field_grid(field, spacing, origin, orientation);
  const auto key = branching_key_of(factor, connectivity, reduction, metric, backend, threads);
  branching_request req;
  req.cut = fine_cut(cut, g, key.connectivity);
  return branching_run(field, g, key, threads, seeds, progress, req);
}

nb::object branching_shape_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                 std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                 std::string metric, std::string backend, int threads, in_array seeds,
                                 std::string method, int k, nb::object progress, std::optional<in_array> points,
                                 std::optional<cut_handle> cut) {
  const gv::grid<3> g = branching_field_grid(field, spacing, origin, orientation);
  const auto key = branching_key_of(factor, connectivity, reduction, metric, backend, threads);
  branching_request req;
  req.cut = fine_cut(cut, g, key.connectivity);
  req.shapes = true;
  req.shape.method = gvcli::parse_method(method);
  req.shape.max_nodes_per_voxel = k;
  req.shape.threads = threads > 0 ? unsigned(threads) : 0u;
  if (points) {
    req.at = true;
    req.points = seeds_to_coords<3>(g, *points, false);
  }
  return branching_run(field, g, key, threads, seeds, progress, req);
}

namespace {
/// A NumPy vector of @p n elements of type V, copied.
template <class V>
std::vector<V> vector_of(const in_array& a, std::size_t n, const char* what) {
  if (a.ndim() != 1 || a.shape(0) != n || a.dtype() != nb::dtype<V>())
    throw std::invalid_argument(std::string("geovoronoi: the diagram's ") + what + " array does not fit its grid");
  const V* p = static_cast<const V*>(a.data());
  return std::vector<V>(p, p + n);
}

template <class T>
nb::object branching_update_impl(const in_array& field, const gv::grid<3>& g, const gvcli::branching_key& key,
                                 int threads, const in_array& seeds, const std::optional<gv::cut_set<3>>& before_cut,
                                 const gv::cut_set<3>& all, const in_array& distance, const in_array& label,
                                 const in_array& parent, const in_array& seed_copies) {
  const auto coords = seeds_to_coords<3>(g, seeds, false);
  gv::branching_diagram<T> before;
  const std::size_t copies = distance.ndim() == 1 ? distance.shape(0) : 0;
  before.distance = vector_of<T>(distance, copies, "distance");
  before.label = vector_of<label_t>(label, copies, "label");
  before.parent = vector_of<index_t>(parent, copies, "parent");
  before.seeds = vector_of<index_t>(seed_copies, coords.size(), "seed_copies");
  gv::update_stats st;
  gvcli::branching_solution<T> s;
  {
    nb::gil_scoped_release release;
    thread_count_scope scope(threads);
    const auto t0 = std::chrono::steady_clock::now();
    s = gvcli::update_branching<T>(key, branching_view<T>(field, g), coords, before_cut ? &*before_cut : nullptr, all,
                                   before, st);
    last_core_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  const std::size_t after = std::size_t(s.grid.copies());
  const std::vector<std::size_t> fine_shape{std::size_t(g.extent(2)), std::size_t(g.extent(1)), std::size_t(g.extent(0))};
  nb::dict d;
  d["grid"] = grid_dict(std::move(s.grid), key.connectivity, key.reduction);
  d["distance"] = vector_to_numpy(std::move(s.copies.distance), {after});
  d["label"] = vector_to_numpy(std::move(s.copies.label), {after});
  d["parent"] = vector_to_numpy(std::move(s.copies.parent), {after});
  d["seed_copies"] = vector_to_numpy(std::move(s.copies.seeds), {coords.size()});
  d["fine_distance"] = vector_to_numpy(std::move(s.fine.distance.values()), fine_shape);
  d["fine_label"] = vector_to_numpy(std::move(s.fine.label.values()), fine_shape);
  nb::dict stats;
  stats["changed"] = st.cut_tree_edges;
  stats["invalidated"] = st.invalidated;
  stats["settled"] = st.settled;
  d["stats"] = stats;
  return d;
}
}  // namespace

nb::object branching_update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                  std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                  std::string metric, std::string backend, int threads, in_array seeds,
                                  std::optional<cut_handle> before_cut, cut_handle all, in_array distance,
                                  in_array label, in_array parent, in_array seed_copies) {
  const gv::grid<3> g = branching_field_grid(field, spacing, origin, orientation);
  const auto key = branching_key_of(factor, connectivity, reduction, metric, backend, threads);
  const auto before = fine_cut(before_cut, g, key.connectivity);
  const auto after = fine_cut(all, g, key.connectivity);
  if (!after) throw std::invalid_argument("geovoronoi: update() of a branching diagram needs a cut with edges");
  const bool f32 = field.dtype() == nb::dtype<float>();
  if (!f32 && field.dtype() != nb::dtype<double>()) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  return f32 ? branching_update_impl<float>(field, g, key, threads, seeds, before, *after, distance, label, parent,
                                            seed_copies)
             : branching_update_impl<double>(field, g, key, threads, seeds, before, *after, distance, label, parent,
                                             seed_copies);
}

}  // namespace gvpy

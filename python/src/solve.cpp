// The extension's solves: voronoi(), shape_functions(), update() and update_shape_functions() on the
// front end's typed problems (tools/geovoronoi/typed_problem.hpp), whose instantiations are compiled
// once for the extension and the command-line tool. This file only translates the arguments and
// the results (bindings.hpp) and picks the problem.
//
// Updates always work on the problem *with* cuts (an empty cut table when the diagram has none): a
// problem whose cut table is empty has every edge of the plain problem, so its solution is the plain
// solve's bit for bit. The diagram's update is the library's host algorithm whatever the backend
// (update.hpp); the shape functions' update runs on the chosen backend.

#include "bindings.hpp"

#include <geovoronoi/update.hpp>

namespace gvpy {

namespace {

/// The array-axis shape and the grid of the field of @p a.
template <int Dim>
std::pair<std::vector<std::size_t>, gv::grid<Dim>> field_grid(const problem_args& a) {
  std::vector<std::size_t> shape(a.field.ndim());
  for (std::size_t i = 0; i < shape.size(); ++i) shape[i] = a.field.shape(i);
  const auto g = make_grid<Dim>(shape, a.spacing, a.origin);
  return {std::move(shape), g};
}

/// The field of @p a, viewed in place on grid @p g (its address recorded for the zero-copy test).
template <class T, int Dim>
gv::image_view<const T, Dim> field_view(const problem_args& a, const gv::grid<Dim>& g) {
  const T* field = static_cast<const T*>(a.field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(field);
  return gv::image_view<const T, Dim>(g, field);
}

/// The typed problem of a call on @p field with the cut edges of @p cuts (may be null): the names of
/// @p a turned into the front end's key, on the backend @p named or, when null ("auto"), the one the
/// front end's rule chooses for this problem (shape functions or not, the call's threads).
template <class T, int Dim>
std::unique_ptr<gvcli::typed_problem<T, Dim>> problem_for(const problem_args& a, const gvcli::backend* named,
                                                          gv::image_view<const T, Dim> field,
                                                          const gv::cut_table* cuts, bool shape_functions) {
  const gvcli::metric_id metric = gvcli::parse_metric(a.metric);
  const int connectivity = gvcli::check_connectivity(a.connectivity, Dim);
  const gvcli::backend_id b =
      named ? named->id
            : gvcli::choose_backend<T, Dim>(metric, connectivity, field, a.threads > 0 ? unsigned(a.threads) : 0u,
                                            shape_functions);
  return gvcli::make_typed_problem<T, Dim>({b, metric, connectivity, cuts != nullptr}, field, cuts);
}

/// Records the backend a solve or shape-function call ran on (the test hook of "auto").
void note_backend(gvcli::backend_id b) { last_backend = b == gvcli::backend_id::thrust ? 1 : 0; }

/// Calls f with the cut table of every cut edge of @p all, an empty one when there is none (the table
/// lives for the call).
template <int Dim, class F>
void with_all_cuts(const cut_handle& all, const gv::grid<Dim>& g, int connectivity, F&& f) {
  if (all.s) {
    const gv::cut_table table(cut_of<Dim>(all, g, connectivity));
    f(table);
    return;
  }
  gvcli::with_connectivity<Dim>(gvcli::check_connectivity(connectivity, Dim), [&](auto conn) {
    const gv::cut_set<Dim> none(g, conn);
    const gv::cut_table table(none);
    f(table);
  });
}

// ---- diagrams -------------------------------------------------------------------------------------

template <class T, int Dim>
nb::object voronoi_impl(const problem_args& a, const in_array& seeds, bool world, bool with_parent,
                        nb::object progress, const cut_handle* cut) {
  const auto fg = field_grid<Dim>(a);
  const auto& shape = fg.first;
  const auto& g = fg.second;
  const auto coords = seeds_to_coords<Dim>(g, seeds, world);
  const auto field = field_view<T, Dim>(a, g);
  const gvcli::backend* named = check_threads(a);
  gv::solve_options opt;
  opt.with_parent = with_parent;
  opt.threads = a.threads > 0 ? unsigned(a.threads) : 0u;
  // the solver's progress hook: reports to the callable and polls Ctrl-C (KeyboardInterrupt cancels)
  progress_bridge bridge{progress, 0.0, std::nullopt};
  opt.progress = [&](double f) { return bridge(f); };
  auto* h = new diagram_handle;
  h->metric = a.metric;
  h->connectivity = a.connectivity;
  if (cut) h->cuts = *cut;
  nb::object owner = nb::cast(h, nb::rv_policy::take_ownership);
  try {
    nb::gil_scoped_release release;
    thread_count_scope threads(a.threads);
    const auto t0 = std::chrono::steady_clock::now();
    std::optional<gv::cut_table> table;
    if (cut) table.emplace(cut_of<Dim>(*cut, g, a.connectivity));
    const auto p = problem_for<T, Dim>(a, named, field, table ? &*table : nullptr, false);
    note_backend(p->key().backend);
    h->d = p->voronoi(coords, opt);
    last_core_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const gv::cancelled&) {
    if (bridge.error) throw std::move(*bridge.error);
    throw;
  }
  if (bridge.error) throw std::move(*bridge.error);
  bridge.finish();
  return diagram_arrays(std::get<gv::diagram<T, Dim>>(h->d), shape, owner);
}

// ---- shape functions ------------------------------------------------------------------------------

/// (weights tuple, state): the state is a shape_state_handle when @p keep (Distance Ratio on the whole
/// grid: shape_options::keep_update_state), else None.
template <class T, int Dim>
nb::object shape_impl(const problem_args& a, diagram_handle& h, bool cuts, const std::string& method, int k,
                      std::size_t batch_size, nb::object progress, const std::optional<in_array>& points, bool keep) {
  auto* dp = &checked_diagram<T, Dim>(a, h);
  const auto fg = field_grid<Dim>(a);
  const auto& shape = fg.first;
  const auto& g = fg.second;
  const auto field = field_view<T, Dim>(a, g);
  const gvcli::backend* named = gvcli::parse_backend(a.backend, true);
  progress_bridge bridge{progress, 0.0, std::nullopt};
  gv::shape_options opt = make_shape_options(a, method, k, batch_size, bridge);
  if (keep && (points || opt.method != gv::shape_method::distance_ratio))
    throw std::invalid_argument("geovoronoi: keep_state applies to Distance Ratio on the whole grid only");
  opt.keep_update_state = keep;
  dr_state_ptr<T> kept;
  // Without points: every voxel (shape_functions); with points: only those voxels (shape_functions_at),
  // given as int64 array indices [z, y, x] already bounds-checked by the Python layer.
  std::optional<std::vector<gv::coord<Dim>>> at;
  if (points) at = seeds_to_coords<Dim>(g, *points, false);
  std::vector<label_t> node;
  std::vector<T> weight;
  std::size_t kk = 0, nodes = 0;
  run_released(a, bridge, [&] {
    std::optional<gv::cut_table> table;
    if (cuts) table.emplace(cut_of<Dim>(h.cuts, g, a.connectivity));
    const auto p = problem_for<T, Dim>(a, named, field, table ? &*table : nullptr, true);
    note_backend(p->key().backend);
    auto take = [&](auto&& w) {
      kk = std::size_t(w.k);
      nodes = w.nodes;
      node = std::move(w.node);
      weight = std::move(w.weight);
    };
    if (at) {
      take(p->shape_functions_at(*dp, *at, opt));
    } else {
      auto w = p->shape_functions(*dp, opt);
      kept = std::move(w.update_state);
      take(std::move(w));
    }
  });
  const std::size_t n = at ? at->size() : std::size_t(g.size());
  nb::object state = nb::none();
  if (kept) state = nb::cast(shape_state_handle::of<T>(std::move(kept), std::size_t(g.size())));
  return nb::make_tuple(weights_to_python(std::move(node), std::move(weight), n, kk, nodes,
                                          at ? std::vector<std::size_t>{n} : shape),
                        state);
}

// ---- updates --------------------------------------------------------------------------------------

/// A change as the Python layer sends it; voxel lists are flat C-order indices (the library's linear
/// indices), already bounds-checked.
struct change_args {
  cut_handle cut;  ///< newly cut edges (null: none)
  cut_handle all;  ///< every cut edge of the problem after the change (null: none)
  std::optional<in_array> carved, added, restiffened;
  std::vector<node_edit_args> nodes;
};

std::vector<index_t> flat_list(const std::optional<in_array>& a) {
  std::vector<index_t> out;
  if (!a) return out;
  if (a->dtype() != nb::dtype<std::int64_t>() || a->ndim() != 1)
    throw std::invalid_argument("geovoronoi: voxel lists must be 1D int64 arrays of flat indices");
  const auto* p = static_cast<const std::int64_t*>(a->data());
  out.assign(p, p + a->shape(0));
  return out;
}

template <int Dim>
gv::change<Dim> make_change(const change_args& c) {
  gv::change<Dim> out;
  if (c.cut.s) {
    const auto* cs = std::get_if<gv::cut_set<Dim>>(c.cut.s.get());
    if (!cs) throw std::invalid_argument("geovoronoi: the cut belongs to a grid of another dimension");
    out.cut = *cs;
  }
  out.carved = flat_list(c.carved);
  out.added = flat_list(c.added);
  out.restiffened = flat_list(c.restiffened);
  for (const auto& [kind, pos, voxel] : c.nodes) {
    const std::size_t at = pos < 0 ? gv::node_edit<Dim>::append : std::size_t(pos);
    gv::coord<Dim> v{};
    if (kind != 1) {
      if (voxel.size() != std::size_t(Dim))
        throw std::invalid_argument("geovoronoi: a node edit's voxel must have " + std::to_string(Dim) + " indices");
      for (int ax = 0; ax < Dim; ++ax) v[ax] = index_t(voxel[std::size_t(Dim - 1 - ax)]);
    }
    if (kind == 0) out.nodes.push_back(gv::node_edit<Dim>::add(v, at));
    else if (kind == 1) out.nodes.push_back(gv::node_edit<Dim>::remove(at));
    else out.nodes.push_back(gv::node_edit<Dim>::move(at, v));
  }
  return out;
}

template <class T, int Dim>
nb::object update_impl(const problem_args& a, diagram_handle& before, const change_args& c) {
  auto& db = checked_diagram<T, Dim>(a, before);
  if (db.parent.size() == 0)
    throw std::invalid_argument("geovoronoi: update needs a diagram with parents; compute it with "
                                "voronoi(..., parent=True)");
  const auto fg = field_grid<Dim>(a);
  const auto& shape = fg.first;
  const auto& g = fg.second;
  const auto field = field_view<T, Dim>(a, g);
  const gvcli::backend* seq = gvcli::parse_backend(a.backend);
  auto* h = new diagram_handle;
  h->metric = a.metric;
  h->connectivity = a.connectivity;
  h->cuts = c.all;
  nb::object owner = nb::cast(h, nb::rv_policy::take_ownership);
  gv::update_stats st;
  {
    nb::gil_scoped_release release;
    const auto t0 = std::chrono::steady_clock::now();
    const auto ch = make_change<Dim>(c);
    with_all_cuts<Dim>(c.all, g, a.connectivity, [&](const gv::cut_table& table) {
      const auto p = problem_for<T, Dim>(a, seq, field, &table, false);
      gv::diagram<T, Dim> d = db;
      st = p->update_in_place(d, ch);
      h->d = std::move(d);
    });
    last_core_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  nb::dict stats;
  stats["cut_tree_edges"] = st.cut_tree_edges;
  stats["invalidated"] = st.invalidated;
  stats["boundary"] = st.boundary;
  stats["settled"] = st.settled;
  stats["reparented"] = st.reparented;
  stats["lowered"] = st.lowered;
  stats["sources_added"] = st.sources_added;
  stats["nodes_removed"] = st.nodes_removed;
  stats["repairs"] = st.repairs;
  return nb::make_tuple(diagram_arrays(std::get<gv::diagram<T, Dim>>(h->d), shape, owner), stats);
}

template <class T, int Dim>
nb::object shape_update_impl(const problem_args& a, diagram_handle& before, diagram_handle& after,
                             const change_args& c, const std::string& method, int k, std::size_t batch_size,
                             nb::object progress, const in_array& old_node, const in_array& old_weight,
                             std::size_t old_nodes, const std::optional<in_array>& points,
                             const shape_state_handle* state) {
  auto& db = checked_diagram<T, Dim>(a, before);
  auto& da = checked_diagram<T, Dim>(a, after);
  const auto fg = field_grid<Dim>(a);
  const auto& shape = fg.first;
  const auto& g = fg.second;
  const auto field = field_view<T, Dim>(a, g);
  if (old_node.dtype() != nb::dtype<label_t>() || old_weight.dtype() != nb::dtype<T>())
    throw std::invalid_argument("geovoronoi: the fixed-K weights must be int32 indices and weights of the field's dtype");
  const std::size_t rows = points ? points->shape(0) : std::size_t(g.size());
  if (old_node.size() != rows * std::size_t(k) || old_weight.size() != old_node.size())
    throw std::invalid_argument("geovoronoi: the weights have " + std::to_string(old_node.size()) + " slots, expected " +
                                std::to_string(rows) + " rows x k = " + std::to_string(k));
  const gvcli::backend* named = gvcli::parse_backend(a.backend, true);
  progress_bridge bridge{progress, 0.0, std::nullopt};
  gv::shape_options opt = make_shape_options(a, method, k, batch_size, bridge);
  // a state given: the update repairs its searches, and keeps them again when it recomputes every row
  dr_state_ptr<T> kept;
  if (state) {
    if (points || opt.method != gv::shape_method::distance_ratio)
      throw std::invalid_argument("geovoronoi: a shape-function state applies to Distance Ratio on the whole grid only");
    kept = state->as<T>(std::size_t(g.size()));
    opt.keep_update_state = true;
  }
  const auto* np = static_cast<const label_t*>(old_node.data());
  const auto* wp = static_cast<const T*>(old_weight.data());
  std::vector<label_t> node(np, np + old_node.size());
  std::vector<T> weight(wp, wp + old_weight.size());
  std::vector<index_t> voxel;
  if (points)
    for (const auto& x : seeds_to_coords<Dim>(g, *points, false)) voxel.push_back(g.index(x));
  gv::shape_update_stats st;
  std::size_t nodes = 0;
  run_released(a, bridge, [&] {
    const auto ch = make_change<Dim>(c);
    with_all_cuts<Dim>(c.all, g, a.connectivity, [&](const gv::cut_table& table) {
      const auto p = problem_for<T, Dim>(a, named, field, &table, true);
      note_backend(p->key().backend);
      if (points) {
        gv::point_weights<T> w;
        w.points = rows;
        w.k = k;
        w.nodes = old_nodes;
        w.voxel = std::move(voxel);
        w.node = std::move(node);
        w.weight = std::move(weight);
        st = p->update_shape_functions_at_in_place(db, da, w, ch, opt);
        nodes = w.nodes;
        node = std::move(w.node);
        weight = std::move(w.weight);
      } else {
        gv::shape_weights<T, Dim> w;
        w.geometry = g;
        w.k = k;
        w.nodes = old_nodes;
        w.node = std::move(node);
        w.weight = std::move(weight);
        w.update_state = std::move(kept);
        st = p->update_shape_functions_in_place(db, da, w, ch, opt);
        nodes = w.nodes;
        node = std::move(w.node);
        weight = std::move(w.weight);
        kept = std::move(w.update_state);
      }
    });
  });
  nb::dict stats;
  stats["rows"] = st.rows;
  stats["recomputed"] = st.recomputed;
  stats["changed"] = st.changed;
  stats["changed_voxels"] = st.changed_voxels;
  stats["region_voxels"] = st.region_voxels;
  stats["nodes_affected"] = st.nodes_affected;
  stats["full"] = st.full;
  nb::object new_state = nb::none();
  if (state) {
    if (!kept) throw std::logic_error("geovoronoi: the update returned no Distance Ratio state");
    new_state = nb::cast(shape_state_handle::of<T>(std::move(kept), std::size_t(g.size())));
  }
  return nb::make_tuple(weights_to_python(std::move(node), std::move(weight), rows, std::size_t(k), nodes,
                                          points ? std::vector<std::size_t>{rows} : shape),
                        stats, new_state);
}

bool is_f32(const in_array& field) {
  const bool f32 = field.dtype() == nb::dtype<float>(), f64 = field.dtype() == nb::dtype<double>();
  if (!f32 && !f64) throw nb::type_error("geovoronoi: the field must be float32 or float64");
  return f32;
}

/// Calls f(T{}, std::integral_constant<int, Dim>{}) for the dtype and dimensions of @p field.
template <class F>
nb::object with_field_type(const in_array& field, F&& f) {
  const bool f32 = is_f32(field);
  if (field.ndim() == 2) return f32 ? f(float{}, std::integral_constant<int, 2>{}) : f(double{}, std::integral_constant<int, 2>{});
  if (field.ndim() == 3) return f32 ? f(float{}, std::integral_constant<int, 3>{}) : f(double{}, std::integral_constant<int, 3>{});
  throw std::invalid_argument("geovoronoi: the field must be a 2D or 3D array, got " + std::to_string(field.ndim()) +
                              " dimensions");
}

change_args make_change_args(std::optional<cut_handle> cut, std::optional<cut_handle> all, std::optional<in_array> carved,
                             std::optional<in_array> added, std::optional<in_array> restiffened,
                             std::vector<node_edit_args> nodes) {
  change_args c;
  if (cut) c.cut = *cut;
  if (all) c.all = *all;
  c.carved = std::move(carved);
  c.added = std::move(added);
  c.restiffened = std::move(restiffened);
  c.nodes = std::move(nodes);
  return c;
}

}  // namespace

nb::object voronoi_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                         int connectivity, std::string backend, int threads, in_array seeds, bool world,
                         bool with_parent, nb::object progress, std::optional<cut_handle> cut) {
  const problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, std::move(backend),
                       threads};
  if (cut && cut->s && cut->connectivity != connectivity)
    throw std::invalid_argument("geovoronoi: the cut was made for connectivity " + std::to_string(cut->connectivity) +
                                ", the solve uses " + std::to_string(connectivity));
  const cut_handle* c = cut && cut->s ? &*cut : nullptr;
  return with_field_type(field, [&](auto t, auto dim) {
    return voronoi_impl<decltype(t), decltype(dim)::value>(a, seeds, world, with_parent, progress, c);
  });
}

nb::object shape_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                       int connectivity, std::string backend, int threads, diagram_handle& h, std::string method, int k,
                       std::size_t batch_size, nb::object progress, std::optional<in_array> points, bool keep) {
  const problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, std::move(backend),
                       threads};
  return with_field_type(field, [&](auto t, auto dim) {
    return shape_impl<decltype(t), decltype(dim)::value>(a, h, !h.cuts.empty(), method, k, batch_size, progress,
                                                         points, keep);
  });
}

nb::object update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                        int connectivity, diagram_handle& before, std::optional<cut_handle> cut,
                        std::optional<cut_handle> all, std::optional<in_array> carved, std::optional<in_array> added,
                        std::optional<in_array> restiffened, std::vector<node_edit_args> nodes) {
  const problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, "seq", 0};
  const change_args c = make_change_args(std::move(cut), std::move(all), std::move(carved), std::move(added),
                                         std::move(restiffened), std::move(nodes));
  return with_field_type(field, [&](auto t, auto dim) {
    return update_impl<decltype(t), decltype(dim)::value>(a, before, c);
  });
}

nb::object shape_update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                              std::string metric, int connectivity, std::string backend, int threads,
                              diagram_handle& before, diagram_handle& after, std::optional<cut_handle> cut,
                              std::optional<cut_handle> all, std::optional<in_array> carved,
                              std::optional<in_array> added, std::optional<in_array> restiffened,
                              std::vector<node_edit_args> nodes, std::string method, int k, std::size_t batch_size,
                              nb::object progress, in_array old_node, in_array old_weight, std::size_t old_nodes,
                              std::optional<in_array> points, const shape_state_handle* state) {
  const problem_args a{field, std::move(spacing), std::move(origin), std::move(metric), connectivity, std::move(backend),
                       threads};
  const change_args c = make_change_args(std::move(cut), std::move(all), std::move(carved), std::move(added),
                                         std::move(restiffened), std::move(nodes));
  return with_field_type(field, [&](auto t, auto dim) {
    return shape_update_impl<decltype(t), decltype(dim)::value>(a, before, after, c, method, k, batch_size, progress,
                                                                old_node, old_weight, old_nodes, points, state);
  });
}

}  // namespace gvpy

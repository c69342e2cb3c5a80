// The extension's wrappers for problems with cut edges and for incremental updates: voronoi() and
// shape_functions() with cuts, update() and update_shape_functions(). Instantiated per dtype in
// cuts_float.cpp and cuts_double.cpp, apart from the plain solves (solve_<T>.cpp), so that a call
// without cuts never needs them and the four heavy translation units compile in parallel.
//
// Updates always work on the problem *with* cuts (an empty cut table when the diagram has none): a
// problem whose cut table is empty has every edge of the plain problem, so its solution is the plain
// solve's bit for bit, and one problem type per metric and connectivity is enough. The update itself
// is the library's single-threaded host algorithm whatever the backend (update.hpp); the shape
// functions' update runs on the chosen backend.

#pragma once

#include "bindings.hpp"

#include <nanobind/stl/tuple.h>

#include <geovoronoi/shape_update.hpp>
#include <geovoronoi/update.hpp>

#include <tuple>

namespace gvpy {

/// One node edit as the Python layer sends it: (kind 0 add / 1 remove / 2 move, position or -1 for
/// "append", voxel in array-axis order (empty for remove)).
using node_edit_args = std::tuple<int, std::int64_t, std::vector<std::int64_t>>;

/// A change as the Python layer sends it; voxel lists are flat C-order indices (the library's linear
/// indices), already bounds-checked.
struct change_args {
  cut_handle cut;  ///< newly cut edges (null: none)
  cut_handle all;  ///< every cut edge of the problem after the change (null: none)
  std::optional<in_array> carved, added, restiffened;
  std::vector<node_edit_args> nodes;
};

inline std::vector<index_t> flat_list(const std::optional<in_array>& a) {
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

/// Calls f with problem @p p carrying the cut edges of @p all (an empty table when there are none).
template <class P, class F>
void with_all_cuts(const P& p, const cut_handle& all, F&& f) {
  constexpr int Dim = P::dim;
  if (all.s) {
    with_problem<true>(p, &all, f);
    return;
  }
  const gv::cut_set<Dim> none(p.geometry, gv::connectivity<P::neighbours>{});
  const gv::cut_table table(none);
  f(gv::with_cuts(p, table));
}

template <class T, int Dim>
nb::object update_impl(const problem_args& a, diagram_handle& before, const change_args& c) {
  auto& db = checked_diagram<T, Dim>(a, before);
  if (db.parent.size() == 0)
    throw std::invalid_argument("geovoronoi: update needs a diagram with parents; compute it with "
                                "voronoi(..., parent=True)");
  std::vector<std::size_t> shape(a.field.ndim());
  for (std::size_t i = 0; i < shape.size(); ++i) shape[i] = a.field.shape(i);
  const auto g = make_grid<Dim>(shape, a.spacing, a.origin);
  const T* field = static_cast<const T*>(a.field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(field);
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
    with_metric(a.metric, [&](auto metric) {
      with_connectivity<Dim>(a.connectivity, [&](auto conn) {
        const auto p0 = gv::make_problem(g, gv::image_view<const T, Dim>(g, field), metric, conn);
        with_all_cuts(p0, c.all, [&](const auto& p) { h->d = gv::update(gv::seq, p, db, ch, &st); });
      });
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
  std::vector<std::size_t> shape(a.field.ndim());
  for (std::size_t i = 0; i < shape.size(); ++i) shape[i] = a.field.shape(i);
  const auto g = make_grid<Dim>(shape, a.spacing, a.origin);
  const T* field = static_cast<const T*>(a.field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(field);
  if (old_node.dtype() != nb::dtype<label_t>() || old_weight.dtype() != nb::dtype<T>())
    throw std::invalid_argument("geovoronoi: the fixed-K weights must be int32 indices and weights of the field's dtype");
  const std::size_t rows = points ? points->shape(0) : std::size_t(g.size());
  if (old_node.size() != rows * std::size_t(k) || old_weight.size() != old_node.size())
    throw std::invalid_argument("geovoronoi: the weights have " + std::to_string(old_node.size()) + " slots, expected " +
                                std::to_string(rows) + " rows x k = " + std::to_string(k));
  progress_bridge bridge{progress, 0.0, std::nullopt};
  gv::shape_options opt = make_shape_options(a, method, k, batch_size, bridge);
  // a state given: the update repairs its searches, and keeps them again when it recomputes every row
  std::shared_ptr<const gv::detail::shape::distance_ratio_state<T>> kept;
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
    with_metric(a.metric, [&](auto metric) {
      with_connectivity<Dim>(a.connectivity, [&](auto conn) {
        const auto p0 = gv::make_problem(g, gv::image_view<const T, Dim>(g, field), metric, conn);
        with_all_cuts(p0, c.all, [&](const auto& p) {
          with_backend(resolve_backend_for(a.backend, p, a.threads, true), [&](const auto& policy) {
            if (points) {
              gv::point_weights<T> w;
              w.points = rows;
              w.k = k;
              w.nodes = old_nodes;
              w.voxel = std::move(voxel);
              w.node = std::move(node);
              w.weight = std::move(weight);
              st = gv::update_shape_functions_at_in_place(policy, p, db, da, w, ch, opt);
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
              st = gv::update_shape_functions_in_place(policy, p, db, da, w, ch, opt);
              nodes = w.nodes;
              node = std::move(w.node);
              weight = std::move(w.weight);
              kept = std::move(w.update_state);
            }
          });
        });
      });
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

template <class T>
nb::object update_typed(const problem_args& a, diagram_handle& before, const change_args& c) {
  if (a.field.ndim() == 2) return update_impl<T, 2>(a, before, c);
  if (a.field.ndim() == 3) return update_impl<T, 3>(a, before, c);
  throw std::invalid_argument("geovoronoi: the field must be a 2D or 3D array");
}

template <class T>
nb::object shape_update_typed(const problem_args& a, diagram_handle& before, diagram_handle& after,
                              const change_args& c, const std::string& method, int k, std::size_t batch_size,
                              nb::object progress, const in_array& old_node, const in_array& old_weight,
                              std::size_t old_nodes, const std::optional<in_array>& points,
                              const shape_state_handle* state) {
  if (a.field.ndim() == 2)
    return shape_update_impl<T, 2>(a, before, after, c, method, k, batch_size, progress, old_node, old_weight,
                                   old_nodes, points, state);
  if (a.field.ndim() == 3)
    return shape_update_impl<T, 3>(a, before, after, c, method, k, batch_size, progress, old_node, old_weight,
                                   old_nodes, points, state);
  throw std::invalid_argument("geovoronoi: the field must be a 2D or 3D array");
}

#define GEOVORONOI_PY_DECLARE_UPDATE(T, EXTERN)                                                               \
  EXTERN template nb::object update_typed<T>(const problem_args&, diagram_handle&, const change_args&);      \
  EXTERN template nb::object shape_update_typed<T>(const problem_args&, diagram_handle&, diagram_handle&,    \
                                                   const change_args&, const std::string&, int, std::size_t, \
                                                   nb::object, const in_array&, const in_array&, std::size_t, \
                                                   const std::optional<in_array>&, const shape_state_handle*);
GEOVORONOI_PY_DECLARE_UPDATE(float, extern)
GEOVORONOI_PY_DECLARE_UPDATE(double, extern)

}  // namespace gvpy

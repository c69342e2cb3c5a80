// Shared part of the extension geovoronoi._geovoronoi (python/src): the translation between NumPy
// buffers and the library's types, the handles that own results, the progress bridge. Every name ->
// type decision and every solve goes through the front-end layer that the command-line tool uses
// (tools/geovoronoi: kinds.hpp, backends.hpp, typed_problem.hpp); solve.cpp holds the calls.
//
// The Python layer (python/geovoronoi/__init__.py) normalises every argument (dtypes, axis order,
// defaults) and calls the private functions of the extension, which only translate:
//   * array axes are [z, y, x] / [y, x]; the library's grid has x fastest, so a C-contiguous array
//     is the library's memory layout as is: the field is viewed in place (image_view), never copied;
//   * seeds, spacing and origin arrive in array-axis order and are reversed into (x, y, z) here;
//   * results are handed to NumPy without a copy: the arrays point into the library's own vectors,
//     kept alive by the Python object that owns them (a diagram handle or a capsule).
// The GIL is released while the library works. Progress callbacks re-acquire it briefly, forward to
// the Python callable and check for signals (Ctrl-C), cancelling the computation through the
// library's progress hook when a Python exception is pending.

#pragma once

#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "backends.hpp"
#include "kinds.hpp"
#include "typed_problem.hpp"

#include <geovoronoi.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/vti.hpp>
#include <geovoronoi/shape_functions.hpp>

#if defined(_OPENMP)
#include <omp.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <thread>
#include <tuple>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace nb = nanobind;
namespace gv = geovoronoi;
namespace gio = geovoronoi::io;
using gv::index_t;
using gv::label_t;

namespace gvpy {

// ---- plumbing -------------------------------------------------------------------------------------

using in_array = nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu>;

/// Address of the field buffer the last solve viewed (a test hook for the zero-copy promise).
inline std::atomic<std::uintptr_t> last_field_address{0};
/// Wall time of the last library call alone, without the binding's work (for the overhead benchmark).
inline std::atomic<double> last_core_seconds{0.0};
/// The backend the last solve or shape-function call ran on: 0 seq, 1 thrust (a test hook for "auto").
inline std::atomic<int> last_backend{-1};

/// NumPy array over the vector `v`, moved into a capsule that frees it with the array.
template <class T>
nb::object vector_to_numpy(std::vector<T>&& v, const std::vector<std::size_t>& shape) {
  auto* heap = new std::vector<T>(std::move(v));
  nb::capsule owner(heap, [](void* p) noexcept { delete static_cast<std::vector<T>*>(p); });
  return nb::cast(nb::ndarray<nb::numpy, T>(heap->data(), shape.size(), shape.data(), owner));
}

/// NumPy array over memory owned by the Python object `owner`.
template <class T>
nb::object view_to_numpy(T* data, const std::vector<std::size_t>& shape, nb::handle owner) {
  return nb::cast(nb::ndarray<nb::numpy, T>(data, shape.size(), shape.data(), owner));
}

/// Array-axis shape ([z, y, x]) of a grid.
template <int Dim>
std::vector<std::size_t> array_shape(const gv::grid<Dim>& g) {
  std::vector<std::size_t> s(Dim);
  for (int a = 0; a < Dim; ++a) s[std::size_t(Dim - 1 - a)] = std::size_t(g.extent(a));
  return s;
}

/// A grid from an array shape and spacing/origin in array-axis order.
template <int Dim>
gv::grid<Dim> make_grid(const std::vector<std::size_t>& shape, const std::vector<double>& spacing,
                        const std::vector<double>& origin, const std::vector<double>& orientation = {}) {
  if (shape.size() != std::size_t(Dim) || spacing.size() != std::size_t(Dim) || origin.size() != std::size_t(Dim))
    throw std::invalid_argument("geovoronoi: shape, spacing and origin must all have " + std::to_string(Dim) + " entries");
  gv::coord<Dim> e{};
  gv::point<Dim> s{}, o{};
  for (int a = 0; a < Dim; ++a) {
    const std::size_t r = std::size_t(Dim - 1 - a);
    e[a] = index_t(shape[r]);
    s[a] = spacing[r];
    o[a] = origin[r];
  }
  if (orientation.empty()) return gv::grid<Dim>(e, s, o);
  // the direction matrix in array-axis order (Python's) -> index-axis order (the library's)
  if (orientation.size() != std::size_t(Dim * Dim))
    throw std::invalid_argument("geovoronoi: the orientation must have " + std::to_string(Dim * Dim) + " entries");
  gv::direction_matrix<Dim> d{};
  for (int r = 0; r < Dim; ++r)
    for (int c = 0; c < Dim; ++c) d[std::size_t(r * Dim + c)] = orientation[std::size_t((Dim - 1 - r) * Dim + (Dim - 1 - c))];
  return gv::grid<Dim>(e, s, o, d);
}

/// Sets the OpenMP thread count of the calling thread's parallel regions for its lifetime.
struct thread_count_scope {
  int old = 0;
  bool set = false;
  explicit thread_count_scope(int n) {
#if defined(_OPENMP)
    if (n > 0) {
      old = omp_get_max_threads();
      omp_set_num_threads(n);
      set = true;
    }
#else
    (void)n;
#endif
  }
  ~thread_count_scope() {
#if defined(_OPENMP)
    if (set) omp_set_num_threads(old);
#endif
  }
  thread_count_scope(const thread_count_scope&) = delete;
  thread_count_scope& operator=(const thread_count_scope&) = delete;
};

/// Forwards the library's progress reports (fraction done) to a Python callable as increments of
/// the percentage done, and turns a pending Python exception (Ctrl-C, or one the callable raised)
/// into a cancellation. Called with the GIL released; takes it briefly.
struct progress_bridge {
  nb::object callback;  // None or a callable
  double reported = 0.0;
  std::optional<nb::python_error> error;

  bool operator()(double fraction) {
    nb::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) {
      error.emplace();  // fetches the pending exception (KeyboardInterrupt)
      return false;
    }
    if (!callback.is_none()) {
      const double pct = std::clamp(fraction, 0.0, 1.0) * 100.0;
      if (pct > reported) {
        try {
          callback(pct - reported);
        } catch (nb::python_error& e) {
          error.emplace(std::move(e));
          return false;
        }
        reported = pct;
      }
    }
    return true;
  }
  /// Reports completion (outside the library, GIL held).
  void finish() {
    if (!callback.is_none() && reported < 100.0) callback(100.0 - reported);
    reported = 100.0;
  }
};

// ---- diagrams -------------------------------------------------------------------------------------

/// A set of cut edges (the library's cut_set) shared by the Python objects that hold it: a Cut and
/// every diagram solved with it. Immutable once built (a merge makes a new one). The cut_set's grid
/// is the solve's grid (extents, spacing, origin, no orientation), so that the library's grid checks
/// compare it with the problem's; the Python layer checks the orientation.
struct cut_handle {
  std::shared_ptr<const std::variant<gv::cut_set<2>, gv::cut_set<3>>> s;  // null: no cut
  int connectivity = 0;
  bool empty() const { return !s || std::visit([](const auto& c) { return c.empty(); }, *s); }
};

/// A diagram computed by the library, owned by a Python object; NumPy arrays view into it.
struct diagram_handle {
  std::variant<gv::diagram<float, 2>, gv::diagram<float, 3>, gv::diagram<double, 2>, gv::diagram<double, 3>> d;
  std::string metric;
  int connectivity = 0;
  cut_handle cuts;  ///< every cut edge the diagram was solved with (none: no cut)
};

/// The cut set @p s moved onto grid @p g (same extents: the solve's grid, without orientation, or a
/// branching grid's fine grid, with it).
template <int Dim, int N>
gv::cut_set<Dim> rehome(const gv::cut_set<Dim>& s, const gv::grid<Dim>& g, gv::connectivity<N> conn) {
  gv::cut_builder<Dim> b(g, conn);
  for (const auto& e : s) b.insert_unchecked(e.voxel, e.forward);
  return b.build();
}

/// The cut set of @p h, which must belong to the grid @p g and the connectivity @p connectivity.
template <int Dim>
const gv::cut_set<Dim>& cut_of(const cut_handle& h, const gv::grid<Dim>& g, int connectivity) {
  const auto* cs = h.s ? std::get_if<gv::cut_set<Dim>>(h.s.get()) : nullptr;
  if (!cs || cs->directions() != connectivity || !(cs->geometry() == g))
    throw std::invalid_argument("geovoronoi: the cut belongs to another grid or connectivity than the field");
  return *cs;
}

/// The library's Distance Ratio state (shape_options::keep_update_state): the type of
/// shape_weights::update_state, the same for every dimension.
template <class T>
using dr_state_ptr = decltype(gv::shape_weights<T, 3>::update_state);

/// Distance Ratio's kept searches for the Python layer's ShapeState: the library's immutable, shared
/// state, its weight type and the grid it belongs to.
struct shape_state_handle {
  std::shared_ptr<const void> state;  ///< the element of a dr_state_ptr<T>
  bool f32 = true;                    ///< T is float (else double)
  std::size_t voxels = 0;             ///< voxels of the grid it was computed on
  std::size_t nbytes = 0;             ///< bytes its lists hold

  template <class T>
  static shape_state_handle of(dr_state_ptr<T> s, std::size_t voxels) {
    shape_state_handle h;
    h.f32 = std::is_same_v<T, float>;
    h.voxels = voxels;
    // the state's lists: every node's support and frontier (voxel, value) pairs (the library has no
    // accessor for their size; this reads its layout)
    for (const auto& nd : s->nodes)
      h.nbytes += (nd.support->size() + nd.frontier->size()) * (sizeof(index_t) + sizeof(T));
    h.state = std::move(s);
    return h;
  }
  /// The state as the library's type, after checking that it is one of T on a grid of @p voxels voxels.
  template <class T>
  dr_state_ptr<T> as(std::size_t n) const {
    if (f32 != std::is_same_v<T, float> || voxels != n || !state)
      throw std::invalid_argument("geovoronoi: the shape-function state belongs to another grid or dtype");
    return std::static_pointer_cast<typename dr_state_ptr<T>::element_type>(state);
  }
};

struct problem_args {
  in_array field;
  std::vector<double> spacing, origin;
  std::string metric;
  int connectivity = 0;
  std::string backend;
  int threads = 0;
};

/// The backend @p a names (checked by the front end: unknown, not built), null for "auto". An explicit
/// "seq", or "auto" where thrust is not built, with threads > 1 is a contradiction (auto may pick seq
/// for a small problem: the thread count is then a limit it did not need).
inline const gvcli::backend* check_threads(const problem_args& a) {
  const gvcli::backend* b = gvcli::parse_backend(a.backend, true);
  const bool seq_only = b ? b->id == gvcli::backend_id::seq : !gvcli::find_backend(gvcli::backend_id::thrust).built();
  if (seq_only && a.threads > 1)
    throw std::invalid_argument("geovoronoi: backend 'seq' runs on one thread; threads=" + std::to_string(a.threads) +
                                " needs backend 'thrust'");
  return b;
}

template <int Dim>
std::vector<gv::coord<Dim>> seeds_to_coords(const gv::grid<Dim>& g, const in_array& seeds, bool world) {
  if (seeds.ndim() != 2 || seeds.shape(1) != std::size_t(Dim))
    throw std::invalid_argument("geovoronoi: seeds must be an (n, " + std::to_string(Dim) + ") array");
  const std::size_t n = seeds.shape(0);
  std::vector<gv::coord<Dim>> out(n);
  if (world) {
    if (seeds.dtype() != nb::dtype<double>()) throw std::invalid_argument("geovoronoi: world seeds must be float64");
    const double* p = static_cast<const double*>(seeds.data());
    for (std::size_t i = 0; i < n; ++i) {
      gv::point<Dim> x{};
      for (int a = 0; a < Dim; ++a) x[a] = p[i * Dim + std::size_t(Dim - 1 - a)];
      out[i] = g.nearest_voxel(x);
    }
  } else {
    if (seeds.dtype() != nb::dtype<std::int64_t>()) throw std::invalid_argument("geovoronoi: seeds must be int64");
    const std::int64_t* p = static_cast<const std::int64_t*>(seeds.data());
    for (std::size_t i = 0; i < n; ++i)
      for (int a = 0; a < Dim; ++a) out[i][a] = index_t(p[i * Dim + std::size_t(Dim - 1 - a)]);
  }
  return out;
}

/// (distance, label, parent or None, seeds) of diagram @p d as NumPy views owned by @p owner.
template <class T, int Dim>
nb::object diagram_arrays(gv::diagram<T, Dim>& d, const std::vector<std::size_t>& shape, nb::handle owner) {
  nb::object distance = view_to_numpy<T>(d.distance.data(), shape, owner);
  nb::object label = view_to_numpy<label_t>(d.label.data(), shape, owner);
  nb::object parent = nb::none();
  if (d.parent.size() != 0) parent = view_to_numpy<index_t>(d.parent.data(), shape, owner);
  std::vector<std::int64_t> sv(d.seeds.size() * Dim);
  for (std::size_t i = 0; i < d.seeds.size(); ++i) {
    const auto c = d.geometry().coords(d.seeds[i]);
    for (int ax = 0; ax < Dim; ++ax) sv[i * Dim + std::size_t(Dim - 1 - ax)] = c[ax];
  }
  nb::object seed_array = vector_to_numpy(std::move(sv), {d.seeds.size(), std::size_t(Dim)});
  return nb::make_tuple(owner, distance, label, parent, seed_array);
}

// ---- shape functions ------------------------------------------------------------------------------

/// The checks and options every shape-function call shares.
template <class T, int Dim>
gv::diagram<T, Dim>& checked_diagram(const problem_args& a, diagram_handle& h) {
  auto* dp = std::get_if<gv::diagram<T, Dim>>(&h.d);
  if (!dp) throw std::invalid_argument("geovoronoi: the diagram was computed on a field of another dtype or dimension");
  if (h.metric != a.metric || h.connectivity != a.connectivity)
    throw std::invalid_argument("geovoronoi: the diagram was computed with another metric or connectivity");
  return *dp;
}

inline gv::shape_options make_shape_options(const problem_args& a, const std::string& method, int k,
                                            std::size_t batch_size, progress_bridge& bridge) {
  check_threads(a);
  gv::shape_options opt;
  opt.method = gvcli::parse_method(method);
  opt.max_nodes_per_voxel = k;
  opt.batch_size = batch_size;
  opt.threads = a.threads > 0 ? unsigned(a.threads) : 0u;
  opt.progress = [&bridge](double f) { return bridge(f); };
  return opt;
}

/// Runs f() with the GIL released and the thread count set, turning a cancellation caused by the
/// bridge back into its Python exception.
template <class F>
void run_released(const problem_args& a, progress_bridge& bridge, F&& f) {
  try {
    nb::gil_scoped_release release;
    thread_count_scope threads(a.threads);
    const auto t0 = std::chrono::steady_clock::now();
    f();
    last_core_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const gv::cancelled&) {
    if (bridge.error) throw std::move(*bridge.error);
    throw;
  }
  // defensive: a Python exception caught by the bridge is never dropped, even if the library had
  // finished when it asked to stop
  if (bridge.error) throw std::move(*bridge.error);
  bridge.finish();
}

/// (data, indices, indptr, nodes, fixed-K indices, fixed-K weights) of n rows of kk slots: the CSR
/// (rows x nodes, column indices sorted within each row) and the library's fixed-K layout with the
/// array shape @p kshape (rows' shape + (kk,)).
template <class T>
nb::object weights_to_python(std::vector<label_t>&& node, std::vector<T>&& weight, std::size_t n, std::size_t kk,
                             std::size_t nodes, std::vector<std::size_t> kshape) {
  std::vector<std::int64_t> indptr(n + 1, 0);
  std::vector<std::int32_t> indices;
  std::vector<T> data;
  std::size_t nnz = 0;
  for (std::size_t v = 0; v < n; ++v)
    for (std::size_t s = 0; s < kk; ++s) nnz += node[v * kk + s] >= 0;
  indices.reserve(nnz);
  data.reserve(nnz);
  std::vector<std::pair<label_t, T>> row;
  for (std::size_t v = 0; v < n; ++v) {
    row.clear();
    for (std::size_t s = 0; s < kk; ++s)
      if (node[v * kk + s] >= 0) row.emplace_back(node[v * kk + s], weight[v * kk + s]);
    std::sort(row.begin(), row.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [nd, w] : row) {
      indices.push_back(nd);
      data.push_back(w);
    }
    indptr[v + 1] = std::int64_t(indices.size());
  }
  kshape.push_back(kk);
  nb::object fixed_idx = vector_to_numpy(std::move(node), kshape);
  nb::object fixed_w = vector_to_numpy(std::move(weight), kshape);
  return nb::make_tuple(vector_to_numpy(std::move(data), {nnz}), vector_to_numpy(std::move(indices), {nnz}),
                        vector_to_numpy(std::move(indptr), {n + 1}), nodes, fixed_idx, fixed_w);
}

// ---- the entries (solve.cpp) ---------------------------------------------------------------------

/// voronoi() on a float32 or float64 field of 2 or 3 dimensions, with the edges of @p cut removed when
/// it is given.
nb::object voronoi_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                         int connectivity, std::string backend, int threads, in_array seeds, bool world,
                         bool with_parent, nb::object progress, std::optional<cut_handle> cut);
/// branching_grid() (branching.cpp): the arrays of the branching grid of a 3D float32 or float64 field,
/// as a dict of gv.BranchingGrid's fields.
nb::object branching_grid_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                std::vector<double> orientation, int factor, int connectivity, std::string reduction);
/// voronoi(..., coarsen=N) (branching.cpp): a dict of the grid's arrays ("grid"), the diagram per copy
/// and painted on the fine grid; with @p cut (edges of the fine grid) the grid is built with the cut.
nb::object branching_voronoi_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                   std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                   std::string metric, std::string backend, int threads, in_array seeds,
                                   nb::object progress, std::optional<cut_handle> cut);
/// shape_functions(..., coarsen=N) (branching.cpp): the dict of branching_voronoi_entry() and the
/// weights: "copy_weights" and "fine_weights" (weights_to_python() tuples of the rows per copy and
/// painted on the fine grid), or "at" (the rows at @p points, fine voxels in array-axis order).
nb::object branching_shape_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                 std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                 std::string metric, std::string backend, int threads, in_array seeds,
                                 std::string method, int k, nb::object progress, std::optional<in_array> points,
                                 std::optional<cut_handle> cut);
/// update(branching_diagram, field, cut=) (branching.cpp): the library's update() of the diagram per
/// copy (@p distance, @p label, @p parent, @p seed_copies) of @p seeds on the grid cut by @p before_cut
/// onto the grid cut by @p all (the cuts before and the new one): the dict of branching_voronoi_entry()
/// and "stats".
nb::object branching_update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                                  std::vector<double> orientation, int factor, int connectivity, std::string reduction,
                                  std::string metric, std::string backend, int threads, in_array seeds,
                                  std::optional<cut_handle> before_cut, cut_handle all, in_array distance,
                                  in_array label, in_array parent, in_array seed_copies);
/// shape_functions() (or shape_functions_at() with points) on diagram @p h (with its cut edges).
nb::object shape_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                       int connectivity, std::string backend, int threads, diagram_handle& h, std::string method, int k,
                       std::size_t batch_size, nb::object progress, std::optional<in_array> points, bool keep);

/// One node edit as the Python layer sends it: (kind 0 add / 1 remove / 2 move, position or -1 for
/// "append", voxel in array-axis order (empty for remove)).
using node_edit_args = std::tuple<int, std::int64_t, std::vector<std::int64_t>>;

/// update() of diagram @p before after a change (on the host, seq).
nb::object update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin, std::string metric,
                        int connectivity, diagram_handle& before, std::optional<cut_handle> cut,
                        std::optional<cut_handle> all, std::optional<in_array> carved, std::optional<in_array> added,
                        std::optional<in_array> restiffened, std::vector<node_edit_args> nodes);
/// update_shape_functions() from @p before to @p after.
nb::object shape_update_entry(in_array field, std::vector<double> spacing, std::vector<double> origin,
                              std::string metric, int connectivity, std::string backend, int threads,
                              diagram_handle& before, diagram_handle& after, std::optional<cut_handle> cut,
                              std::optional<cut_handle> all, std::optional<in_array> carved,
                              std::optional<in_array> added, std::optional<in_array> restiffened,
                              std::vector<node_edit_args> nodes, std::string method, int k, std::size_t batch_size,
                              nb::object progress, in_array old_node, in_array old_weight, std::size_t old_nodes,
                              std::optional<in_array> points, const shape_state_handle* state);

}  // namespace gvpy

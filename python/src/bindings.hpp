// Shared part of the extension geovoronoi._geovoronoi (python/src): argument translation and the
// templated solve wrappers, instantiated per dtype in solve_float.cpp and solve_double.cpp so that
// the two heavy translation units compile in parallel. The same wrappers on problems with cut edges,
// and the incremental updates, are instantiated apart (cuts.hpp, cuts_float.cpp, cuts_double.cpp):
// only the calls that involve cuts pay for those instantiations.
//
// geovoronoi._geovoronoi: the nanobind extension behind the Python package.
//
// The Python layer (python/geovoronoi/__init__.py) normalises every argument (dtypes, axis order,
// defaults) and calls the private functions defined here, which only translate between NumPy
// buffers and the library's types:
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
#include <nanobind/stl/vector.h>

#include <geovoronoi.hpp>
#include <geovoronoi/backend/choose.hpp>
#include <geovoronoi/io/metaimage.hpp>
#include <geovoronoi/io/vti.hpp>
#include <geovoronoi/shape_functions.hpp>

#if defined(GEOVORONOI_PY_THRUST)
#include <geovoronoi/backend/thrust.hpp>
#endif
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

/// Calls f with the metric object named `name`.
template <class F>
decltype(auto) with_metric(const std::string& name, F&& f) {
  if (name == "min_stiffness") return f(gv::min_stiffness{});
  if (name == "mean_stiffness") return f(gv::mean_stiffness{});
  if (name == "mean_cost") return f(gv::mean_cost{});
  if (name == "uniform") return f(gv::uniform{});
  throw std::invalid_argument("geovoronoi: unknown metric '" + name +
                              "' (uniform, min_stiffness, mean_stiffness or mean_cost)");
}

/// Calls f with the connectivity<n> of dimension Dim.
template <int Dim, class F>
decltype(auto) with_connectivity(int n, F&& f) {
  if constexpr (Dim == 2) {
    if (n == 4) return f(gv::connectivity<4>{});
    if (n == 8) return f(gv::connectivity<8>{});
    throw std::invalid_argument("geovoronoi: 2D connectivity must be 4 or 8, got " + std::to_string(n));
  } else {
    if (n == 6) return f(gv::connectivity<6>{});
    if (n == 18) return f(gv::connectivity<18>{});
    if (n == 26) return f(gv::connectivity<26>{});
    throw std::invalid_argument("geovoronoi: 3D connectivity must be 6, 18 or 26, got " + std::to_string(n));
  }
}

inline bool thrust_built() {
#if defined(GEOVORONOI_PY_THRUST)
  return true;
#else
  return false;
#endif
}

/// The backend a name stands for before the problem is known (names checked): "auto" is thrust
/// (OpenMP) when built and more than one hardware thread is there, else seq (default_backend()).
inline std::string resolve_backend(const std::string& b) {
  if (b == "auto") return thrust_built() && std::thread::hardware_concurrency() > 1 ? "thrust" : "seq";
  if (b == "seq") return b;
  if (b == "thrust") {
    if (!thrust_built()) throw std::invalid_argument("geovoronoi: backend 'thrust' is not built into this package");
    return b;
  }
  if (b == "cuda")
    throw std::invalid_argument("geovoronoi: backend 'cuda' is not built into this package (CPU backends only: seq, thrust)");
  throw std::invalid_argument("geovoronoi: unknown backend '" + b + "' (auto, seq or thrust)");
}

/// The backend @p b names for problem @p p. "auto" follows the library's per-problem rule, as the
/// command-line tool's default does (backend/choose.hpp, docs/backends.md): thrust when it is built,
/// the call may use more than one thread (threads=, else OpenMP's limit) and, for a Voronoi solve,
/// the domain is large enough to share (shape functions share their searches at any size); else seq.
template <class P>
std::string resolve_backend_for(const std::string& b, const P& p, int threads, bool shape_functions) {
  if (b != "auto" || !thrust_built()) return resolve_backend(b);
  unsigned t = threads > 0 ? unsigned(threads) : std::thread::hardware_concurrency();
#if defined(_OPENMP)
  if (threads <= 0) t = unsigned(omp_get_max_threads());
#endif
  const auto k = shape_functions ? gv::recommended_shape_backend(p, t) : gv::recommended_backend(p, t);
  return k == gv::backend_kind::thrust ? "thrust" : "seq";
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

/// Calls f with the backend policy named `backend` ("seq" or "thrust", already resolved).
template <class F>
decltype(auto) with_backend(const std::string& backend, F&& f) {
#if defined(GEOVORONOI_PY_THRUST)
  if (backend == "thrust") {
    last_backend = 1;
    return f(gv::thrust::par);
  }
#endif
  (void)backend;
  last_backend = 0;
  return f(gv::seq);
}

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

/// Calls f with problem @p p, or with p and the cut edges of @p cut when Cuts is true (the table
/// lives for the call). The cut set must be of p's grid and connectivity.
template <bool Cuts, class P, class F>
void with_problem(const P& p, const cut_handle* cut, F&& f) {
  if constexpr (Cuts) {
    const auto* cs = std::get_if<gv::cut_set<P::dim>>(cut->s.get());
    if (!cs || cs->directions() != P::neighbours || !(cs->geometry() == p.geometry))
      throw std::invalid_argument("geovoronoi: the cut belongs to another grid or connectivity than the field");
    const gv::cut_table table(*cs);
    f(gv::with_cuts(p, table));
  } else {
    (void)cut;
    f(p);
  }
}

/// Distance Ratio's kept searches (shape_options::keep_update_state) for the Python layer's ShapeState:
/// the library's immutable, shared distance_ratio_state<T>, its weight type and the grid it belongs to.
struct shape_state_handle {
  std::shared_ptr<const void> state;  ///< a const detail::shape::distance_ratio_state<T>
  bool f32 = true;                    ///< T is float (else double)
  std::size_t voxels = 0;             ///< voxels of the grid it was computed on
  std::size_t nbytes = 0;             ///< bytes its lists hold

  template <class T>
  static shape_state_handle of(std::shared_ptr<const gv::detail::shape::distance_ratio_state<T>> s, std::size_t voxels) {
    shape_state_handle h;
    h.f32 = std::is_same_v<T, float>;
    h.voxels = voxels;
    for (const auto& nd : s->nodes)
      h.nbytes += (nd.support->size() + nd.frontier->size()) * (sizeof(index_t) + sizeof(T));
    h.state = std::move(s);
    return h;
  }
  /// The state as the library's type, after checking that it is one of T on a grid of @p voxels voxels.
  template <class T>
  std::shared_ptr<const gv::detail::shape::distance_ratio_state<T>> as(std::size_t n) const {
    if (f32 != std::is_same_v<T, float> || voxels != n || !state)
      throw std::invalid_argument("geovoronoi: the shape-function state belongs to another grid or dtype");
    return std::static_pointer_cast<const gv::detail::shape::distance_ratio_state<T>>(state);
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

/// An explicit "seq" with threads > 1 is a contradiction (auto may pick seq for a small problem: the
/// thread count is then a limit it did not need).
inline void check_threads(const problem_args& a) {
  if (resolve_backend(a.backend) == "seq" && (a.backend == "seq" || !thrust_built()) && a.threads > 1)
    throw std::invalid_argument("geovoronoi: backend 'seq' runs on one thread; threads=" + std::to_string(a.threads) +
                                " needs backend 'thrust'");
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

template <class T, int Dim, bool Cuts>
nb::object voronoi_impl(const problem_args& a, const in_array& seeds, bool world, bool with_parent,
                        nb::object progress, const cut_handle* cut) {
  std::vector<std::size_t> shape(a.field.ndim());
  for (std::size_t i = 0; i < shape.size(); ++i) shape[i] = a.field.shape(i);
  const auto g = make_grid<Dim>(shape, a.spacing, a.origin);
  const auto coords = seeds_to_coords<Dim>(g, seeds, world);
  const T* field = static_cast<const T*>(a.field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(field);
  check_threads(a);
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
    with_metric(a.metric, [&](auto metric) {
      with_connectivity<Dim>(a.connectivity, [&](auto conn) {
        const auto p0 = gv::make_problem(g, gv::image_view<const T, Dim>(g, field), metric, conn);
        with_problem<Cuts>(p0, cut, [&](const auto& p) {
          with_backend(resolve_backend_for(a.backend, p, a.threads, false),
                       [&](const auto& policy) { h->d = gv::voronoi(policy, p, coords, opt); });
        });
      });
    });
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

inline gv::shape_method parse_method(const std::string& m) {
  if (m == "distance_ratio") return gv::shape_method::distance_ratio;
  if (m == "sibson") return gv::shape_method::sibson;
  if (m == "laplace") return gv::shape_method::laplace;
  throw std::invalid_argument("geovoronoi: unknown method '" + m + "' (distance_ratio, sibson or laplace)");
}

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
  opt.method = parse_method(method);
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

/// (weights tuple, state): the state is a shape_state_handle when @p keep (Distance Ratio on the whole
/// grid: shape_options::keep_update_state), else None.
template <class T, int Dim, bool Cuts>
nb::object shape_impl(const problem_args& a, diagram_handle& h, const std::string& method, int k,
                      std::size_t batch_size, nb::object progress, const std::optional<in_array>& points, bool keep) {
  auto* dp = &checked_diagram<T, Dim>(a, h);
  std::vector<std::size_t> shape(a.field.ndim());
  for (std::size_t i = 0; i < shape.size(); ++i) shape[i] = a.field.shape(i);
  const auto g = make_grid<Dim>(shape, a.spacing, a.origin);
  const T* field = static_cast<const T*>(a.field.data());
  last_field_address = reinterpret_cast<std::uintptr_t>(field);
  progress_bridge bridge{progress, 0.0, std::nullopt};
  gv::shape_options opt = make_shape_options(a, method, k, batch_size, bridge);
  if (keep && (points || opt.method != gv::shape_method::distance_ratio))
    throw std::invalid_argument("geovoronoi: keep_state applies to Distance Ratio on the whole grid only");
  opt.keep_update_state = keep;
  std::shared_ptr<const gv::detail::shape::distance_ratio_state<T>> kept;
  // Without points: every voxel (shape_functions); with points: only those voxels (shape_functions_at),
  // given as int64 array indices [z, y, x] already bounds-checked by the Python layer.
  std::optional<std::vector<gv::coord<Dim>>> at;
  if (points) at = seeds_to_coords<Dim>(g, *points, false);
  std::vector<label_t> node;
  std::vector<T> weight;
  std::size_t kk = 0, nodes = 0;
  run_released(a, bridge, [&] {
    with_metric(a.metric, [&](auto metric) {
      with_connectivity<Dim>(a.connectivity, [&](auto conn) {
        const auto p0 = gv::make_problem(g, gv::image_view<const T, Dim>(g, field), metric, conn);
        with_problem<Cuts>(p0, &h.cuts, [&](const auto& p) {
          with_backend(resolve_backend_for(a.backend, p, a.threads, true), [&](const auto& policy) {
            auto take = [&](auto&& w) {
              kk = std::size_t(w.k);
              nodes = w.nodes;
              node = std::move(w.node);
              weight = std::move(w.weight);
            };
            if (at) {
              take(gv::shape_functions_at(policy, p, *dp, *at, opt));
            } else {
              auto w = gv::shape_functions(policy, p, *dp, opt);
              kept = std::move(w.update_state);
              take(std::move(w));
            }
          });
        });
      });
    });
  });
  const std::size_t n = at ? at->size() : std::size_t(g.size());
  nb::object state = nb::none();
  if (kept) state = nb::cast(shape_state_handle::of<T>(std::move(kept), std::size_t(g.size())));
  return nb::make_tuple(weights_to_python(std::move(node), std::move(weight), n, kk, nodes,
                                          at ? std::vector<std::size_t>{n} : shape),
                        state);
}

/// voronoi() on a T field of 2 or 3 dimensions, with the edges of @p cut removed when it is not null
/// (defined in solve_<T>.cpp, and in cuts_<T>.cpp for the cut form).
template <class T, bool Cuts>
nb::object voronoi_typed(const problem_args& a, const in_array& seeds, bool world, bool with_parent,
                         nb::object progress, const cut_handle* cut) {
  if (a.field.ndim() == 2) return voronoi_impl<T, 2, Cuts>(a, seeds, world, with_parent, progress, cut);
  if (a.field.ndim() == 3) return voronoi_impl<T, 3, Cuts>(a, seeds, world, with_parent, progress, cut);
  throw std::invalid_argument("geovoronoi: the field must be a 2D or 3D array, got " + std::to_string(a.field.ndim()) +
                              " dimensions");
}

/// shape_functions() on a T field of 2 or 3 dimensions (Cuts: with the diagram's cut edges).
template <class T, bool Cuts>
nb::object shape_typed(const problem_args& a, diagram_handle& h, const std::string& method, int k,
                       std::size_t batch_size, nb::object progress, const std::optional<in_array>& points, bool keep) {
  if (a.field.ndim() == 2) return shape_impl<T, 2, Cuts>(a, h, method, k, batch_size, progress, points, keep);
  if (a.field.ndim() == 3) return shape_impl<T, 3, Cuts>(a, h, method, k, batch_size, progress, points, keep);
  throw std::invalid_argument("geovoronoi: the field must be a 2D or 3D array, got " + std::to_string(a.field.ndim()) +
                              " dimensions");
}

#define GEOVORONOI_PY_DECLARE(T, CUTS, EXTERN)                                                                      \
  EXTERN template nb::object voronoi_typed<T, CUTS>(const problem_args&, const in_array&, bool, bool, nb::object, \
                                                    const cut_handle*);                                          \
  EXTERN template nb::object shape_typed<T, CUTS>(const problem_args&, diagram_handle&, const std::string&, int,  \
                                                  std::size_t, nb::object, const std::optional<in_array>&, bool);
GEOVORONOI_PY_DECLARE(float, false, extern)
GEOVORONOI_PY_DECLARE(double, false, extern)
GEOVORONOI_PY_DECLARE(float, true, extern)
GEOVORONOI_PY_DECLARE(double, true, extern)

}  // namespace gvpy

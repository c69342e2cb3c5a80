// See branching.hpp. The one unit that instantiates the library's branching grids and their solves
// for the front end: 3D, float and double, every metric and connectivity of kinds.hpp, on seq and
// (when built) the Thrust backend on OpenMP host threads.
#include "branching.hpp"

#include "usage_error.hpp"

#include <geovoronoi/backend/seq.hpp>
#if defined(GEOVORONOI_FRONTEND_THRUST)
#include <geovoronoi/backend/thrust.hpp>
#endif

#include <algorithm>

namespace gvcli {

gv::stiffness_reduction parse_reduction(const std::string& name) {
  if (name == "mean") return gv::stiffness_reduction::mean;
  if (name == "min") return gv::stiffness_reduction::min;
  if (name == "max") return gv::stiffness_reduction::max;
  if (name == "harmonic" || name == "harmonic_mean") return gv::stiffness_reduction::harmonic_mean;
  throw usage_error("--reduction must be mean, min, max or harmonic, got '" + name + "'");
}

const char* reduction_name(gv::stiffness_reduction r) noexcept {
  switch (r) {
    case gv::stiffness_reduction::mean: return "mean";
    case gv::stiffness_reduction::min: return "min";
    case gv::stiffness_reduction::max: return "max";
    case gv::stiffness_reduction::harmonic_mean: return "harmonic";
  }
  return "?";
}

namespace {

/// The library's branching grid of @p fine (a copy of the view: make_branching_grid takes an image).
template <class T, int N>
gv::branching_grid<3, T, N> grid_of(gv::image_view<const T, 3> fine, int factor, gv::stiffness_reduction r) {
  const gv::image<T, 3> img(fine.geometry(),
                            std::vector<T>(fine.data(), fine.data() + std::size_t(fine.geometry().size())));
  gv::branching_options o;
  o.reduction = r;
  return gv::make_branching_grid(img, factor, gv::connectivity<N>{}, o);
}

template <class T, int N>
branching_arrays<T> arrays_of(const gv::branching_grid<3, T, N>& bg) {
  branching_arrays<T> a;
  a.coarse = bg.coarse();
  a.factor = bg.factor();
  a.cell_begin = bg.cell_begin();
  a.copy_cell = bg.copy_cell();
  a.copy_voxel = bg.copy_voxel();
  a.voxel_count = bg.voxel_count();
  a.link_begin = bg.link_begin();
  a.link_copy = bg.link_copy();
  a.link_dir = bg.link_dir();
  a.stiffness = bg.stiffness();
  a.fine_copy = bg.fine_copy();
  return a;
}

/// Calls f with the policy object of backend @p b (seq or thrust; cuda has no branching solve).
template <class F>
void with_branching_policy(backend_id b, F&& f) {
  switch (b) {
    case backend_id::seq: f(gv::seq); return;
    case backend_id::thrust:
#if defined(GEOVORONOI_FRONTEND_THRUST)
      f(gv::thrust::par);
      return;
#else
      throw usage_error("the thrust backend is not built into this binary");
#endif
    case backend_id::cuda:
      throw usage_error("--coarsen: the cuda backend is not available on branching grids; use --backend seq or thrust");
  }
  throw usage_error("--coarsen: unknown backend");
}

}  // namespace

template <class T>
branching_arrays<T> build_branching(gv::image_view<const T, 3> fine, int factor, int connectivity,
                                    gv::stiffness_reduction reduction) {
  branching_arrays<T> out;
  with_connectivity<3>(check_connectivity(connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    out = arrays_of(grid_of<T, N>(fine, factor, reduction));
  });
  return out;
}

template <class T>
branching_solution<T> solve_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                      const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt) {
  branching_solution<T> out;
  // the backend first: a refusal before any work
  with_branching_policy(key.backend, [](auto) {});
  with_connectivity<3>(check_connectivity(key.connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    const auto bg = grid_of<T, N>(fine, key.factor, key.reduction);
    with_metric(key.metric, [&](auto metric) {
      const auto p = gv::make_problem(bg, metric);
      with_branching_policy(key.backend, [&](auto policy) {
        gv::solve_options o = opt;
        o.with_parent = true;
        out.copies = gv::voronoi(policy, p, seeds, o);
      });
    });
    out.fine = gv::paint_fine(bg, out.copies);
    for (const auto& s : seeds) out.fine.seeds.push_back(bg.fine().index(s));
    out.grid = arrays_of(bg);
  });
  return out;
}

template branching_arrays<float> build_branching(gv::image_view<const float, 3>, int, int, gv::stiffness_reduction);
template branching_arrays<double> build_branching(gv::image_view<const double, 3>, int, int, gv::stiffness_reduction);
template branching_solution<float> solve_branching(const branching_key&, gv::image_view<const float, 3>,
                                                   const std::vector<gv::coord<3>>&, const gv::solve_options&);
template branching_solution<double> solve_branching(const branching_key&, gv::image_view<const double, 3>,
                                                    const std::vector<gv::coord<3>>&, const gv::solve_options&);

}  // namespace gvcli

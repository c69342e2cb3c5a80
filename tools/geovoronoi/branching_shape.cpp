// See branching.hpp. The unit that instantiates the library's shape functions on branching grids
// (include/geovoronoi/branching_shape.hpp) and the cut's update for the front end: 3D, float and
// double, every metric and connectivity of kinds.hpp, on seq and (when built) the Thrust backend on
// OpenMP host threads.
#include "branching.hpp"

#include "branching_impl.hpp"

#include <chrono>
#include <utility>

namespace gvcli {

using detail::grid_of;
using detail::with_branching_policy;

namespace {

double since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The weights of the diagram in @p out on problem @p p of grid @p bg, as @p x asks: per copy and
/// painted on the fine grid, or at the fine voxels x.at.
template <class T, int N, class P, class Policy>
void weights_into(branching_solution<T>& out, const gv::branching_grid<3, T, N>& bg, const P& p, const Policy& policy,
                  const branching_extras& x) {
  if (!x.shape) return;
  if (x.at) {
    out.at_weights = gv::shape_functions_at(policy, p, out.copies, *x.at, *x.shape);
    out.has_at = true;
    return;
  }
  out.weights = gv::shape_functions(policy, p, out.copies, *x.shape);
  out.fine_weights = gv::paint_fine(bg, out.weights);
  out.has_weights = true;
}

}  // namespace

template <class T>
branching_solution<T> solve_branching_shapes(const branching_key& key, gv::image_view<const T, 3> fine,
                                             const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                             const branching_extras& x) {
  branching_solution<T> out;
  with_branching_policy(key.backend, [](auto) {});  // a refusal before any work
  with_connectivity<3>(check_connectivity(key.connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    const auto bg = grid_of<T, N>(fine, key.factor, key.reduction, x.cut);
    with_metric(key.metric, [&](auto metric) {
      const auto p = gv::make_problem(bg, metric);
      with_branching_policy(key.backend, [&](auto policy) {
        detail::solve_into(out, bg, p, policy, seeds, opt);
        weights_into(out, bg, p, policy, x);
      });
    });
  });
  return out;
}

template <class T>
branching_cut_run<T> cut_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                   const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt,
                                   const gv::cut_set<3>& cut, const gv::shape_options* shape) {
  branching_cut_run<T> run;
  with_branching_policy(key.backend, [](auto) {});  // a refusal before any work
  // Distance Ratio keeps its searches with the weights before, for the update to reuse
  gv::shape_options shape_kept;
  if (shape) {
    shape_kept = *shape;
    shape_kept.keep_update_state = shape->method == gv::shape_method::distance_ratio;
  }
  branching_extras kept, plain;  // the weights before (with the state), the recompute's (as the user's run)
  kept.shape = shape ? &shape_kept : nullptr;
  plain.shape = shape;
  with_connectivity<3>(check_connectivity(key.connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    const auto before_grid = grid_of<T, N>(fine, key.factor, key.reduction);
    auto t0 = std::chrono::steady_clock::now();
    const auto after_grid = grid_of<T, N>(fine, key.factor, key.reduction, &cut);
    run.grid_seconds = since(t0);
    with_metric(key.metric, [&](auto metric) {
      with_branching_policy(key.backend, [&](auto policy) {
        const auto before_p = gv::make_problem(before_grid, metric);
        const auto after_p = gv::make_problem(after_grid, metric);
        detail::solve_into(run.before, before_grid, before_p, policy, seeds, opt);
        weights_into(run.before, before_grid, before_p, policy, kept);
        // the full recompute on the cut grid
        t0 = std::chrono::steady_clock::now();
        detail::solve_into(run.full, after_grid, after_p, policy, seeds, opt);
        run.recompute_seconds = since(t0);
        t0 = std::chrono::steady_clock::now();
        weights_into(run.full, after_grid, after_p, policy, plain);
        run.shape_recompute_seconds = since(t0);
        // the library's incremental update from the diagram (and weights) before
        t0 = std::chrono::steady_clock::now();
        run.updated.copies = gv::update(policy, after_p, before_grid, run.before.copies, seeds, &run.stats);
        run.update_seconds = since(t0);
        run.updated.fine = gv::paint_fine(after_grid, run.updated.copies);
        for (const auto& s : seeds) run.updated.fine.seeds.push_back(after_grid.fine().index(s));
        run.updated.grid = detail::arrays_of(after_grid);
        run.copies_before = std::size_t(before_grid.copies());
        run.copies_after = std::size_t(after_grid.copies());
        if (shape) {
          t0 = std::chrono::steady_clock::now();
          run.updated.weights = gv::update_shape_functions(policy, after_p, before_grid, run.before.copies,
                                                           run.updated.copies, run.before.weights, shape_kept);
          run.shape_update_seconds = since(t0);
          run.updated.fine_weights = gv::paint_fine(after_grid, run.updated.weights);
          run.updated.has_weights = true;
        }
      });
    });
  });
  return run;
}

template <class T>
branching_solution<T> update_branching(const branching_key& key, gv::image_view<const T, 3> fine,
                                       const std::vector<gv::coord<3>>& seeds, const gv::cut_set<3>* before_cut,
                                       const gv::cut_set<3>& after_cut, const gv::branching_diagram<T>& before,
                                       gv::update_stats& stats) {
  branching_solution<T> out;
  with_branching_policy(key.backend, [](auto) {});  // a refusal before any work
  with_connectivity<3>(check_connectivity(key.connectivity, 3), [&](auto conn) {
    constexpr int N = decltype(conn)::size;
    const auto before_grid = grid_of<T, N>(fine, key.factor, key.reduction, before_cut);
    const auto after_grid = grid_of<T, N>(fine, key.factor, key.reduction, &after_cut);
    with_metric(key.metric, [&](auto metric) {
      const auto p = gv::make_problem(after_grid, metric);
      with_branching_policy(key.backend, [&](auto policy) {
        out.copies = gv::update(policy, p, before_grid, before, seeds, &stats);
      });
    });
    out.fine = gv::paint_fine(after_grid, out.copies);
    for (const auto& s : seeds) out.fine.seeds.push_back(after_grid.fine().index(s));
    out.grid = detail::arrays_of(after_grid);
  });
  return out;
}

template branching_solution<float> solve_branching_shapes(const branching_key&, gv::image_view<const float, 3>,
                                                          const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                          const branching_extras&);
template branching_solution<double> solve_branching_shapes(const branching_key&, gv::image_view<const double, 3>,
                                                           const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                           const branching_extras&);
template branching_solution<float> update_branching(const branching_key&, gv::image_view<const float, 3>,
                                                    const std::vector<gv::coord<3>>&, const gv::cut_set<3>*,
                                                    const gv::cut_set<3>&, const gv::branching_diagram<float>&,
                                                    gv::update_stats&);
template branching_solution<double> update_branching(const branching_key&, gv::image_view<const double, 3>,
                                                     const std::vector<gv::coord<3>>&, const gv::cut_set<3>*,
                                                     const gv::cut_set<3>&, const gv::branching_diagram<double>&,
                                                     gv::update_stats&);
template branching_cut_run<float> cut_branching(const branching_key&, gv::image_view<const float, 3>,
                                                const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                const gv::cut_set<3>&, const gv::shape_options*);
template branching_cut_run<double> cut_branching(const branching_key&, gv::image_view<const double, 3>,
                                                 const std::vector<gv::coord<3>>&, const gv::solve_options&,
                                                 const gv::cut_set<3>&, const gv::shape_options*);

}  // namespace gvcli

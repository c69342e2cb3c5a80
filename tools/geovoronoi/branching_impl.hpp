#pragma once
// What the front end's branching units (branching.cpp: the diagram; branching_shape.cpp: the shape
// functions and the cut's update) share: the library's branching grid of a fine view, its arrays
// copied out, the backend's policy. Included by those units only.

#include "branching.hpp"
#include "usage_error.hpp"

#include <geovoronoi/backend/seq.hpp>
#if defined(GEOVORONOI_FRONTEND_THRUST)
#include <geovoronoi/backend/thrust.hpp>
#endif

namespace gvcli::detail {

/// The library's branching grid of @p fine (a copy of the view: make_branching_grid takes an image),
/// with the fine grid's cut edges @p cut (null: none) splitting the copies they cross.
template <class T, int N>
gv::branching_grid<3, T, N> grid_of(gv::image_view<const T, 3> fine, int factor, gv::stiffness_reduction r,
                                    const gv::cut_set<3>* cut = nullptr) {
  const gv::image<T, 3> img(fine.geometry(),
                            std::vector<T>(fine.data(), fine.data() + std::size_t(fine.geometry().size())));
  gv::branching_options o;
  o.reduction = r;
  if (cut) return gv::make_branching_grid(img, factor, gv::connectivity<N>{}, *cut, o);
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

/// The diagram of @p seeds on the problem @p p of grid @p bg (parents included), per copy and painted
/// on the fine grid, into @p out (grid arrays included).
template <class T, int N, class P, class Policy>
void solve_into(branching_solution<T>& out, const gv::branching_grid<3, T, N>& bg, const P& p, const Policy& policy,
                const std::vector<gv::coord<3>>& seeds, const gv::solve_options& opt) {
  gv::solve_options o = opt;
  o.with_parent = true;
  out.copies = gv::voronoi(policy, p, seeds, o);
  out.fine = gv::paint_fine(bg, out.copies);
  for (const auto& s : seeds) out.fine.seeds.push_back(bg.fine().index(s));
  out.grid = arrays_of(bg);
}

}  // namespace gvcli::detail

// Random edits (cuts, carving, added voxels, field edits, node edits, in sequences) on a Thrust
// policy: update(policy, ...) equals voronoi(policy, ..., {with_parent}) bit for bit.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#ifdef GEOVORONOI_TEST_UPDATE_OMP
#include <thrust/system/omp/execution_policy.h>
#define GEOVORONOI_TEST_UPDATE_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)
#else
#include <thrust/system/cpp/execution_policy.h>
#define GEOVORONOI_TEST_UPDATE_POLICY() ::geovoronoi::thrust::par_on(::thrust::cpp::par)
#endif

#include "support/update_edits.hpp"

TEST_CASE("update with a Thrust policy equals that policy's full solve after every edit") {
  const auto policy = GEOVORONOI_TEST_UPDATE_POLICY();
  const unsigned all = gvtest::field_edit | gvtest::carve_edit | gvtest::add_edit | gvtest::node_edits | gvtest::cut_edit;
  gvtest::edit_all_metrics<float, 2, 8>(policy, 6, 3, all);
  gvtest::edit_all_metrics<float, 3, 26>(policy, 6, 3, all);
  gvtest::edit_all_metrics<double, 3, 6>(policy, 3, 3, all);
  CHECK(gvtest::totals().updates > 100);
}

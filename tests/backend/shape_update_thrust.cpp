// Shape functions after random edits (shape_update.hpp) on a Thrust policy: along the random edit
// sequences of update_edits.hpp, the updated weights (every method, K 1/3/4, and at random points)
// equal that policy's full shape_functions / shape_functions_at bit for bit after every step. Fewer
// cases than the sequential test (shape_update.test.cpp): the update is the same host algorithm for
// every policy, only the row computations run on the policy.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>
#define GEOVORONOI_TEST_UPDATE_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)

#include "support/shape_update_check.hpp"

TEST_CASE("shape update with a Thrust policy equals that policy's full computation after every edit") {
  const auto policy = GEOVORONOI_TEST_UPDATE_POLICY();
  const unsigned all = gvtest::field_edit | gvtest::carve_edit | gvtest::add_edit | gvtest::node_edits | gvtest::cut_edit;
  gvtest::shape_edits<float, 2, 8, geovoronoi::min_stiffness, gvtest::destination_cost>(policy, 6, 3, all, 21, true);
  gvtest::shape_edits<float, 3, 26, gvtest::wavy_cost, geovoronoi::mean_cost>(policy, 5, 3, all, 22, false);
  const auto& t = gvtest::shape_totals();
  MESSAGE(t.updates << " voxel updates, " << t.point_updates << " point updates, " << t.partial
                    << " recomputed fewer rows than all; rows recomputed " << t.recomputed << " of " << t.rows);
  CHECK(t.updates > 400);
  CHECK(t.partial > t.updates / 4);
}

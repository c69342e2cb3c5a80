// Shape-function benchmarks on the Thrust backend, OMP system (cases in cases.hpp), and the updates
// after a change (update_cases.hpp).
#include "cases.hpp"
#include "update_cases.hpp"

#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

int main(int argc, char** argv) {
  gvbench_shape::register_cases(geovoronoi::thrust::par_on(thrust::omp::par), "thrust_omp");
  // every query searched (shape_options::skip_single_owner_rows off): the before of that change
  gvbench_shape::register_cases(geovoronoi::thrust::par_on(thrust::omp::par), "thrust_omp_nofilter", false, true,
                                false);
  gvbench_shape::register_update_cases(geovoronoi::thrust::par_on(thrust::omp::par), "thrust_omp");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

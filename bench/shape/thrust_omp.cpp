// Shape-function benchmarks on the Thrust backend, OMP system (cases in cases.hpp), and the updates
// after a change (update_cases.hpp).
#include "cases.hpp"
#include "update_cases.hpp"

#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

int main(int argc, char** argv) {
  gvbench_shape::register_cases(geovoronoi::thrust::par_on(thrust::omp::par), "thrust_omp");
  gvbench_shape::register_update_cases(geovoronoi::thrust::par_on(thrust::omp::par), "thrust_omp");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

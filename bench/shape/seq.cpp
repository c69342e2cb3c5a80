// Shape-function benchmarks on the sequential backend (cases in cases.hpp).
#include "cases.hpp"

int main(int argc, char** argv) {
  gvbench_shape::register_cases(geovoronoi::seq, "seq");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

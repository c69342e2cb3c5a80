// Shape-function benchmarks on the sequential backend (cases in cases.hpp), and the same cases on
// `seq_materialise`: the sequential backend through the materialise-and-re-read path that Sibson and
// Laplace used before the fused search (for same-run before/after ratios), and `seq_noreuse`: the
// fused search without the exact balls of constant regions, and `seq_nofilter`: every Sibson query
// searched (no rows of one node written without their search). Also the updates after a change
// (update_cases.hpp: shape_update/<method>/seq/steak128/<edit>).
#include "cases.hpp"
#include "update_cases.hpp"

int main(int argc, char** argv) {
  gvbench_shape::register_cases(geovoronoi::seq, "seq");
  gvbench_shape::register_cases(gvbench_shape::materialise_seq_t{}, "seq_materialise", false);
  gvbench_shape::register_cases(geovoronoi::seq, "seq_noreuse", false, false);  // fused, no exact balls
  gvbench_shape::register_cases(geovoronoi::seq, "seq_nofilter", false, true, false);
  gvbench_shape::register_update_cases(geovoronoi::seq, "seq");
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

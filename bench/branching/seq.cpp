/// @file bench/branching/seq.cpp
/// @brief Branching grids on the sequential backend (`branching/seq/...`, see cases.hpp).

#include "branching/cases.hpp"
#include "branching/shape_cases.hpp"

GEOVORONOI_BENCH_REGISTER(register_branching_seq) {
  geovoronoi::bench::branching::register_cases("seq", geovoronoi::seq);
  geovoronoi::bench::branching_shape::register_shape_cases("seq", geovoronoi::seq);
  geovoronoi::bench::branching_shape::register_update_cases("seq", geovoronoi::seq);
}

#ifndef GEOVORONOI_BENCH_COMBINED
GEOVORONOI_BENCH_MAIN()
#endif

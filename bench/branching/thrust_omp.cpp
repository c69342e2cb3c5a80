/// @file bench/branching/thrust_omp.cpp
/// @brief Branching grids on the Thrust backend, OpenMP system (`branching/thrust_omp/...`, see
///        cases.hpp); linked with seq.cpp so that both backends run in one process.

#include "branching/cases.hpp"
#include "branching/shape_cases.hpp"

#include <geovoronoi/backend/thrust.hpp>
#include <thrust/system/omp/execution_policy.h>

GEOVORONOI_BENCH_REGISTER(register_branching_thrust_omp) {
  geovoronoi::bench::branching::register_cases("thrust_omp", geovoronoi::thrust::par_on(::thrust::omp::par));
  geovoronoi::bench::branching_shape::register_shape_cases("thrust_omp", geovoronoi::thrust::par_on(::thrust::omp::par));
}

GEOVORONOI_BENCH_MAIN()

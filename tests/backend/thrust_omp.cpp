// The shared backend suite on the Thrust backend, OMP system (an explicit execution policy).
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

#define GEOVORONOI_TEST_BACKEND_NAME "thrust_omp"
#define GEOVORONOI_TEST_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)
#include "backend/suite.hpp"
#include "backend/thrust_extra.hpp"

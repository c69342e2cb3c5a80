// The shared backend suite on the Thrust backend, CPP system (an explicit execution policy).
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/cpp/execution_policy.h>

#define GEOVORONOI_TEST_BACKEND_NAME "thrust_cpp"
#define GEOVORONOI_TEST_POLICY() ::geovoronoi::thrust::par_on(::thrust::cpp::par)
// the full type/connectivity matrix runs on thrust_omp (same engine code, another Thrust system)
#define GEOVORONOI_TEST_REDUCED_MATRIX
#include "backend/suite.hpp"
#include "backend/thrust_extra.hpp"

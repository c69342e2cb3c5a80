// The shape-function suite on the Thrust backend, OMP system, plus a bitwise comparison with seq.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

#define GEOVORONOI_SHAPE_BACKEND_NAME "thrust_omp"
#define GEOVORONOI_SHAPE_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)
#include "backend/shape/suite.hpp"
#include "backend/shape/versus_seq.hpp"

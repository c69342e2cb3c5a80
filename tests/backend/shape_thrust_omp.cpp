// The shape-function suite on the Thrust backend, OMP system, plus a bitwise comparison with seq.
#include <geovoronoi.hpp>
#include <geovoronoi/backend/thrust.hpp>

#include <thrust/system/omp/execution_policy.h>

#define GEOVORONOI_SHAPE_BACKEND_NAME "thrust_omp"
#define GEOVORONOI_SHAPE_POLICY() ::geovoronoi::thrust::par_on(::thrust::omp::par)
// the SSE2 and 16-lane forms of the lane search are policy-independent code, compared in the seq suite
#define GEOVORONOI_SHAPE_SIMD_VARIANTS 0
#include "backend/shape/suite.hpp"
#include "backend/shape/versus_seq.hpp"

// Tests of geovoronoi/shape_functions.hpp on the sequential backend (the shared suite in
// tests/shape/suite.hpp; other backends instantiate it from tests/backend/shape_<backend>.cmake hooks).
#include <geovoronoi.hpp>

#define GEOVORONOI_SHAPE_BACKEND_NAME "seq"
#define GEOVORONOI_SHAPE_POLICY() ::geovoronoi::seq
#include "shape/suite.hpp"

// The shared backend suite, instantiated for the sequential backend.
#include <geovoronoi.hpp>

#define GEOVORONOI_TEST_BACKEND_NAME "seq"
#define GEOVORONOI_TEST_POLICY() ::geovoronoi::seq
#include "backend/suite.hpp"

// The float instantiations of the extension's solve wrappers (see bindings.hpp).
#include "bindings.hpp"

namespace gvpy {
GEOVORONOI_PY_DECLARE(float, false, )
}  // namespace gvpy

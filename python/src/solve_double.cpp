// The double instantiations of the extension's solve wrappers (see bindings.hpp).
#include "bindings.hpp"

namespace gvpy {
GEOVORONOI_PY_DECLARE(double, false, )
}  // namespace gvpy

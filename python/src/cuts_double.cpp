// The double instantiations of the extension's wrappers with cut edges and of the updates (see cuts.hpp).
#include "cuts.hpp"

namespace gvpy {
GEOVORONOI_PY_DECLARE(double, true, )
GEOVORONOI_PY_DECLARE_UPDATE(double, )
}  // namespace gvpy

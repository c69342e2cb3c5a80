// image::view() of a temporary image would dangle once the statement ends, so it is deleted.
#include <geovoronoi/image.hpp>

namespace gv = geovoronoi;

float view_of_a_named_image() {
  const gv::grid<2> g({4, 4});
#ifdef GEOVORONOI_COMPILE_FAIL
  const auto v = gv::image<float, 2>(g, 1.0f).view();
#else
  const gv::image<float, 2> img(g, 1.0f);
  const auto v = img.view();
#endif
  return v.data()[0];
}

# The shared backend suite on the Thrust backend: one executable per Thrust system available.
if(TARGET geovoronoi::thrust_cpp)
  geovoronoi_add_test(test_backend_thrust_cpp backend/thrust_cpp.cpp LIBS geovoronoi::thrust_cpp)
endif()
if(TARGET geovoronoi::thrust_omp)
  geovoronoi_add_test(test_backend_thrust_omp backend/thrust_omp.cpp LIBS geovoronoi::thrust_omp)
endif()
if(TARGET geovoronoi::thrust_tbb)
  geovoronoi_add_test(test_backend_thrust_tbb backend/thrust_tbb.cpp LIBS geovoronoi::thrust_tbb)
endif()
if(TARGET geovoronoi::thrust_cuda)
  # Compiled by nvcc for GEOVORONOI_CUDA_ARCHITECTURES; reports skipped (77) without a device.
  geovoronoi_add_test(test_backend_thrust_cuda backend/thrust_cuda.cu LIBS geovoronoi::thrust_cuda)
  set_target_properties(test_backend_thrust_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
endif()
if(TARGET geovoronoi::thrust)
  # The public header compiles on its own (twice: include guard).
  set(_gv_tu ${CMAKE_CURRENT_BINARY_DIR}/headers/geovoronoi_backend_thrust_hpp.cpp)
  file(CONFIGURE OUTPUT ${_gv_tu} CONTENT
       "#include <geovoronoi/backend/thrust.hpp>\n#include <geovoronoi/backend/thrust.hpp> // include guard works\n")
  add_library(geovoronoi_thrust_header_check OBJECT ${_gv_tu})
  target_link_libraries(geovoronoi_thrust_header_check PRIVATE geovoronoi::thrust_cpp geovoronoi_dev_options)
endif()

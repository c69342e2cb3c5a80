# The shared backend suite on the Thrust backend: one executable per Thrust system available. The CPP
# and TBB suites (a reduced matrix) can be left out of a build that has already run them elsewhere
# (GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS=OFF, e.g. the "sanitize" preset's second build).
option(GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS "Build the Thrust CPP and TBB backend suites" ON)
if(TARGET geovoronoi::thrust_cpp AND GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS)
  geovoronoi_add_test(test_backend_thrust_cpp backend/thrust_cpp.cpp LIBS geovoronoi::thrust_cpp)
endif()
option(GEOVORONOI_TEST_REDUCED_MATRIX
       "The Thrust OpenMP backend suite instantiates the reduced matrix (for a second build, e.g. under sanitizers)" OFF)
if(TARGET geovoronoi::thrust_omp)
  geovoronoi_add_test(test_backend_thrust_omp backend/thrust_omp.cpp LIBS geovoronoi::thrust_omp)
  if(GEOVORONOI_TEST_REDUCED_MATRIX)
    target_compile_definitions(test_backend_thrust_omp PRIVATE GEOVORONOI_TEST_REDUCED_MATRIX=)
  endif()
endif()
if(TARGET geovoronoi::thrust_tbb AND GEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS)
  geovoronoi_add_test(test_backend_thrust_tbb backend/thrust_tbb.cpp LIBS geovoronoi::thrust_tbb)
endif()
if(TARGET geovoronoi::thrust_cuda)
  # Compiled by nvcc for GEOVORONOI_CUDA_ARCHITECTURES; reports skipped (77) without a device.
  # Its own main() (exit code 77 when no case found a device), so not geovoronoi_add_test's.
  add_executable(test_backend_thrust_cuda backend/thrust_cuda.cu)
  if(GEOVORONOI_TEST_CUDA_REDUCED_MATRIX)  # option in cuda.cmake: compile-only builds
    target_compile_definitions(test_backend_thrust_cuda PRIVATE GEOVORONOI_TEST_REDUCED_MATRIX=)
  endif()
  target_include_directories(test_backend_thrust_cuda PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(test_backend_thrust_cuda PRIVATE doctest::doctest geovoronoi::thrust_cuda geovoronoi_dev_options
                        CUDA::cudart)
  add_test(NAME test_backend_thrust_cuda COMMAND test_backend_thrust_cuda)
  set_tests_properties(test_backend_thrust_cuda PROPERTIES SKIP_RETURN_CODE 77)
  set_target_properties(test_backend_thrust_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  # branching grids on the CUDA system against seq (a small executable of its own, same conventions)
  add_executable(test_branching_thrust_cuda backend/branching_thrust_cuda.cu)
  target_link_libraries(test_branching_thrust_cuda PRIVATE doctest::doctest geovoronoi::thrust_cuda geovoronoi_dev_options
                        CUDA::cudart)
  add_test(NAME test_branching_thrust_cuda COMMAND test_branching_thrust_cuda)
  set_tests_properties(test_branching_thrust_cuda PROPERTIES SKIP_RETURN_CODE 77)
  set_target_properties(test_branching_thrust_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
endif()
if(TARGET geovoronoi::thrust AND GEOVORONOI_HEADER_CHECKS)
  # The public header compiles on its own (twice: include guard).
  set(_gv_tu ${CMAKE_CURRENT_BINARY_DIR}/headers/geovoronoi_backend_thrust_hpp.cpp)
  file(CONFIGURE OUTPUT ${_gv_tu} CONTENT
       "#include <geovoronoi/backend/thrust.hpp>\n#include <geovoronoi/backend/thrust.hpp> // include guard works\n")
  add_library(geovoronoi_thrust_header_check OBJECT ${_gv_tu})
  target_link_libraries(geovoronoi_thrust_header_check PRIVATE geovoronoi::thrust_cpp geovoronoi_dev_options)
endif()

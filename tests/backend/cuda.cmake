# CUDA backend tests.
#  - test_backend_cuda_detail_tiling (tests/backend/cuda/detail/tiling.test.cpp, added by the
#    *.test.cpp glob, g++ only): the
#    host-device arithmetic of the backend (tiles, halo slots, keys, worklist, query boxes). Built
#    on every machine; it only needs the backend's include directory.
#  - test_backend_cuda (tests/backend/cuda.cu, nvcc): the shared backend suite. Without a device it
#    exits 77 and CTest reports it skipped.
#  - test_backend_cuda_detail_tile_ops (tests/backend/cuda/detail/tile_ops.test.cpp, g++): the
#    algorithm run on the host from the kernels' own per-voxel steps (tile_ops.hpp), against seq.
foreach(t test_backend_cuda_detail_tiling test_backend_cuda_detail_tile_ops)
  if(TARGET ${t})
    target_include_directories(${t} PRIVATE ${PROJECT_SOURCE_DIR}/backends/cuda/include)
  endif()
endforeach()
# Where no GPU will run them (scripts/test.sh on a machine without one), the nvcc-compiled suites
# (test_backend_cuda, test_backend_thrust_cuda) only prove that the code compiles; then they may
# instantiate the suite's reduced type/connectivity matrix (suite.hpp), which halves their compile
# time. With a GPU, leave this OFF: the full matrix runs.
option(GEOVORONOI_TEST_CUDA_REDUCED_MATRIX
       "Instantiate the reduced backend-suite matrix in the nvcc-compiled suites (for compile-only builds)" OFF)
if(GEOVORONOI_HAVE_CUDA)
  add_executable(test_backend_cuda ${CMAKE_CURRENT_LIST_DIR}/cuda.cu)
  if(GEOVORONOI_TEST_CUDA_REDUCED_MATRIX)
    target_compile_definitions(test_backend_cuda PRIVATE GEOVORONOI_TEST_REDUCED_MATRIX=)
  endif()
  target_include_directories(test_backend_cuda PRIVATE ${CMAKE_CURRENT_SOURCE_DIR})
  target_link_libraries(test_backend_cuda PRIVATE doctest::doctest geovoronoi::cuda geovoronoi_dev_options)
  set_target_properties(test_backend_cuda PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  # the host compiler's warnings, as errors when asked; nvcc's own diagnostics as errors too
  # 20011, 20014: the oracle's destination_cost metric is host-only, and the core's host-device
  # problem::inside() instantiates with it; that call only ever runs on the host (kernels use
  # the device_metric specialisation in cuda.cu), so the diagnostic is silenced for this TU only.
  target_compile_options(test_backend_cuda PRIVATE
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow;--diag-suppress=20011,20014>
    $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
  add_test(NAME test_backend_cuda COMMAND test_backend_cuda)
  set_tests_properties(test_backend_cuda PROPERTIES SKIP_RETURN_CODE 77 LABELS cuda)
endif()

# Every public header compiles on its own: cuda.cuh with nvcc, the compiler-neutral detail headers
# with the C++ compiler (they are what the host tests include).
set(_gv_cuda_tus)
foreach(h geovoronoi/backend/cuda/detail/tiling.hpp geovoronoi/backend/cuda/detail/tile_ops.hpp)
  string(MAKE_C_IDENTIFIER ${h} id)
  file(CONFIGURE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/headers/${id}.cpp CONTENT "#include <${h}>\n#include <${h}>\n")
  list(APPEND _gv_cuda_tus ${CMAKE_CURRENT_BINARY_DIR}/headers/${id}.cpp)
endforeach()
add_library(geovoronoi_cuda_host_header_check OBJECT ${_gv_cuda_tus})
target_include_directories(geovoronoi_cuda_host_header_check PRIVATE ${PROJECT_SOURCE_DIR}/backends/cuda/include)
target_link_libraries(geovoronoi_cuda_host_header_check PRIVATE geovoronoi::geovoronoi geovoronoi_dev_options)
if(GEOVORONOI_HAVE_CUDA)
  file(CONFIGURE OUTPUT ${CMAKE_CURRENT_BINARY_DIR}/headers/geovoronoi_backend_cuda_cuh.cu
       CONTENT "#include <geovoronoi/backend/cuda.cuh>\n#include <geovoronoi/backend/cuda.cuh>\n")
  add_library(geovoronoi_cuda_header_check OBJECT ${CMAKE_CURRENT_BINARY_DIR}/headers/geovoronoi_backend_cuda_cuh.cu)
  target_link_libraries(geovoronoi_cuda_header_check PRIVATE geovoronoi::cuda)
  target_compile_options(geovoronoi_cuda_header_check PRIVATE
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow>
    $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
endif()

# Without a device: every entry point throws cuda_error with the call site and CUDA's message.
if(GEOVORONOI_HAVE_CUDA)
  add_executable(test_cuda_errors ${CMAKE_CURRENT_LIST_DIR}/cuda_errors.cu)
  target_link_libraries(test_cuda_errors PRIVATE geovoronoi::cuda geovoronoi_dev_options)
  set_target_properties(test_cuda_errors PROPERTIES CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
  target_compile_options(test_cuda_errors PRIVATE
    $<$<COMPILE_LANGUAGE:CUDA>:-Xcompiler=-Wall,-Wextra,-Wshadow>
    $<$<AND:$<COMPILE_LANGUAGE:CUDA>,$<BOOL:${GEOVORONOI_WERROR}>>:-Werror=all-warnings>)
  add_test(NAME test_cuda_errors COMMAND test_cuda_errors)
  set_tests_properties(test_cuda_errors PROPERTIES SKIP_RETURN_CODE 77 LABELS cuda)
endif()

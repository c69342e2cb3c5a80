# Optional backends. Each is an INTERFACE target that adds its include directory to the core.
#   geovoronoi::thrust  (Thrust from the CUDA toolkit's CCCL, else Debian's libthrust-dev)
#   geovoronoi::cuda    (needs the CUDA language)
# Filled in by the Thrust and CUDA backend work; until then both report themselves unavailable.
set(GEOVORONOI_HAVE_THRUST OFF)
set(GEOVORONOI_HAVE_CUDA OFF)
if(EXISTS ${PROJECT_SOURCE_DIR}/backends/thrust/backend.cmake)
  include(${PROJECT_SOURCE_DIR}/backends/thrust/backend.cmake)
endif()
if(EXISTS ${PROJECT_SOURCE_DIR}/backends/cuda/backend.cmake)
  include(${PROJECT_SOURCE_DIR}/backends/cuda/backend.cmake)
endif()
message(STATUS "geovoronoi: Thrust backend ${GEOVORONOI_HAVE_THRUST}, CUDA backend ${GEOVORONOI_HAVE_CUDA}")

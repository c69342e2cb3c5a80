# Locates Thrust's headers (directory holding thrust/version.h) into GEOVORONOI_THRUST_INCLUDE_DIR.
# Used by the build (backends/thrust/backend.cmake) and, installed next to the package config, by
# geovoronoi-backends.cmake on the consumer's machine, so the installed package names no absolute
# path: Thrust comes from the CUDA toolkit's CCCL (include/cccl, which also holds CUB and libcu++)
# when the toolkit is found, else from the default search path (Debian's libthrust-dev).
if(NOT GEOVORONOI_THRUST_INCLUDE_DIR)
  find_package(CUDAToolkit QUIET)
  set(_gv_thrust_hints)
  foreach(_gv_d IN LISTS CUDAToolkit_INCLUDE_DIRS)
    list(APPEND _gv_thrust_hints ${_gv_d}/cccl ${_gv_d})
  endforeach()
  find_path(GEOVORONOI_THRUST_INCLUDE_DIR thrust/version.h HINTS ${_gv_thrust_hints}
            DOC "Directory holding thrust/version.h (and cub/, cuda/ for CCCL)")
  unset(_gv_thrust_hints)
  unset(_gv_d)
endif()

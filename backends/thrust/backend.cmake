# The Thrust backend (included by cmake/GeovoronoiBackends.cmake).
#
# Thrust is header-only. It comes from the CUDA toolkit's CCCL (include/cccl, which also holds CUB and
# libcu++) when present, else from a system install such as Debian's libthrust-dev. Targets:
#   geovoronoi::thrust      core + backend headers; the consumer sets THRUST_DEVICE_SYSTEM itself
#   geovoronoi::thrust_cpp  THRUST_DEVICE_SYSTEM=CPP (serial, always available)
#   geovoronoi::thrust_omp  THRUST_DEVICE_SYSTEM=OMP + OpenMP::OpenMP_CXX   (when OpenMP is found)
#   geovoronoi::thrust_tbb  THRUST_DEVICE_SYSTEM=TBB + TBB::tbb             (when TBB is found)
#   geovoronoi::thrust_cuda THRUST_DEVICE_SYSTEM=CUDA                       (when the CUDA language is on)
# GEOVORONOI_THRUST = AUTO (use it if found) | ON (fail if not found) | OFF.

string(TOUPPER "${GEOVORONOI_THRUST}" _gv_thrust_mode)
if(NOT _gv_thrust_mode STREQUAL "OFF")
  find_package(CUDAToolkit QUIET)
  set(_gv_thrust_hints)
  if(CUDAToolkit_INCLUDE_DIRS)
    foreach(d ${CUDAToolkit_INCLUDE_DIRS})
      list(APPEND _gv_thrust_hints ${d}/cccl ${d})
    endforeach()
  endif()
  list(APPEND _gv_thrust_hints /usr/local/cuda/include/cccl /usr/local/cuda/include)
  find_path(GEOVORONOI_THRUST_INCLUDE_DIR thrust/version.h HINTS ${_gv_thrust_hints}
            DOC "Directory holding thrust/version.h (and cub/, cuda/ for CCCL)")
  if(GEOVORONOI_THRUST_INCLUDE_DIR)
    set(GEOVORONOI_HAVE_THRUST ON)
  elseif(_gv_thrust_mode STREQUAL "ON")
    message(FATAL_ERROR "geovoronoi: GEOVORONOI_THRUST=ON but Thrust was not found "
                        "(install the CUDA toolkit or libthrust-dev, or set GEOVORONOI_THRUST_INCLUDE_DIR)")
  endif()
endif()

if(GEOVORONOI_HAVE_THRUST)
  add_library(geovoronoi_thrust INTERFACE)
  add_library(geovoronoi::thrust ALIAS geovoronoi_thrust)
  set_target_properties(geovoronoi_thrust PROPERTIES EXPORT_NAME thrust)
  target_include_directories(geovoronoi_thrust INTERFACE
    $<BUILD_INTERFACE:${CMAKE_CURRENT_LIST_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_include_directories(geovoronoi_thrust SYSTEM INTERFACE ${GEOVORONOI_THRUST_INCLUDE_DIR})
  target_link_libraries(geovoronoi_thrust INTERFACE geovoronoi::geovoronoi)
  # device lambdas are not used; constexpr std:: helpers (numeric_limits) are called from device code
  target_compile_options(geovoronoi_thrust INTERFACE $<$<COMPILE_LANGUAGE:CUDA>:--expt-relaxed-constexpr>)

  add_library(geovoronoi_thrust_cpp INTERFACE)
  add_library(geovoronoi::thrust_cpp ALIAS geovoronoi_thrust_cpp)
  target_link_libraries(geovoronoi_thrust_cpp INTERFACE geovoronoi_thrust)
  target_compile_definitions(geovoronoi_thrust_cpp INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CPP)

  find_package(OpenMP QUIET COMPONENTS CXX)
  if(OpenMP_CXX_FOUND)
    add_library(geovoronoi_thrust_omp INTERFACE)
    add_library(geovoronoi::thrust_omp ALIAS geovoronoi_thrust_omp)
    target_link_libraries(geovoronoi_thrust_omp INTERFACE geovoronoi_thrust OpenMP::OpenMP_CXX)
    target_compile_definitions(geovoronoi_thrust_omp INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP)
  endif()

  find_package(TBB QUIET CONFIG)
  if(TBB_FOUND)
    add_library(geovoronoi_thrust_tbb INTERFACE)
    add_library(geovoronoi::thrust_tbb ALIAS geovoronoi_thrust_tbb)
    target_link_libraries(geovoronoi_thrust_tbb INTERFACE geovoronoi_thrust TBB::tbb)
    target_compile_definitions(geovoronoi_thrust_tbb INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_TBB)
  endif()

  # The CUDA system: only with nvcc, and only when both GEOVORONOI_CUDA and GEOVORONOI_THRUST allow it.
  string(TOUPPER "${GEOVORONOI_CUDA}" _gv_cuda_mode)
  if(NOT _gv_cuda_mode STREQUAL "OFF")
    if(NOT CMAKE_CUDA_COMPILER)
      include(CheckLanguage)
      check_language(CUDA)
    endif()
    if(CMAKE_CUDA_COMPILER)
      if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
        set(CMAKE_CUDA_ARCHITECTURES ${GEOVORONOI_CUDA_ARCHITECTURES})
      endif()
      if(NOT DEFINED CMAKE_CUDA_STANDARD)
        set(CMAKE_CUDA_STANDARD 17)
        set(CMAKE_CUDA_STANDARD_REQUIRED ON)
      endif()
      enable_language(CUDA)
    endif()
  endif()
  get_property(_gv_langs GLOBAL PROPERTY ENABLED_LANGUAGES)
  if("CUDA" IN_LIST _gv_langs)
    add_library(geovoronoi_thrust_cuda INTERFACE)
    add_library(geovoronoi::thrust_cuda ALIAS geovoronoi_thrust_cuda)
    target_link_libraries(geovoronoi_thrust_cuda INTERFACE geovoronoi_thrust)
    target_compile_definitions(geovoronoi_thrust_cuda INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CUDA)
  endif()

  # Install: the headers, geovoronoi::thrust in its own export set, and a script that the package
  # config includes (geovoronoi-backends.cmake) re-creating the per-system targets on the consumer's
  # side from what it finds there.
  install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(TARGETS geovoronoi_thrust EXPORT geovoronoi-thrust-targets)
  install(EXPORT geovoronoi-thrust-targets NAMESPACE geovoronoi::
          DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geovoronoi)
  file(WRITE ${PROJECT_BINARY_DIR}/geovoronoi-backends.cmake [=[
# geovoronoi's optional backends, included by geovoronoi-config.cmake.
if(NOT TARGET geovoronoi::thrust)
  include("${CMAKE_CURRENT_LIST_DIR}/geovoronoi-thrust-targets.cmake")
  if(NOT TARGET geovoronoi::thrust_cpp)
    add_library(geovoronoi::thrust_cpp INTERFACE IMPORTED)
    set_target_properties(geovoronoi::thrust_cpp PROPERTIES INTERFACE_LINK_LIBRARIES geovoronoi::thrust
      INTERFACE_COMPILE_DEFINITIONS THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CPP)
  endif()
  find_package(OpenMP QUIET COMPONENTS CXX)
  if(OpenMP_CXX_FOUND AND NOT TARGET geovoronoi::thrust_omp)
    add_library(geovoronoi::thrust_omp INTERFACE IMPORTED)
    set_target_properties(geovoronoi::thrust_omp PROPERTIES
      INTERFACE_LINK_LIBRARIES "geovoronoi::thrust;OpenMP::OpenMP_CXX"
      INTERFACE_COMPILE_DEFINITIONS THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP)
  endif()
  find_package(TBB QUIET CONFIG)
  if(TBB_FOUND AND NOT TARGET geovoronoi::thrust_tbb)
    add_library(geovoronoi::thrust_tbb INTERFACE IMPORTED)
    set_target_properties(geovoronoi::thrust_tbb PROPERTIES
      INTERFACE_LINK_LIBRARIES "geovoronoi::thrust;TBB::tbb"
      INTERFACE_COMPILE_DEFINITIONS THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_TBB)
  endif()
  get_property(_gv_langs GLOBAL PROPERTY ENABLED_LANGUAGES)
  if("CUDA" IN_LIST _gv_langs AND NOT TARGET geovoronoi::thrust_cuda)
    add_library(geovoronoi::thrust_cuda INTERFACE IMPORTED)
    set_target_properties(geovoronoi::thrust_cuda PROPERTIES INTERFACE_LINK_LIBRARIES geovoronoi::thrust
      INTERFACE_COMPILE_DEFINITIONS THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CUDA)
  endif()
endif()
]=])
  install(FILES ${PROJECT_BINARY_DIR}/geovoronoi-backends.cmake DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geovoronoi)
endif()

# CUDA kernel backend: INTERFACE target geovoronoi::cuda (headers under backends/cuda/include).
#   GEOVORONOI_CUDA = AUTO (use nvcc if found), ON (fail without nvcc), OFF.
# Sets GEOVORONOI_HAVE_CUDA. Safe to include after another part of the build (the Thrust backend)
# has already enabled the CUDA language: the language is enabled once, architectures are kept.
set(GEOVORONOI_HAVE_CUDA OFF)
string(TOUPPER "${GEOVORONOI_CUDA}" _gv_cuda_mode)
if(NOT _gv_cuda_mode STREQUAL "OFF")
  get_property(_gv_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  if(NOT "CUDA" IN_LIST _gv_languages)
    if(NOT DEFINED CMAKE_CUDA_COMPILER AND NOT DEFINED ENV{CUDACXX})
      # nvcc is often not on PATH; look where the toolkit installs it
      find_program(GEOVORONOI_NVCC nvcc HINTS ENV CUDA_PATH PATH_SUFFIXES bin PATHS /usr/local/cuda/bin)
      if(GEOVORONOI_NVCC)
        set(CMAKE_CUDA_COMPILER "${GEOVORONOI_NVCC}" CACHE FILEPATH "CUDA compiler")
      endif()
    endif()
    include(CheckLanguage)
    check_language(CUDA)
    if(CMAKE_CUDA_COMPILER)
      if(NOT DEFINED CMAKE_CUDA_ARCHITECTURES)
        set(CMAKE_CUDA_ARCHITECTURES "${GEOVORONOI_CUDA_ARCHITECTURES}")
      endif()
      if(PROJECT_IS_TOP_LEVEL AND NOT DEFINED CMAKE_CUDA_STANDARD)
        set(CMAKE_CUDA_STANDARD 17)
        set(CMAKE_CUDA_STANDARD_REQUIRED ON)
        set(CMAKE_CUDA_EXTENSIONS OFF)
      endif()
      enable_language(CUDA)
    endif()
  endif()
  get_property(_gv_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
  if("CUDA" IN_LIST _gv_languages)
    find_package(CUDAToolkit)
  endif()
  if("CUDA" IN_LIST _gv_languages AND CUDAToolkit_FOUND)
    add_library(geovoronoi_cuda INTERFACE)
    add_library(geovoronoi::cuda ALIAS geovoronoi_cuda)
    set_target_properties(geovoronoi_cuda PROPERTIES EXPORT_NAME cuda)
    target_include_directories(geovoronoi_cuda INTERFACE
      $<BUILD_INTERFACE:${CMAKE_CURRENT_LIST_DIR}/include>
      $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_libraries(geovoronoi_cuda INTERFACE geovoronoi CUDA::cudart_static)
    # --fmad=false: the determinism contract (no fused multiply-add in the relaxation);
    # --expt-relaxed-constexpr: the core's host-device policies use std::array's constexpr accessors.
    target_compile_options(geovoronoi_cuda INTERFACE
      $<$<COMPILE_LANGUAGE:CUDA>:--fmad=false;--expt-relaxed-constexpr>)
    target_compile_features(geovoronoi_cuda INTERFACE cuda_std_17)
    set(GEOVORONOI_HAVE_CUDA ON)

    install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
    install(TARGETS geovoronoi_cuda EXPORT geovoronoi-cuda-targets)
    # In the package: loaded when the consumer's project has enabled CUDA and finds the toolkit.
    geovoronoi_package_backend(geovoronoi-cuda-targets
      "get_property(_gv_langs GLOBAL PROPERTY ENABLED_LANGUAGES)"
      "if(\"CUDA\" IN_LIST _gv_langs)"
      "  find_package(CUDAToolkit QUIET)"
      "endif()"
      "if(NOT \"CUDA\" IN_LIST _gv_langs OR NOT TARGET CUDA::cudart_static)"
      "  set(_gv_ok FALSE)"
      "endif()")
  elseif(_gv_cuda_mode STREQUAL "ON")
    message(FATAL_ERROR "geovoronoi: GEOVORONOI_CUDA=ON but no working CUDA compiler (nvcc) or CUDA toolkit was "
                        "found; install the CUDA toolkit, set CMAKE_CUDA_COMPILER, or use GEOVORONOI_CUDA=AUTO|OFF")
  else()
    message(STATUS "geovoronoi: no CUDA compiler found; the CUDA backend is disabled")
  endif()
endif()

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
  include(${PROJECT_SOURCE_DIR}/cmake/GeovoronoiFindThrust.cmake)
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
  # Thrust's own headers: this machine's path in the build tree; in the installed package the target
  # geovoronoi::thrust_headers, which geovoronoi-backends.cmake creates from what it finds there.
  target_include_directories(geovoronoi_thrust SYSTEM INTERFACE $<BUILD_INTERFACE:${GEOVORONOI_THRUST_INCLUDE_DIR}>)
  target_link_libraries(geovoronoi_thrust INTERFACE geovoronoi $<INSTALL_INTERFACE:geovoronoi::thrust_headers>)
  # device lambdas are not used; constexpr std:: helpers (numeric_limits) are called from device code
  target_compile_options(geovoronoi_thrust INTERFACE $<$<COMPILE_LANGUAGE:CUDA>:--expt-relaxed-constexpr>)

  add_library(geovoronoi_thrust_cpp INTERFACE)
  add_library(geovoronoi::thrust_cpp ALIAS geovoronoi_thrust_cpp)
  set_target_properties(geovoronoi_thrust_cpp PROPERTIES EXPORT_NAME thrust_cpp)
  target_link_libraries(geovoronoi_thrust_cpp INTERFACE geovoronoi_thrust)
  target_compile_definitions(geovoronoi_thrust_cpp INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CPP)

  find_package(OpenMP QUIET COMPONENTS CXX)
  if(OpenMP_CXX_FOUND)
    add_library(geovoronoi_thrust_omp INTERFACE)
    add_library(geovoronoi::thrust_omp ALIAS geovoronoi_thrust_omp)
    set_target_properties(geovoronoi_thrust_omp PROPERTIES EXPORT_NAME thrust_omp)
    target_link_libraries(geovoronoi_thrust_omp INTERFACE geovoronoi_thrust OpenMP::OpenMP_CXX)
    target_compile_definitions(geovoronoi_thrust_omp INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_OMP)
  endif()

  find_package(TBB QUIET CONFIG)
  if(TBB_FOUND)
    add_library(geovoronoi_thrust_tbb INTERFACE)
    add_library(geovoronoi::thrust_tbb ALIAS geovoronoi_thrust_tbb)
    set_target_properties(geovoronoi_thrust_tbb PROPERTIES EXPORT_NAME thrust_tbb)
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
    set_target_properties(geovoronoi_thrust_cuda PROPERTIES EXPORT_NAME thrust_cuda)
    target_link_libraries(geovoronoi_thrust_cuda INTERFACE geovoronoi_thrust)
    target_compile_definitions(geovoronoi_thrust_cuda INTERFACE THRUST_DEVICE_SYSTEM=THRUST_DEVICE_SYSTEM_CUDA)
  endif()

  # Install: the headers, and one export set per group of targets with the same dependencies; the
  # package loads each set only when the consumer's machine has those dependencies.
  install(DIRECTORY ${CMAKE_CURRENT_LIST_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(TARGETS geovoronoi_thrust geovoronoi_thrust_cpp EXPORT geovoronoi-thrust-targets)
  geovoronoi_package_backend(geovoronoi-thrust-targets
    "include(\"\${CMAKE_CURRENT_LIST_DIR}/GeovoronoiFindThrust.cmake\")"
    "if(GEOVORONOI_THRUST_INCLUDE_DIR AND NOT TARGET geovoronoi::thrust_headers)"
    "  add_library(geovoronoi::thrust_headers INTERFACE IMPORTED)"
    "  set_target_properties(geovoronoi::thrust_headers PROPERTIES INTERFACE_INCLUDE_DIRECTORIES \"\${GEOVORONOI_THRUST_INCLUDE_DIR}\")"
    "endif()"
    "if(NOT TARGET geovoronoi::thrust_headers)"
    "  set(_gv_ok FALSE)"
    "endif()")
  if(TARGET geovoronoi_thrust_omp)
    install(TARGETS geovoronoi_thrust_omp EXPORT geovoronoi-thrust_omp-targets)
    geovoronoi_package_backend(geovoronoi-thrust_omp-targets
      "if(TARGET geovoronoi::thrust)"
      "  find_package(OpenMP QUIET COMPONENTS CXX)"
      "endif()"
      "if(NOT TARGET geovoronoi::thrust OR NOT TARGET OpenMP::OpenMP_CXX)"
      "  set(_gv_ok FALSE)"
      "endif()")
  endif()
  if(TARGET geovoronoi_thrust_tbb)
    install(TARGETS geovoronoi_thrust_tbb EXPORT geovoronoi-thrust_tbb-targets)
    geovoronoi_package_backend(geovoronoi-thrust_tbb-targets
      "if(TARGET geovoronoi::thrust)"
      "  find_package(TBB QUIET CONFIG)"
      "endif()"
      "if(NOT TARGET geovoronoi::thrust OR NOT TARGET TBB::tbb)"
      "  set(_gv_ok FALSE)"
      "endif()")
  endif()
  if(TARGET geovoronoi_thrust_cuda)
    install(TARGETS geovoronoi_thrust_cuda EXPORT geovoronoi-thrust_cuda-targets)
    geovoronoi_package_backend(geovoronoi-thrust_cuda-targets
      "get_property(_gv_langs GLOBAL PROPERTY ENABLED_LANGUAGES)"
      "if(NOT TARGET geovoronoi::thrust OR NOT \"CUDA\" IN_LIST _gv_langs)"
      "  set(_gv_ok FALSE)"
      "endif()")
  endif()
endif()

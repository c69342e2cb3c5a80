# `cmake --install` puts the geovoronoi tool in <prefix>/bin and it runs from there (cmake -P):
#   -DBUILD_DIR=<build tree> -DPREFIX=<scratch prefix>
cmake_minimum_required(VERSION 3.20)
file(REMOVE_RECURSE ${PREFIX})
execute_process(COMMAND ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${PREFIX}
                RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc}):\n${out}")
endif()
if(NOT EXISTS ${PREFIX}/bin/geovoronoi)
  message(FATAL_ERROR "cmake --install did not install bin/geovoronoi:\n${out}")
endif()
execute_process(COMMAND ${PREFIX}/bin/geovoronoi --version RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
if(NOT rc EQUAL 0 OR NOT out MATCHES "^geovoronoi [0-9]+\\.[0-9]+\\.[0-9]+")
  message(FATAL_ERROR "installed geovoronoi --version: exit ${rc}, output '${out}'")
endif()
message(STATUS "installed ${PREFIX}/bin/geovoronoi: ${out}")

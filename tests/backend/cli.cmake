# Hook of the I/O and command-line work (included by tests/backend/backends.cmake): links libpng
# into the I/O tests, adds the command-line end-to-end tests, and the fuzz targets when the compiler
# is clang (see scripts/test.sh, which builds them in build-fuzz/). zlib (compressed MetaImage data)
# comes with geovoronoi::geovoronoi itself when the top-level CMakeLists.txt found it.
find_package(PNG)
if(TARGET test_io_png)
  if(PNG_FOUND)
    target_link_libraries(test_io_png PRIVATE PNG::PNG)
  else()
    target_compile_definitions(test_io_png PRIVATE GEOVORONOI_NO_PNG=1)
  endif()
endif()

if(GEOVORONOI_BUILD_TOOLS AND EXISTS ${PROJECT_SOURCE_DIR}/examples/CMakeLists.txt)
  add_test(NAME cli_end_to_end
    COMMAND ${CMAKE_COMMAND} -DGEOVORONOI=$<TARGET_FILE:geovoronoi_tool> -DWORK=${CMAKE_CURRENT_BINARY_DIR}/cli-work
            # the backends compiled into the tool, as examples/CMakeLists.txt decides (evaluated at
            # generation time, when the examples' targets exist)
            "-DBUILT=seq$<$<TARGET_EXISTS:geovoronoi_thrust_omp>:,thrust>$<$<TARGET_EXISTS:geovoronoi_tool_cuda>:,cuda>"
            -P ${CMAKE_CURRENT_LIST_DIR}/../cli/run_cli.cmake)
  set_tests_properties(cli_end_to_end PROPERTIES LABELS cli)
endif()

# libFuzzer targets: only with clang and -DGEOVORONOI_FUZZ=ON (scripts/test.sh builds them apart).
option(GEOVORONOI_FUZZ "Build the libFuzzer targets (clang only)" OFF)
if(GEOVORONOI_FUZZ AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  foreach(f metaimage npy pnm)
    add_executable(fuzz_${f} ${CMAKE_CURRENT_LIST_DIR}/../fuzz/fuzz_${f}.cpp)
    target_link_libraries(fuzz_${f} PRIVATE geovoronoi::geovoronoi)
    target_compile_options(fuzz_${f} PRIVATE -fsanitize=fuzzer,address,undefined -g -O1)
    target_link_options(fuzz_${f} PRIVATE -fsanitize=fuzzer,address,undefined)
  endforeach()
endif()

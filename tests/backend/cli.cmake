# Hook of the I/O work (included by tests/backend/backends.cmake): the fuzz targets when the compiler
# is clang (see scripts/test.sh, which builds them in build-fuzz/). zlib (compressed MetaImage data)
# and libpng (io::write_png) come with geovoronoi::geovoronoi itself when the top-level CMakeLists.txt
# found them.
# libFuzzer targets: only with clang and -DGEOVORONOI_FUZZ=ON (scripts/test.sh builds them apart).
option(GEOVORONOI_FUZZ "Build the libFuzzer targets (clang only)" OFF)
if(GEOVORONOI_FUZZ AND CMAKE_CXX_COMPILER_ID MATCHES "Clang")
  foreach(f metaimage npy pnm mesh points)
    add_executable(fuzz_${f} ${CMAKE_CURRENT_LIST_DIR}/../fuzz/fuzz_${f}.cpp)
    target_link_libraries(fuzz_${f} PRIVATE geovoronoi::geovoronoi)
    target_compile_options(fuzz_${f} PRIVATE -fsanitize=fuzzer,address,undefined -g -O1)
    target_link_options(fuzz_${f} PRIVATE -fsanitize=fuzzer,address,undefined)
  endforeach()
  # the tool's seed and points reader (a header of the front end)
  target_include_directories(fuzz_points PRIVATE ${PROJECT_SOURCE_DIR}/tools/geovoronoi)
endif()

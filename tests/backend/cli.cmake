# Hook of the I/O work (included by tests/backend/backends.cmake): links libpng into the I/O tests,
# and adds the fuzz targets when the compiler
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

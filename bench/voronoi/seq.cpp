/// @file bench/voronoi/seq.cpp
/// @brief The sequential backend (geovoronoi::seq) over the full voronoi case matrix:
///        n = 64, 128, 256; 10, 100, 1000 seeds; 6- and 26-connectivity; constant, gradient, steak;
///        plus the MRI-like pelvis (`voronoi/seq/mri/221/20/26`: 221x271x69, 0.9x0.9x2.5, 20 seeds).

#include "common.hpp"

GEOVORONOI_BENCH_REGISTER(register_seq_cases) {
  geovoronoi::bench::register_voronoi_cases("seq", geovoronoi::seq, {64, 128, 256}, {10, 100, 1000}, {6, 26},
                                            geovoronoi::bench::field_names());
  geovoronoi::bench::register_voronoi_cases("seq", geovoronoi::seq, {221}, {20}, {26}, {"mri"});
}

#ifndef GEOVORONOI_BENCH_COMBINED
GEOVORONOI_BENCH_MAIN()
#endif

/// @file bench/voronoi/cpu.cpp
/// @brief main() of bench_voronoi_cpu, which links seq.cpp and sofa_set.cpp (compiled with
///        GEOVORONOI_BENCH_COMBINED) so both backends run in one process and one report.

#include "common.hpp"

GEOVORONOI_BENCH_MAIN()

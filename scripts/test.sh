#!/usr/bin/env bash
# The README's test command: installs what it needs from Debian's packages if missing, builds
# everything (every backend this machine supports, the tool, benchmarks, examples, header checks)
# with g++ at -O1 and -Werror and runs ctest (unit tests, CLI tests, consumer projects, and every
# benchmark once as a smoke test), builds the Python package (g++ -O3, -Werror) and runs its pytest
# suite, then builds and runs the tests again with clang under AddressSanitizer +
# UndefinedBehaviorSanitizer, then fuzzes the parsers. Any failure fails it. Prints each stage's time.
#
# To stay fast on a 2-core machine:
# - the test build is g++ -O1 (folder build-test/, so an optimised build/ for benchmarks is never
#   replaced): on the largest test unit, tests/backend/thrust_cpp.cpp, g++ takes 92 s CPU at -O3 and
#   44 s at -O1; clang -O1 50 s, clang -O1 -g1 with ASan + UBSan 112 s, g++ -O1 -g1 with both 166 s
#   (2-core AMD EPYC development VM, 2026-12-01, same load for all five). The optimised code is still
#   tested: the Python extension is compiled at -O3 (every solver, shape function and reader it binds,
#   for each metric, connectivity, precision and host backend), and its pytest suite checks it against
#   SciPy, scikit-image and, byte for byte, the C++ tool of the test build;
# - each nvcc translation unit is compiled once, for ONE architecture (GEOVORONOI_CUDA_ARCHITECTURES):
#   on a machine with a GPU "80" (sm_80 code plus PTX that newer GPUs compile at load time); without
#   one "80-virtual", PTX only (nvcc's front end and NVVM still run, only ptxas is skipped), and then
#   the nvcc-compiled backend suites, which can only prove that they compile, instantiate the suite's
#   reduced type/connectivity matrix (GEOVORONOI_TEST_CUDA_REDUCED_MATRIX);
# - the Thrust CPP and TBB suites run a reduced type/metric matrix (the code they share with the
#   OpenMP suite is that suite's full matrix; what differs is the Thrust system);
# - the benchmarks run one short iteration per case at most 32 voxels per side (ctest label
#   `bench`), not timed runs;
# - the sanitizer build has only the tests that run: no benchmarks, no CUDA units, no tool, no
#   examples, no compile-only header checks (all of those were built and run in the first stage), no
#   Thrust CPP/TBB suites, and the Thrust OpenMP suite on the reduced matrix (the full one ran in the
#   first stage; what the sanitizers look for is in the code paths, which the reduced matrix runs);
#   it is compiled by clang at -O1 with line tables only (-g1), what AddressSanitizer recommends.

set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/packages.sh
ensure_packages cmake g++ make libeigen3-dev doctest-dev libbenchmark-dev libpng-dev zlib1g-dev libtbb-dev libomp-dev clang

jobs=$(nproc)
gpu=0
if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L 2>/dev/null | grep -q GPU; then
  gpu=1
  cuda_arch="${GEOVORONOI_CUDA_ARCHITECTURES:-80}"
else
  cuda_arch="${GEOVORONOI_CUDA_ARCHITECTURES:-80-virtual}"
fi
start=$SECONDS
stage_start=$SECONDS
times=()
stage_done() {
  local t=$((SECONDS - stage_start))
  times+=("$(printf '%-28s %5d s' "$1" "$t")")
  echo "== $1: ${t} s"
  stage_start=$SECONDS
}

reduced_cuda=OFF
[ "$gpu" = 0 ] && reduced_cuda=ON
echo "== test build (g++ -O1, -Werror, CUDA architecture ${cuda_arch})"
cmake -S . -B build-test -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
      -DCMAKE_CUDA_FLAGS_RELEASE="-O1 -DNDEBUG" -DGEOVORONOI_WERROR=ON \
      -DGEOVORONOI_CUDA_ARCHITECTURES="$cuda_arch" -DGEOVORONOI_TEST_CUDA_REDUCED_MATRIX="$reduced_cuda" >/dev/null
cmake --build build-test -j"$jobs"
stage_done "test build"
ctest --test-dir build-test --output-on-failure -j"$jobs"
stage_done "ctest"

echo "== Python package (pip install . into build-python/venv, pytest)"
GEOVORONOI_CLI="$PWD/build-test/bin/geovoronoi" scripts/test-python.sh
stage_done "python package"

echo "== ASan + UBSan build (tests only, $(basename "$(command -v clang++ || command -v g++)"))"
# clang when present (test.sh installs it): its ASan + UBSan build of the tests costs about 0.6 of
# GCC's at the same -O1 -g1 (GCC's UBSan instrumentation is the difference). Warnings were made
# errors in the release stage, on the same sources; this stage is for what runs.
san_cxx=$(command -v clang++ || command -v g++)
cmake -S . -B build-sanitize -DCMAKE_CXX_COMPILER="$san_cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
      -DGEOVORONOI_SANITIZE=ON -DGEOVORONOI_WERROR=OFF \
      -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF \
      -DGEOVORONOI_HEADER_CHECKS=OFF -DGEOVORONOI_CUDA=OFF -DGEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS=OFF \
      -DGEOVORONOI_TEST_REDUCED_MATRIX=ON >/dev/null
cmake --build build-sanitize -j"$jobs"
stage_done "sanitizer build"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-sanitize --output-on-failure -j"$jobs" -LE "consumer|fuzz"
stage_done "sanitizer ctest"

# ---- fuzzing: libFuzzer on the MetaImage, NumPy, PGM/PPM and STL/OBJ parsers ----
# Built apart with clang in build-fuzz/ (only the fuzz targets), each run for a bounded time on a
# copy of the seed corpus in tests/fuzz/corpus/. A crash, sanitizer report, leak or timeout fails.
if command -v clang++ >/dev/null 2>&1; then
  fuzz_seconds="${GEOVORONOI_FUZZ_SECONDS:-20}"
  echo "== fuzzing (clang, ${fuzz_seconds} s per parser)"
  cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DGEOVORONOI_FUZZ=ON \
        -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF \
        -DGEOVORONOI_THRUST=OFF -DGEOVORONOI_CUDA=OFF >/dev/null
  cmake --build build-fuzz --target fuzz_metaimage fuzz_npy fuzz_pnm fuzz_mesh -j"$jobs"
  stage_done "fuzz build"
  for f in metaimage npy pnm mesh; do
    rm -rf "build-fuzz/corpus-$f" && mkdir -p "build-fuzz/corpus-$f"
    cp tests/fuzz/corpus/"$f"/* "build-fuzz/corpus-$f"/
    if ! (cd build-fuzz && ./tests/fuzz_"$f" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2048 \
          -max_len=4096 -print_final_stats=1 "corpus-$f" > "fuzz-$f.log" 2>&1); then
      tail -n 40 "build-fuzz/fuzz-$f.log"
      echo "fuzz_$f found a problem (see build-fuzz/fuzz-$f.log and build-fuzz/crash-*)"
      exit 1
    fi
    grep -E "^stat::number_of_executed_units|Done" "build-fuzz/fuzz-$f.log" | head -n 2
  done
  stage_done "fuzz runs"
else
  echo "== fuzzing skipped (no clang++)"
fi
echo "== stage times"
printf '   %s\n' "${times[@]}"
echo "== all tests passed in $((SECONDS - start)) s (load average now:$(uptime | sed 's/.*load average://'))"

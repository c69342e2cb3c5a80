#!/usr/bin/env bash
# The README's test command: installs what it needs from Debian's packages if missing, builds and
# runs every test, and fails at the first failure. Prints each stage's time. docs/testing.md says what
# each stage covers and what it costs. Two builds, each source compiled once:
# - the host suites (every tests/*.test.cpp, the sequential, sparse and Thrust OpenMP backend, shape
#   and update suites, the compile-fail tests) are built once, with clang at -O0 -g1 under
#   AddressSanitizer + UndefinedBehaviorSanitizer and -Werror (build-sanitize/), and run there; this
#   stage runs in the background from the start (scripts/lib/sanitizer-stage.sh, log
#   build-sanitize/stage.log);
# - everything else is built with g++ at -O1 and -Werror (build-test/): the CLI tool and its
#   end-to-end tests, the Python extension (GEOVORONOI_BUILD_PYTHON: it links the front-end objects
#   the tool links, compiled once), the benchmarks (run once each as a smoke test: ctest label
#   `bench`), the examples, the compile-only header checks, the consumer projects, the suites the
#   sanitizer build does not have (the full Thrust OpenMP backend matrix, the Thrust CPP and TBB
#   suites, the nvcc units);
# - the Python package (scripts/test-python.sh): `pip install .` re-configures build-test/ with its
#   own options and installs the extension compiled there (nothing is compiled again; a user's
#   `pip install .` builds at -O3 in its own folder), then its pytest suite, which checks it against
#   SciPy, scikit-image and, byte for byte, the C++ tool of the g++ build;
# - the parsers fuzzed (libFuzzer, clang, ASan + UBSan).
#
# To stay fast on a 2-core machine (figures: docs/testing.md):
# - Ninja (Debian's ninja-build) instead of make when it is there;
# - each nvcc translation unit is compiled once, for ONE architecture (GEOVORONOI_CUDA_ARCHITECTURES):
#   on a machine with a GPU "80" (sm_80 code plus PTX that newer GPUs compile at load time); without
#   one "80-virtual", PTX only (nvcc's front end and NVVM still run, only ptxas is skipped). Without a
#   GPU no device code can run, so the nvcc units only prove that they compile: they instantiate the
#   suites' reduced type/connectivity matrix (GEOVORONOI_TEST_CUDA_REDUCED_MATRIX), and NVVM runs
#   with nvcc's fastest device-compile setting (-Ofc max, where nvcc has it);
# - the Thrust CPP and TBB suites run a reduced type/metric matrix (the code they share with the
#   OpenMP suite is that suite's full matrix; what differs is the Thrust system); under the sanitizers
#   the Thrust OpenMP suite runs the reduced matrix too (the full one runs in the g++ build);
# - the front end's typed-problem units (every metric, connectivity and host backend, for the tool and
#   the Python extension: half of the g++ build at -O1) are compiled at -O0: there they run only the
#   small problems of the end-to-end tests, and the library code they instantiate is compiled at -O1
#   (with its warnings) by the Thrust suites and the benchmarks;
# - the benchmarks run one short iteration per case at most 32 voxels per side (ctest label
#   `bench`), not timed runs;
# - the sanitizer build is clang at -O0 with line tables (-g1): a quarter of the compile time of -O1
#   (which loses no finding: ASan and UBSan check every access and operation the code performs at
#   any level); the tests run about four times slower, far less than the compile time saved;
# - the sanitizer stage runs alongside the g++ build, its ctest and the Python stage (each of which
#   leaves a core idle some of the time), and the five fuzzers run side by side, one per core.

set -euo pipefail
cd "$(dirname "$0")/.."

source scripts/lib/packages.sh
source scripts/lib/python-venv.sh
ensure_packages cmake g++ make ninja-build libeigen3-dev doctest-dev libbenchmark-dev libpng-dev zlib1g-dev \
                libtbb-dev libomp-dev clang python3-dev python3-pip python3-venv python3-numpy python3-scipy \
                python3-skimage python3-pytest

jobs=$(nproc)
gpu=0
if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L 2>/dev/null | grep GPU >/dev/null; then
  gpu=1
  cuda_arch="${GEOVORONOI_CUDA_ARCHITECTURES:-80}"
else
  cuda_arch="${GEOVORONOI_CUDA_ARCHITECTURES:-80-virtual}"
fi
generator="Unix Makefiles"
if command -v ninja >/dev/null 2>&1; then
  generator=Ninja
fi
start=$SECONDS
stage_start=$SECONDS
times=()
# CPU seconds (user + system) of the finished child processes so far: with the machine shared, the
# CPU time of a stage says more than its wall time
# (bash's `times`, run in this shell, not in a subshell, whose children would be none; a background
# job counts once bash has reaped it, which it does as soon as the job ends: the sanitizer stage's
# CPU time is counted in the stage during which it ended)
cpu_file=$(mktemp)
child_cpu() {
  times > "$cpu_file"
  cpu_now=$(tail -n 1 "$cpu_file" | awk '{ n = 0; for (i = 1; i <= 2; ++i) { split($i, a, /[ms]/); n += a[1] * 60 + a[2] } printf "%d", n }')
}
child_cpu
stage_cpu=$cpu_now
stage_done() {
  local t=$((SECONDS - stage_start))
  child_cpu
  times+=("$(printf '%-44s %5d s   CPU %5d s' "$1" "$t" "$((cpu_now - stage_cpu))")")
  echo "== $1: ${t} s (CPU $((cpu_now - stage_cpu)) s)"
  stage_start=$SECONDS
  stage_cpu=$cpu_now
}
# configure DIR ARGS...: a folder configured before with another generator is started afresh
configure() {
  local dir=$1
  shift
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -qx "CMAKE_GENERATOR:INTERNAL=$generator" "$dir/CMakeCache.txt"; then
    echo "== $dir was configured with another generator: removing it"
    rm -rf "$dir"
  fi
  cmake -S . -B "$dir" -G "$generator" "$@" >/dev/null
}
# the background sanitizer build, if still running when this script stops, stops with it
san_pid=""
trap '[ -n "$san_pid" ] && kill -- -"$san_pid" 2>/dev/null; rm -f "$cpu_file"; true' EXIT

reduced_cuda=OFF
cuda_flags="-O1 -DNDEBUG"
if [ "$gpu" = 0 ]; then
  # Nothing compiled by nvcc can run its kernels here: the host side at -O0 and, where nvcc has
  # it (12.8 and later), its fastest device compile (-Ofc=max), about half the CPU time per unit
  reduced_cuda=ON
  cuda_flags="-O0 -DNDEBUG"
  nvcc_bin=$(command -v nvcc || echo /usr/local/cuda/bin/nvcc)
  # (grep reads the whole help: with -q it would stop at the match, nvcc would die of SIGPIPE and,
  # under pipefail, the test would fail at random)
  if [ -x "$nvcc_bin" ] && "$nvcc_bin" --help 2>/dev/null | grep -- "--Ofast-compile" >/dev/null; then
    cuda_flags="$cuda_flags -Ofc=max"
  fi
fi
# ---- ASan + UBSan: the host suites, built and run in the background from the start ----
# clang when present (test.sh installs it): its ASan + UBSan build of the tests costs about 0.6 of
# GCC's at the same -O1 -g1 (GCC's UBSan instrumentation is the difference); -O0 instead of -O1 cuts
# its compile time to between a quarter and a half (docs/testing.md).
san_cxx=$(command -v clang++ || command -v g++)
echo "== ASan + UBSan stage (the host suites, $(basename "$san_cxx") -O0 -g1, -Werror) started in the background"
configure build-sanitize -DCMAKE_CXX_COMPILER="$san_cxx" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
      -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O0 -g1 -DNDEBUG" \
      -DGEOVORONOI_SANITIZE=ON -DGEOVORONOI_WERROR=ON \
      -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF \
      -DGEOVORONOI_HEADER_CHECKS=OFF -DGEOVORONOI_CUDA=OFF -DGEOVORONOI_TEST_EXTRA_THRUST_SYSTEMS=OFF \
      -DGEOVORONOI_TEST_REDUCED_MATRIX=ON -DGEOVORONOI_TEST_HOST_SUITES=ON
san_start=$SECONDS
setsid scripts/lib/sanitizer-stage.sh "$jobs" > build-sanitize/stage.log 2>&1 &
san_pid=$!

echo "== g++ build (g++ -O1, -Werror, CUDA architecture ${cuda_arch}, nvcc ${cuda_flags}, ${generator}, the Python extension)"
# the extension is built against the venv's Python and nanobind (the ones pip's build uses later)
python_venv
configure build-test -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O1 -DNDEBUG" \
      -DCMAKE_CUDA_FLAGS_RELEASE="$cuda_flags" -DGEOVORONOI_WERROR=ON \
      -DGEOVORONOI_CUDA_ARCHITECTURES="$cuda_arch" -DGEOVORONOI_TEST_CUDA_REDUCED_MATRIX="$reduced_cuda" \
      -DGEOVORONOI_TEST_HOST_SUITES=OFF -DGEOVORONOI_BUILD_PYTHON=ON -DPython_EXECUTABLE="$venv_python" \
      -DGEOVORONOI_FRONTEND_INSTANCE_OPTIONS=-O0
cmake --build build-test -j"$jobs"
stage_done "g++ build (sanitizer stage alongside)"

ctest --test-dir build-test --output-on-failure -j"$jobs"
stage_done "g++ ctest (sanitizer stage alongside)"

echo "== Python package (pip install . into build-python/venv from build-test's objects, pytest)"
GEOVORONOI_PYTHON_BUILD_DIR=build-test scripts/test-python.sh
stage_done "python package (sanitizer stage alongside)"

echo "== waiting for the ASan + UBSan stage"
san_rc=0
wait "$san_pid" || san_rc=$?
san_pid=""
grep -E "^== |tests passed|tests failed" build-sanitize/stage.log || true
if [ "$san_rc" -ne 0 ]; then
  tail -n 80 build-sanitize/stage.log
  echo "the ASan + UBSan stage failed (build-sanitize/stage.log)"
  exit 1
fi
stage_done "sanitizer stage, rest"
echo "   (the ASan + UBSan stage took $((SECONDS - san_start)) s from its start, alongside the stages above)"

# ---- fuzzing: libFuzzer on the MetaImage, NumPy, PGM/PPM and STL/OBJ parsers and the tool's seed/points reader ----
# Built apart with clang in build-fuzz/ (only the fuzz targets), each run for a bounded time on a
# copy of the seed corpus in tests/fuzz/corpus/, as many at once as there are cores (each fuzzer is
# one process on one core, so running them side by side does not shorten any run). A crash,
# sanitizer report, leak or timeout fails.
if command -v clang++ >/dev/null 2>&1; then
  fuzz_seconds="${GEOVORONOI_FUZZ_SECONDS:-20}"
  echo "== fuzzing (clang, ${fuzz_seconds} s per parser, ${jobs} at a time)"
  configure build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DGEOVORONOI_FUZZ=ON \
        -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF \
        -DGEOVORONOI_THRUST=OFF -DGEOVORONOI_CUDA=OFF
  cmake --build build-fuzz --target fuzz_metaimage fuzz_npy fuzz_pnm fuzz_mesh fuzz_points -j"$jobs"
  stage_done "fuzz build"
  fuzz_one() {
    local f=$1
    rm -rf "build-fuzz/corpus-$f" && mkdir -p "build-fuzz/corpus-$f"
    cp tests/fuzz/corpus/"$f"/* "build-fuzz/corpus-$f"/
    (cd build-fuzz && ./tests/fuzz_"$f" -max_total_time="$fuzz_seconds" -timeout=10 -rss_limit_mb=2048 \
       -max_len=4096 -print_final_stats=1 "corpus-$f" > "fuzz-$f.log" 2>&1)
  }
  fuzzers=(metaimage npy pnm mesh points)
  failed=()
  for ((i = 0; i < ${#fuzzers[@]}; i += jobs)); do
    pids=()
    for f in "${fuzzers[@]:i:jobs}"; do
      fuzz_one "$f" &
      pids+=("$!:$f")
    done
    for p in "${pids[@]}"; do
      wait "${p%%:*}" || failed+=("${p#*:}")
    done
  done
  for f in "${fuzzers[@]}"; do
    grep -E "^stat::number_of_executed_units|Done" "build-fuzz/fuzz-$f.log" | head -n 2 | sed "s/^/$f: /"
  done
  if ((${#failed[@]})); then
    for f in "${failed[@]}"; do
      tail -n 40 "build-fuzz/fuzz-$f.log"
      echo "fuzz_$f found a problem (see build-fuzz/fuzz-$f.log and build-fuzz/crash-*)"
    done
    exit 1
  fi
  stage_done "fuzz runs"
else
  echo "== fuzzing skipped (no clang++)"
fi
echo "== stage times"
printf '   %s\n' "${times[@]}"
child_cpu
echo "== all tests passed in $((SECONDS - start)) s, CPU ${cpu_now} s (load average now:$(uptime | sed 's/.*load average://'))"

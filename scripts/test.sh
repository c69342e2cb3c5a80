#!/usr/bin/env bash
# The README's test command: installs what it needs from Debian's packages if missing, builds
# everything (every backend this machine supports) with -Werror, runs ctest, then builds and runs the
# tests again under AddressSanitizer + UndefinedBehaviorSanitizer.
set -euo pipefail
cd "$(dirname "$0")/.."

packages=(cmake g++ make libeigen3-dev doctest-dev libbenchmark-dev libpng-dev zlib1g-dev libtbb-dev libomp-dev clang)
missing=()
for p in "${packages[@]}"; do dpkg -s "$p" >/dev/null 2>&1 || missing+=("$p"); done
if ((${#missing[@]})); then
  echo "== installing: ${missing[*]}"
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get update -q
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -q --no-install-recommends "${missing[@]}"
fi

jobs=$(nproc)
start=$SECONDS
echo "== release build (-Werror)"
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release -DGEOVORONOI_WERROR=ON
cmake --build build -j"$jobs"
ctest --test-dir build --output-on-failure -j"$jobs"

echo "== ASan + UBSan build"
cmake -S . -B build-sanitize -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGEOVORONOI_SANITIZE=ON -DGEOVORONOI_WERROR=ON \
      -DGEOVORONOI_BUILD_BENCH=OFF -DGEOVORONOI_CUDA=OFF
cmake --build build-sanitize -j"$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  ctest --test-dir build-sanitize --output-on-failure -j"$jobs" -LE "consumer|fuzz"
echo "== all tests passed in $((SECONDS - start)) s"

#!/usr/bin/env bash
# The README's main job: installs the Debian packages the build needs if missing, builds the
# `geovoronoi` command-line tool (Release), runs `geovoronoi demo` on the built-in T-bone steak
# phantom and says where the pictures and volumes are.
#   scripts/demo.sh [OUT_DIR]      (default: demo-out)
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-demo-out}"

source scripts/lib/packages.sh
ensure_packages cmake g++ make libeigen3-dev libpng-dev zlib1g-dev doctest-dev libbenchmark-dev

echo "== building the geovoronoi tool (build-demo/, Release)"
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DGEOVORONOI_BUILD_TESTS=OFF -DGEOVORONOI_BUILD_BENCH=OFF \
      -DGEOVORONOI_BUILD_TOOLS=ON >/dev/null
cmake --build build-demo --target geovoronoi_tool -j"$(nproc)"

echo "== geovoronoi demo --out $out"
build-demo/bin/geovoronoi demo --out "$out"
echo
echo "Pictures (PNG) and volumes (.mhd/.raw, .vti, .npy) are in $(cd "$out" && pwd):"
ls -1 "$out"/*.png "$out"/*/*.png

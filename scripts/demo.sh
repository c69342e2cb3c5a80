#!/usr/bin/env bash
# The README's main job: installs the Debian packages the build needs if missing, builds the
# `geovoronoi` command-line tool (Release) and only that, lean (GEOVORONOI_TOOL_LEAN: only the
# metrics and connectivity the demo uses are compiled in), runs `geovoronoi demo` on the built-in
# T-bone steak phantom and says where the pictures and volumes are, and how long it all took.
#   scripts/demo.sh [OUT_DIR]      (default: demo-out)
# The CUDA backend (an nvcc translation unit) is built only when a GPU answers (nvidia-smi -L);
# GEOVORONOI_DEMO_CUDA=ON or OFF overrides that.
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-demo-out}"
start=$SECONDS

source scripts/lib/packages.sh
ensure_packages cmake g++ make libeigen3-dev libpng-dev zlib1g-dev

cuda="${GEOVORONOI_DEMO_CUDA:-}"
if [ -z "$cuda" ]; then
  if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L >/dev/null 2>&1; then cuda=AUTO; else cuda=OFF; fi
fi

echo "== building the geovoronoi tool (build-demo/, Release, CUDA backend: $cuda)"
cmake -S . -B build-demo -DCMAKE_BUILD_TYPE=Release -DGEOVORONOI_BUILD_TESTS=OFF -DGEOVORONOI_BUILD_BENCH=OFF \
      -DGEOVORONOI_BUILD_EXAMPLES=OFF -DGEOVORONOI_BUILD_TOOLS=ON -DGEOVORONOI_TOOL_LEAN=ON \
      -DGEOVORONOI_CUDA="$cuda" >/dev/null
cmake --build build-demo --target geovoronoi_tool -j"$(nproc)"
echo "== built in $((SECONDS - start)) s"

echo "== geovoronoi demo --out $out"
build-demo/bin/geovoronoi demo --out "$out"
echo
echo "Pictures (PNG) and volumes (.mhd/.raw, .vti, .npy) are in $(cd "$out" && pwd):"
ls -1 "$out"/*.png "$out"/*/*.png
echo "== demo done in $((SECONDS - start)) s"

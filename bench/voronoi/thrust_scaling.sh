#!/usr/bin/env bash
# Thrust (OpenMP system) against seq in the same run, with 1 and 2 OpenMP threads:
#   bench/voronoi/thrust_scaling.sh [build-dir] [repetitions]
# For each thread count it runs bench_voronoi_thrust once on the gradient and steak cases at 128^3,
# 10 seeds, 26-connectivity, with --benchmark_repetitions, and prints the mean times and the ratio
# seq / thrust_omp (> 1: thrust_omp faster). Before each run it waits (up to QUIET_WAIT seconds,
# default 600) until no other process uses more than 20% of a core, and says whether it got that.
# OMP_WAIT_POLICY and GOMP_SPINCOUNT are passed through unchanged (see docs/backend-thrust.md on
# loaded machines).
set -euo pipefail
build=${1:-build}
reps=${2:-3}
exe="$build/bench/bench_voronoi_thrust"
[[ -x $exe ]] || { echo "no $exe: cmake --build $build --target bench_voronoi_thrust" >&2; exit 1; }
py=/usr/bin/python3
[[ -x $py ]] || py=python3
filter='voronoi/(seq|thrust_omp)/(gradient|steak)/128/10/26'
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT

busiest() {  # highest CPU share (percent of one core) of any process over one second (top's 2nd sample)
  top -bn2 -d1 | awk '/^ *PID/{n++; next} n==2 && $9+0 > m {m = $9+0} END {print m+0}'
}

wait_quiet() {
  local waited=0 limit=${QUIET_WAIT:-600} b
  while :; do
    b=$(busiest)
    if awk -v b="$b" 'BEGIN{exit !(b < 20)}'; then echo "quiet (busiest other process ${b}% of a core)"; return; fi
    if (( waited >= limit )); then echo "NOT quiet after ${limit}s (busiest other process ${b}%)"; return; fi
    sleep 10
    waited=$((waited + 10))
  done
}

echo "machine: $(lscpu | awk -F: '/Model name/{gsub(/^ +/,"",$2); print $2; exit}'), $(nproc) CPUs; $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-<unset>} GOMP_SPINCOUNT=${GOMP_SPINCOUNT:-<unset>}"
for t in 1 2; do
  echo "== OMP_NUM_THREADS=$t: $(wait_quiet); load average $(cut -d' ' -f1-3 /proc/loadavg)"
  OMP_NUM_THREADS=$t "$exe" --benchmark_filter="$filter" --benchmark_repetitions="$reps" \
    --benchmark_out="$out/t$t.json" --benchmark_out_format=json >/dev/null 2>"$out/t$t.log"
  "$py" - "$out/t$t.json" <<'EOF'
import json, re, statistics, sys
runs = [b for b in json.load(open(sys.argv[1]))["benchmarks"] if b.get("run_type") == "iteration"]
by = {}
for b in runs:
    m = re.match(r"voronoi/([^/]+)/([^/]+)/", b["run_name"])
    by.setdefault((m.group(1), m.group(2)), []).append(b)
for field in ("gradient", "steak"):
    s = [b["real_time"] for b in by.get(("seq", field), [])]
    o = by.get(("thrust_omp", field), [])
    t = [b["real_time"] for b in o]
    if not s or not t:
        continue
    rel = o[-1].get("relaxations_per_voxel", float("nan"))
    print(f"  {field:8s} seq {statistics.mean(s):7.1f} ms (runs {', '.join(f'{x:.0f}' for x in s)})"
          f"   thrust_omp {statistics.mean(t):7.1f} ms (runs {', '.join(f'{x:.0f}' for x in t)})"
          f"   seq/thrust_omp {statistics.mean(s) / statistics.mean(t):.2f}x   relaxations/voxel {rel:.4f}")
EOF
done

#!/usr/bin/env bash
# Thrust (OpenMP system) against seq in the same run, with 1 and 2 OpenMP threads, in interleaved rounds:
#   bench/voronoi/thrust_scaling.sh [build-dir] [rounds]
# Each round runs bench_voronoi_thrust once with OMP_NUM_THREADS=1, then once with 2, on the cases of
# FILTER (default: gradient and steak 128^3 and gradient 256^3 with 10 seeds, the MRI-like pelvis
# mri/221/20; all 26-connected), so a disturbance hits both thread counts and both backends alike.
# It prints, per case and thread count, the median times over the rounds, the ratio seq / thrust_omp
# (> 1: thrust_omp faster), thrust_omp's slowest run over its median (one run = one solve at 256^3 and
# for mri; the mean of 2 solves at 128^3; the issue asks <= 1.2) and
# relaxations per voxel, and the load average at the start of every run. Before the first round and
# after the last it times a fixed memory-bound loop without the library (the machine's own spread). Before the first round it
# waits (up to QUIET_WAIT seconds, default 600) until no other process uses more than 20% of a core,
# and says whether it got that. OMP_WAIT_POLICY and GOMP_SPINCOUNT are passed through unchanged
# (see docs/backend-thrust.md on loaded machines).
set -euo pipefail
build=${1:-build}
rounds=${2:-3}
exe="$build/bench/bench_voronoi_thrust"
[[ -x $exe ]] || { echo "no $exe: cmake --build $build --target bench_voronoi_thrust" >&2; exit 1; }
py=/usr/bin/python3
[[ -x $py ]] || py=python3
filter=${FILTER:-'voronoi/(seq|thrust_omp)/((gradient|steak)/128/10/26|gradient/256/10/26|mri/221/20/26)'}
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

# The machine's own spread on memory-bound work, without the library: a fixed random gather over
# 64 MiB (NumPy), 8 runs after a warm-up. A solve of these sizes waits on memory, so its slowest / median can only be
# judged against this one (docs/benchmarks.md, "Huge pages, and where the spread comes from").
memory_spread() {
  "$py" - <<'PYEOF' 2>/dev/null || echo "(no NumPy for $py: machine check skipped)"
import statistics, time
import numpy as np
n = 16 << 20
a = np.arange(n, dtype=np.uint32)
idx = np.random.default_rng(1).integers(0, n, n, dtype=np.int64)
int(a[idx].sum())  # warm-up: page faults of the first gather
ts = []
for _ in range(8):
    t = time.perf_counter()
    int(a[idx].sum())
    ts.append(time.perf_counter() - t)
m = statistics.median(ts)
print(f"machine check (random gather over 64 MiB, 8 runs): fastest {min(ts):.3f} s, median {m:.3f} s, "
      f"slowest {max(ts):.3f} s, slowest / median {max(ts) / m:.2f}")
PYEOF
}

echo "machine: $(lscpu | awk -F: '/Model name/{gsub(/^ +/,"",$2); print $2; exit}'), $(nproc) CPUs; $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-<unset>} GOMP_SPINCOUNT=${GOMP_SPINCOUNT:-<unset>}"
echo "before round 1: $(wait_quiet)"
memory_spread
for r in $(seq 1 "$rounds"); do
  for t in 1 2; do
    echo "round $r, OMP_NUM_THREADS=$t: load average $(cut -d' ' -f1-3 /proc/loadavg)"
    OMP_NUM_THREADS=$t "$exe" --benchmark_filter="$filter" \
      --benchmark_out="$out/r${r}t$t.json" --benchmark_out_format=json >/dev/null 2>"$out/r${r}t$t.log"
  done
done
memory_spread
echo "done: load average $(cut -d' ' -f1-3 /proc/loadavg), $(date -u '+%H:%M UTC')"
"$py" - "$out" <<'EOF'
import glob, json, os, re, statistics, sys
by = {}
for f in sorted(glob.glob(os.path.join(sys.argv[1], "r*t*.json"))):
    t = int(re.search(r"t(\d+)\.json$", f).group(1))
    for b in json.load(open(f))["benchmarks"]:
        if b.get("run_type") != "iteration":
            continue
        m = re.match(r"voronoi/([^/]+)/(.+?)(/iterations.*)?$", b["run_name"])
        by.setdefault((m.group(2), t, m.group(1)), []).append(b)
cases = sorted({(c, t) for c, t, _ in by})
print("| case | threads | seq ms (median; runs) | thrust_omp ms (median; runs) | seq / thrust_omp | thrust slowest / median | relaxations/voxel |")
print("|---|---:|---:|---:|---:|---:|---:|")
for c, t in cases:
    s = [b["real_time"] for b in by.get((c, t, "seq"), [])]
    o = by.get((c, t, "thrust_omp"), [])
    th = [b["real_time"] for b in o]
    if not s or not th:
        continue
    ms, mt = statistics.median(s), statistics.median(th)
    rel = max(b.get("relaxations_per_voxel", float("nan")) for b in o)
    fmt = lambda xs: ", ".join(f"{x:.0f}" for x in xs)
    print(f"| {c} | {t} | {ms:.0f} ({fmt(s)}) | {mt:.0f} ({fmt(th)}) | {ms / mt:.2f}x | {max(th) / mt:.2f} | {rel:.4f} |")
EOF

#!/usr/bin/env bash
# Builds the benchmark executables (Release) and runs every case that docs/benchmarks.md reports,
# writing Google Benchmark JSON files that bench/report.py turns into the document's tables:
#
#   bench/run_all.sh [options]                    one run; then: bench/report.py tables OUT
#   bench/run_all.sh --before-rev main [options]  the same cases on the code of `main`, alternated
#                                                 with the working tree's; then: bench/report.py compare OUT
#
# Options:
#   -o, --out DIR        results folder (default build-bench/results/<UTC date and time>)
#   -b, --build DIR      build folder of the working tree (default build-bench; configured Release)
#   --no-build           run the executables already in the build folders
#   --before DIR         a build folder of another version (its bench/ executables are run as "before")
#   --before-rev REV     check REV out in a git worktree under <build>-before/src, build it in
#                        <build>-before/build (kept for the next run) and use it as --before
#   --rounds N           rounds (default 1, with a before set 3); each round runs every case once per
#                        side, before and current alternating (the first side alternates too)
#   --repetitions N      --benchmark_repetitions of the short cases (default 3; the shape cases, one
#                        iteration of seconds to a minute each, run once per round)
#   --threads "1 2"      OpenMP thread counts of the Thrust runs (default "1 <nproc>")
#   --groups LIST        comma-separated subset of: voronoi,thrust,queue,sparse,shape,shape_update,cuda,python
#   --quick              the headline cases only (minutes instead of about an hour)
#   --full               every registered case, also those docs/benchmarks.md does not report
#   --no-verify          shape_update cases without GEOVORONOI_BENCH_VERIFY (no bit-for-bit check,
#                        half the time)
#   --python PY          run bench/python/bench_python.py with interpreter PY (the package installed)
#   --quiet-wait S       before each run wait up to S seconds for the 1-minute load average to fall
#                        below 0.5 (default 0: do not wait); the load of every run is logged anyway
#
# Output: OUT/current/<executable>[.t<threads>].r<round>[.c<case>].json (and OUT/before/... with a
# before set), OUT/meta.txt (commits, compiler, flags, CPU model, dates), OUT/commands.txt (every
# command as run, for the document's "reproduce" lines) and OUT/<side>/logs/ (each run's output).
# Each shape-function case runs in a process of its own, so that its peak_rss_MB counter is its own.
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
cd "$src"

build=build-bench
out=""
do_build=1
before=""
before_rev=""
rounds=""
reps=3
threads="1 $(nproc)"
groups="voronoi,thrust,queue,sparse,shape,shape_update,cuda,python"
mode=default
verify=1
python=""
quiet_wait=0
while (($#)); do
  case $1 in
    -o|--out) out=$2; shift ;;
    -b|--build) build=$2; shift ;;
    --no-build) do_build=0 ;;
    --before) before=$2; shift ;;
    --before-rev) before_rev=$2; shift ;;
    --rounds) rounds=$2; shift ;;
    --repetitions) reps=$2; shift ;;
    --threads) threads=$2; shift ;;
    --groups) groups=$2; shift ;;
    --quick) mode=quick ;;
    --full) mode=full ;;
    --no-verify) verify=0 ;;
    --python) python=$2; shift ;;
    --quiet-wait) quiet_wait=$2; shift ;;
    -h|--help) sed -n '2,/^set -euo/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "unknown option $1 (--help)" >&2; exit 2 ;;
  esac
  shift
done
[[ -n $rounds ]] || { [[ -n $before || -n $before_rev ]] && rounds=3 || rounds=1; }
out=${out:-$build/results/$(date -u +%Y%m%d-%H%M%S)}
has_group() { [[ ",$groups," == *",$1,"* ]]; }
gpu=0
if command -v nvidia-smi >/dev/null 2>&1 && nvidia-smi -L 2>/dev/null | grep GPU >/dev/null; then gpu=1; fi
max_threads=${threads##* }

targets=(bench_voronoi_cpu bench_voronoi_thrust bench_queue_ablation bench_seq_sparse bench_shape_seq
         bench_shape_thrust_omp)
((gpu)) && targets+=(bench_voronoi_gpu_cpu bench_voronoi_thrust_cuda)

# configure_and_build SRC BUILD: Release, benchmarks only; builds the targets this configuration has
configure_and_build() {
  local s=$1 b=$2 gen=()
  if [[ ! -f $b/CMakeCache.txt ]] && command -v ninja >/dev/null 2>&1; then gen=(-G Ninja); fi
  cmake -S "$s" -B "$b" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DGEOVORONOI_BUILD_BENCH=ON \
        -DGEOVORONOI_BUILD_TESTS=OFF -DGEOVORONOI_BUILD_TOOLS=OFF -DGEOVORONOI_BUILD_EXAMPLES=OFF >/dev/null
  local have=() known
  known=$(cmake --build "$b" --target help 2>/dev/null || true)
  for t in "${targets[@]}"; do
    grep -qw -- "$t" <<<"$known" && have+=("$t")
  done
  echo "== building in $b: ${have[*]}"
  cmake --build "$b" --target "${have[@]}" -j"$(nproc)"
}

if [[ -n $before_rev ]]; then
  before_root=$build-before
  mkdir -p "$before_root"
  if [[ ! -d $before_root/src ]]; then
    git worktree add --detach "$before_root/src" "$before_rev" >/dev/null
  else
    git -C "$before_root/src" checkout --detach -q "$before_rev"
  fi
  before=$before_root/build
  ((do_build)) && configure_and_build "$before_root/src" "$before"
fi
((do_build)) && configure_and_build "$src" "$build"

exe_dir() { if [[ -d $1/bench ]]; then echo "$1/bench"; else echo "$1"; fi; }
sides=(current)
declare -A dir=([current]=$(exe_dir "$build"))
if [[ -n $before ]]; then
  sides=(before current)
  dir[before]=$(exe_dir "$before")
fi
mkdir -p "$out"
for s in "${sides[@]}"; do mkdir -p "$out/$s/logs"; done

git_desc() { git -C "$1" rev-parse --short HEAD 2>/dev/null || echo "?"; }
dirty() { [[ -n $(git -C "$1" status --porcelain --untracked-files=no 2>/dev/null) ]] && echo " (with uncommitted changes)" || true; }
cache_value() { { sed -n "s/^$2:[A-Z]*=//p" "$1/CMakeCache.txt" 2>/dev/null || true; } | head -n 1; }
cxx=$(cache_value "$build" CMAKE_CXX_COMPILER)
{
  echo "commit=$(git_desc "$src")$(dirty "$src")"
  [[ -n $before_rev ]] && echo "commit_before=$before_rev ($(git_desc "$before_root/src"))"
  [[ -n $before && -z $before_rev ]] && echo "commit_before=the executables in $before"
  echo "cpu_model=$(lscpu 2>/dev/null | sed -n 's/^Model name: *//p' | head -n 1)"
  echo "cpus=$(nproc)"
  echo "compiler=$("${cxx:-c++}" --version 2>/dev/null | head -n 1)"
  echo "flags=$(cache_value "$build" CMAKE_CXX_FLAGS_RELEASE) (CMAKE_BUILD_TYPE=$(cache_value "$build" CMAKE_BUILD_TYPE))"
  echo "started=$(date -u '+%Y-%m-%d %H:%M UTC')"
  echo "load_start=$(cut -d' ' -f1-3 /proc/loadavg)"
  echo "repetitions=$reps"
  echo "rounds=$rounds"
  echo "omp_threads=$threads"
  echo "omp_env=OMP_WAIT_POLICY=${OMP_WAIT_POLICY:-unset} OMP_PROC_BIND=${OMP_PROC_BIND:-unset}"
  echo "mode=$mode"
} > "$out/meta.txt"

failures=0
wait_quiet() {
  ((quiet_wait > 0)) || return 0
  local waited=0
  while awk '{exit !($1 >= 0.5)}' /proc/loadavg && ((waited < quiet_wait)); do sleep 10; waited=$((waited + 10)); done
}

# run SIDE FILE EXE FILTER REPS [ENV...]: one process; its JSON goes to OUT/SIDE/FILE
run() {
  local side=$1 file=$2 exe=$3 filter=$4 r=$5
  shift 5
  local path=${dir[$side]}/$exe
  [[ -x $path ]] || { echo "   (no $path: skipped)"; return 0; }
  wait_quiet
  local cmd=(env "$@" "$path" "--benchmark_filter=$filter" "--benchmark_out=$out/$side/$file"
             --benchmark_out_format=json)
  ((r > 1)) && cmd+=("--benchmark_repetitions=$r")
  local load t0=$SECONDS
  load=$(cut -d' ' -f1 /proc/loadavg)
  printf '%q ' "${cmd[@]}" >> "$out/commands.txt"
  echo >> "$out/commands.txt"
  if ! "${cmd[@]}" > "$out/$side/logs/${file%.json}.log" 2>&1; then
    echo "   FAILED: $side $exe (log: $out/$side/logs/${file%.json}.log)"
    tail -n 5 "$out/$side/logs/${file%.json}.log"
    failures=$((failures + 1))
    return 0
  fi
  echo "   $side $file: $((SECONDS - t0)) s (load average before: $load)"
}

# alternate ROUND ARGS...: run ARGS for every side, the first side alternating with the round
alternate() {
  local round=$1
  shift
  local order=("${sides[@]}")
  ((${#sides[@]} == 2 && round % 2 == 0)) && order=(current before)
  for s in "${order[@]}"; do run "$s" "$@"; done
}

# per_case ROUND EXE TAG FILTER [ENV...]: every case matching FILTER in a process of its own
per_case() {
  local round=$1 exe=$2 tag=$3 filter=$4
  shift 4
  local path=${dir[current]}/$exe
  [[ -x $path ]] || { echo "   (no $path: skipped)"; return 0; }
  local names i=0 c
  names=$("$path" --benchmark_list_tests=true "--benchmark_filter=$filter" 2>/dev/null |
          sed -E 's#/(iterations|min_time|real_time|manual_time|repeats)(:[^/]*)?##g' | sort -u)
  for c in $names; do
    i=$((i + 1))
    alternate "$round" "$exe$tag.r$round.c$(printf %02d "$i").json" "$exe" "^$c/" 1 "$@"
  done
}

# ---- the case filters (Google Benchmark's --benchmark_filter, POSIX extended regular expressions) ----
case $mode in
  quick)
    f_cpu='voronoi/(seq|sofa_set)/(gradient|steak)/(64|128)/10/26/|voronoi/seq/mri/|voronoi/seq/steak128/|update/seq/steak128/(cut20|add_node|carve8)/'
    f_thrust='voronoi/(seq|thrust_omp)/((gradient|steak)/128/10/26|mri/221/20/26)/'
    f_shape='^shape/(sibson|laplace|distance_ratio)/seq/(table1|beam|steak64|at1000)/'
    f_shape_omp='^shape/(sibson|laplace|distance_ratio)/thrust_omp/(table1|beam|steak64|at1000)/'
    f_update='^shape_update/(distance_ratio_kept|sibson)/[a-z_]+/steak128/cut20/'
    f_sparse='sparse/(insert|bounded)/paged64/|sparse/dense/'
    ;;
  full)
    f_cpu='.'
    f_thrust='.'
    f_shape='^shape/[a-z_]+/seq/|^shape/(sibson|laplace)/(seq_materialise|seq_noreuse)/(beam|steak64|at1000)/|^shape/sibson/seq_nofilter/'
    f_shape_omp='^shape/'
    f_update='^shape_update/'
    f_sparse='.'
    ;;
  *)
    f_cpu='.'
    f_thrust='voronoi/(seq|thrust_omp|thrust_tbb)/(((constant|gradient|steak)/(64|128|256)/10/26)|mri/221/20/26)/|voronoi/(seq|thrust_omp)/steak128|update/thrust_omp/'
    f_shape='^shape/[a-z_]+/seq/|^shape/(sibson|laplace)/(seq_materialise|seq_noreuse)/(beam|steak64|at1000)/|^shape/sibson/seq_nofilter/'
    f_shape_omp='^shape/[a-z_]+/thrust_omp/|^shape/sibson/thrust_omp_nofilter/'
    f_update='^shape_update/'
    f_sparse='.'
    ;;
esac
# seq_materialise on steak128 takes about a quarter of an hour: --full does not add it either;
# run it alone when needed: bench_shape_seq --benchmark_filter='^shape/sibson/seq_materialise/steak128/'

echo "== results in $out (rounds: $rounds; sides: ${sides[*]}; threads: $threads; $mode)"
for round in $(seq 1 "$rounds"); do
  echo "== round $round"
  if has_group voronoi; then
    alternate "$round" "bench_voronoi_cpu.r$round.json" bench_voronoi_cpu "$f_cpu" "$reps"
  fi
  if has_group thrust; then
    for t in $threads; do
      alternate "$round" "bench_voronoi_thrust.t$t.r$round.json" bench_voronoi_thrust "$f_thrust" "$reps" \
        "OMP_NUM_THREADS=$t"
    done
  fi
  if has_group queue; then
    alternate "$round" "bench_queue_ablation.r$round.json" bench_queue_ablation . "$reps"
  fi
  if has_group sparse; then
    alternate "$round" "bench_seq_sparse.r$round.json" bench_seq_sparse "$f_sparse" "$reps"
  fi
  if has_group shape; then
    per_case "$round" bench_shape_seq "" "$f_shape"
    per_case "$round" bench_shape_thrust_omp ".t$max_threads" "$f_shape_omp" "OMP_NUM_THREADS=$max_threads"
  fi
  if has_group shape_update; then
    venv=()
    ((verify)) && venv=(GEOVORONOI_BENCH_VERIFY=1)
    alternate "$round" "bench_shape_seq.update.r$round.json" bench_shape_seq "$f_update" 1 "${venv[@]}"
    alternate "$round" "bench_shape_thrust_omp.t$max_threads.update.r$round.json" bench_shape_thrust_omp \
      "$f_update" 1 "OMP_NUM_THREADS=$max_threads" "${venv[@]}"
  fi
  if has_group cuda && ((gpu)); then
    alternate "$round" "bench_voronoi_gpu_cpu.r$round.json" bench_voronoi_gpu_cpu \
      'voronoi/(cuda|cuda_end_to_end|seq|sofa_set)/((constant|gradient|steak)/(64|128|256)/10/26)/|voronoi/cuda/[a-z]+/512/10/26/|copy/cuda/' "$reps"
    alternate "$round" "bench_voronoi_thrust_cuda.r$round.json" bench_voronoi_thrust_cuda \
      'voronoi/(seq|thrust_cuda)/(((constant|gradient|steak)/(128|256)/10/26)|mri/221/20/26)/' "$reps"
  fi
done
if has_group python && [[ -n $python ]]; then
  echo "== bench/python/bench_python.py with $python"
  "$python" bench/python/bench_python.py > "$out/current/python.txt" 2>&1 || echo "   FAILED (see $out/current/python.txt)"
  echo "$python bench/python/bench_python.py" >> "$out/commands.txt"
fi
echo "finished=$(date -u '+%Y-%m-%d %H:%M UTC')" >> "$out/meta.txt"
echo "load_end=$(cut -d' ' -f1-3 /proc/loadavg)" >> "$out/meta.txt"
echo "== done: bench/report.py tables $out"
[[ ${#sides[@]} == 2 ]] && echo "          bench/report.py compare $out"
if ((failures)); then
  echo "== $failures run(s) failed: see the logs under $out"
  exit 1
fi
exit 0

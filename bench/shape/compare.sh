#!/bin/sh
# Before/after timing of the shape-function cases in one script run: each case runs as its own process
# under /usr/bin/time (user+sys = CPU of all threads; elapsed = wall), the old and the new executable
# alternately, with the load average before each run.
#   bench/shape/compare.sh OLD_DIR NEW_DIR [filter regex of case names]
# OLD_DIR and NEW_DIR hold bench_shape_seq and bench_shape_thrust_omp (e.g. a build of the previous commit
# and build/bench). thrust_omp runs with OMP_NUM_THREADS=2.
old=$1
new=$2
filter=${3:-.}
cases="sibson/seq/beam laplace/seq/beam sibson/seq/steak64 laplace/seq/steak64
distance_ratio/seq/at1000 sibson/seq/at1000 laplace/seq/at1000
sibson/thrust_omp/beam laplace/thrust_omp/beam sibson/thrust_omp/steak64 laplace/thrust_omp/steak64
distance_ratio/thrust_omp/at1000 sibson/thrust_omp/at1000 laplace/thrust_omp/at1000"
# call_s: Google Benchmark's wall time of the shape-function call alone; cpu_s and wall_s: the whole
# process (case set-up and diagram included, about 0.1-0.4 s on steak128).
printf '%-34s %-4s %8s %8s %8s %6s  %s\n' case side call_s cpu_s wall_s load1 peak_rss_MB
for c in $cases; do
  echo "$c" | grep -Eq "$filter" || continue
  case $c in */thrust_omp/*) exe=bench_shape_thrust_omp ;; *) exe=bench_shape_seq ;; esac
  for side in old new; do
    dir=$old
    [ $side = new ] && dir=$new
    load=$(cut -d' ' -f1 /proc/loadavg)
    out=$(OMP_NUM_THREADS=2 /usr/bin/time -f 'TIME %U %S %e' "$dir/$exe" --benchmark_filter="^shape/$c/" 2>&1)
    t=$(echo "$out" | grep '^TIME')
    rss=$(echo "$out" | grep -o 'peak_rss_MB=[0-9.]*' | cut -d= -f2)
    call=$(echo "$out" | grep "^shape/$c/" | awk '{print $2 " " $3}')
    echo "$t" | awk -v c="$c" -v s="$side" -v l="$load" -v r="$rss" -v call="$call" '{split(call, a, " "); v = a[1]; if (a[2] == "ms") v = v / 1000; printf "%-34s %-4s %8.3f %8.2f %8.2f %6s  %s\n", c, s, v, $2 + $3, $4, l, r}'
  done
done

#!/bin/bash
# Old and new rebuild_bench interleaved on this machine: median wall and CPU time per map of
# BM_RebuildTen over N repetitions, so noise from other jobs hits both alike. One-thread runs
# are pinned to CPU 1 (taskset), two-thread runs are not.
#   bench/meta/compare_rebuild.sh OLD_BINARY NEW_BINARY [N] [TREND]
# Both binaries must name the benchmark BM_RebuildTen/threads:T/trend:D (main since issue 16);
# TREND 0 is the random database, 1 (the default) the trend database of a real run.
set -euo pipefail
old=$1 new=$2 n=${3:-5} trend=${4:-1}
declare -A wall cpu
run() {  # binary threads label
  local line pin=()
  [[ $2 == 1 ]] && pin=(taskset -c 1)
  line=$("${pin[@]}" "$1" --benchmark_filter="BM_RebuildTen/threads:$2/trend:$trend" --benchmark_min_time=0.5 2>&1 |
         grep '^BM_' | head -1)
  [[ -n $line ]] || { echo "no BM_RebuildTen/threads:$2/trend:$trend in $1" >&2; exit 1; }
  wall[$3]+="$(echo "$line" | awk '{print $2 / 10}') "
  cpu[$3]+="$(echo "$line" | awk '{print $4 / 10}') "
}
for _ in $(seq "$n"); do
  for t in 1 2; do
    run "$old" "$t" "old/threads:$t"
    run "$new" "$t" "new/threads:$t"
  done
done
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
for k in old/threads:1 new/threads:1 old/threads:2 new/threads:2; do
  echo "$k  ms per map: wall $(median "${wall[$k]}"), main-thread CPU $(median "${cpu[$k]}")   (wall of each: ${wall[$k]})"
done

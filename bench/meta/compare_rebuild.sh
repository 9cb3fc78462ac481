#!/bin/bash
# Old and new rebuild_bench interleaved on this machine: median wall and CPU time per map of
# BM_RebuildTen over N repetitions, so noise from other jobs hits both alike.
#   bench/meta/compare_rebuild.sh OLD_BINARY NEW_BINARY [N]
# OLD_BINARY names its benchmark BM_RebuildTen/T (before issue 16), NEW_BINARY
# BM_RebuildTen/threads:T/trend:0 (the same random database).
set -euo pipefail
old=$1 new=$2 n=${3:-5}
declare -A wall cpu
run() {  # binary filter label
  local line
  line=$("$1" --benchmark_filter="$2" --benchmark_min_time=0.5 2>&1 | grep '^BM_' | head -1)
  wall[$3]+="$(echo "$line" | awk '{print $2 / 10}') "
  cpu[$3]+="$(echo "$line" | awk '{print $4 / 10}') "
}
for _ in $(seq "$n"); do
  for t in 1 2; do
    run "$old" "BM_RebuildTen/$t/" "old/threads:$t"
    run "$new" "BM_RebuildTen/threads:$t/trend:0" "new/threads:$t"
  done
done
median() { tr ' ' '\n' <<<"$1" | grep . | sort -g | awk '{a[NR] = $1} END {print a[int((NR + 1) / 2)]}'; }
for k in old/threads:1 new/threads:1 old/threads:2 new/threads:2; do
  echo "$k  ms per map: wall $(median "${wall[$k]}"), main-thread CPU $(median "${cpu[$k]}")   (wall of each: ${wall[$k]})"
done

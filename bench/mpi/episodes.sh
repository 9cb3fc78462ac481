#!/usr/bin/env bash
# Episodes/s of random RHex controllers with 1 and 2 MPI ranks (and a plain 1-thread run), for
# docs/scaling.md. Usage: bench/mpi/episodes.sh [BUILD_DIR] [RANKS...]; prints one line per run.
set -euo pipefail
cd "$(dirname "$0")/../.."
build=${1:-build}
shift || true
if [ $# -gt 0 ]; then ranks=("$@"); else ranks=(1 2); fi
if [ "$(id -u)" -eq 0 ]; then export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1; fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
report() {  # label, run dir, wall seconds
  local evals
  evals=$(grep -o '"evals": [0-9]*' "$2/summary.json" | grep -o '[0-9]*$')
  awk -v l="$1" -v e="$evals" -v w="$3" 'BEGIN { printf "%-22s %4d episodes in %7.2f s: %6.2f episodes/s\n", l, e, w, e / w }'
}
start=$(date +%s.%N)
"$build/qdmeta" run --config bench/mpi/rhex-random.toml --out "$out/threads" --threads 1 --quiet
report "threads=1 (no MPI)" "$out/threads" "$(echo "$(date +%s.%N) - $start" | bc)"
for n in "${ranks[@]}"; do
  start=$(date +%s.%N)
  mpirun --oversubscribe --mca btl self,vader -np "$n" "$build/qdmeta" run --config bench/mpi/rhex-random.toml \
    --out "$out/ranks$n" --quiet
  report "mpirun -np $n" "$out/ranks$n" "$(echo "$(date +%s.%N) - $start" | bc)"
  cmp -s "$out/threads/archive.csv" "$out/ranks$n/archive.csv" || { echo "archive.csv differs with $n ranks"; exit 1; }
done

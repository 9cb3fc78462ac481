#!/usr/bin/env bash
# The Rastrigin evidence of docs/results/rastrigin.md, as one command: the paper's study (four
# conditions and QD-Meta Translation's frozen control, 20 replicates), the meta-population-size
# study (lambda in {1, 2, 5, 10, 20}, 10 replicates) and the paper's study at the authors'
# effective mutation SD 0.0025 (10 replicates), each with its test phase and report; then the
# reports (report.md, figures, data/*.csv) are copied under docs/results/rastrigin/.
#
#   scripts/rastrigin-study.sh [EVALS] [OUT]      (defaults: 100000000, results/rastrigin-study)
#
# Two experiments run at once with one thread each (whole runs in parallel scale better than
# two threads inside one run); every run gives the same bits at any thread count. Rerun the same
# command after a crash: finished runs are skipped and unfinished ones resumed.
set -euo pipefail
cd "$(dirname "$0")/.."
EVALS=${1:-100000000}
OUT=${2:-results/rastrigin-study}
BIN=${QDMETA:-build/qdmeta}
DOCS=docs/results/rastrigin
[[ -x $BIN ]] || { echo "rastrigin-study: $BIN not found: build first (make build)" >&2; exit 2; }

experiment() {  # name config replicates
  "$BIN" experiment --config "configs/rastrigin/$2" --out "$OUT/$1" --replicates "$3" --evals "$EVALS" --threads 1 \
    --no-report --quiet
  echo "rastrigin-study: $1 finished ($(date -u +%H:%M:%S))"
}

start=$(date +%s)
experiment paper experiment.toml 20 &
paper=$!
{ experiment lambda experiment-lambda.toml 10 && experiment sigma experiment-sigma.toml 10; } &
others=$!
status=0
wait $paper || status=$?
wait $others || status=$?
[[ $status == 0 ]] || { echo "rastrigin-study: an experiment failed (exit $status)" >&2; exit "$status"; }
echo "rastrigin-study: all runs finished in $(( $(date +%s) - start )) s"

for name in paper lambda sigma; do
  "$BIN" report "$OUT/$name"
  rm -rf "${DOCS:?}/$name"
  mkdir -p "$DOCS/$name"
  cp -r "$OUT/$name/report.md" "$OUT/$name/figures" "$OUT/$name/data" "$DOCS/$name/"
done
echo "rastrigin-study: reports copied to $DOCS/{paper,lambda,sigma}"

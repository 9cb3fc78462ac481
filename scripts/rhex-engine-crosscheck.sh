#!/bin/bash
# The engine cross-check (docs/fidelity.md, "Cross-check, engine against engine"): 200 random
# controllers and the tripod in the 14 environments of the study, on each model, run in slices
# (one environment and model, compliant legs 50 controllers at a time) at low priority, so that an
# interrupted run resumes where it stopped (a slice is kept once complete); then the finished slices are joined, in the study's
# order, into the committed CSV that tools/rhex_engines_table.py makes the table from.
#   scripts/rhex-engine-crosscheck.sh [BUILD_DIR] [SLICE_DIR] [CSV]
# MODELS (default: dart-rigid mujoco-rigid dart-compliant, and mujoco-compliant when the build
# has it), THREADS (2) and NICE (19) from the environment; JOIN_ONLY=1 only joins.
set -euo pipefail
build=${1:-build}
slices=${2:-build/rhex-crosscheck}
csv=${3:-docs/results/rhex-engines/episodes.csv}
models=${MODELS:-dart-rigid mujoco-rigid dart-compliant mujoco-compliant}
count=200
mkdir -p "$slices" "$(dirname "$csv")"

ranges() {  # the slices of one model: "from to" per line
  case $1 in
    *compliant) for from in 0 50 100 150; do echo "$from $((from + 50))"; done ;;
    *) echo "0 $count" ;;
  esac
}

# Round by round: round k runs each model's k-th slice in every environment (rigid legs have one
# slice, compliant legs four of 50 controllers), so that a run stopped early covers every model
# and environment with the same controllers; the tripod goes with each model's first slice.
if [[ ${JOIN_ONLY:-0} != 1 ]]; then
  for round in 0 1 2 3; do
    for model in $models; do
      ranges "$model" | sed -n "$((round + 1))p" | while read -r from to; do
        for env in $(seq 0 13); do
          out="$slices/$env-$model-$from.csv"
          [[ -f $out ]] && continue
          nice -n "${NICE:-19}" "$build/bench/rhex_crosscheck" models="$model" env="$env" count=$count from="$from" \
            to="$to" tripod=$((from == 0)) threads="${THREADS:-2}" header=0 > "$out.part"
          mv "$out.part" "$out"
        done
      done
    done
  done
fi

# A slice joins only when it is done in every environment (a whole round of its model).
complete() {
  local e
  for e in $(seq 0 13); do [[ -f $slices/$e-$1-$2.csv ]] || return 1; done
}
echo "environment,model,controller,distance,dead,cause" > "$csv.part"
for env in $(seq 0 13); do
  for model in dart-rigid dart-compliant mujoco-rigid mujoco-compliant; do
    ranges "$model" | while read -r from _; do
      if complete "$model" "$from"; then cat "$slices/$env-$model-$from.csv"; fi
    done
  done
done >> "$csv.part"
mv "$csv.part" "$csv"

#!/bin/bash
# scripts/slurm-experiment.sh against a stand-in sbatch that runs each job at once (array tasks
# in order, without mpirun): the plan, every run, the finishing job's tests and report, and a
# resubmission that reruns only the run that went missing.
# Usage: slurm_experiment_test.sh QDMETA_BINARY SOURCE_DIR
set -euo pipefail
bin=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

mkdir "$tmp/bin"
cat > "$tmp/bin/sbatch" <<'STUB'
#!/bin/bash
array=""
while [[ ${1:-} == --* ]]; do
  case $1 in --array=*) array=${1#--array=} ;; esac
  shift
done
script=$1
shift
echo "job ${array:-single} $*" >> "$SBATCH_LOG"
if [[ -n $array ]]; then
  range=${array%%\%*}
  for k in $(seq "${range%-*}" "${range#*-}"); do
    SLURM_ARRAY_TASK_ID=$k bash "$script" "$@" >> "$SBATCH_LOG" 2>&1 || echo "task $k failed" >> "$SBATCH_LOG"
  done
else
  bash "$script" "$@" >> "$SBATCH_LOG" 2>&1
fi
echo "$RANDOM;cluster"
STUB
chmod +x "$tmp/bin/sbatch"

cat > "$tmp/experiment.toml" <<TOML
name = "slurm"
replicates = 2
tests = ["dimension"]
[[condition]]
name = "MAP-Elites"
config = "$src/configs/rastrigin/map-elites.toml"
[[condition]]
name = "Small batches"
config = "$src/configs/rastrigin/map-elites.toml"
set = { map_elites = { batch_size = 50 } }
TOML

export SBATCH_LOG=$tmp/sbatch.log QDMETA=$bin QDMETA_LAUNCHER="" PATH=$tmp/bin:$PATH
out=$tmp/out
bash "$src/scripts/slurm-experiment.sh" submit "$tmp/experiment.toml" "$out" --evals 20000 > "$tmp/submit.log"
grep -q "4 runs as array job" "$tmp/submit.log" || fail "submit: $(cat "$tmp/submit.log")"
[[ $(wc -l < "$out/plan.tsv") == 5 ]] || fail "plan.tsv: $(cat "$out/plan.tsv")"
grep -q "evaluations = 20000" "$out/small-batches/condition.toml" || fail "the budget is not in condition.toml"
grep -q "batch_size = 50" "$out/small-batches/condition.toml" || fail "the condition's set is not in condition.toml"
for run in map-elites/seed-1 map-elites/seed-2 small-batches/seed-1 small-batches/seed-2; do
  grep -q '"stop_reason": "budget"' "$out/$run/summary.json" || fail "$run did not finish"
  [[ -f $out/$run/adapt-dimension.csv ]] || fail "$run has no test phase"
done
grep -q "0 runs finished now, 0 resumed, 4 already finished; 4 test phases" "$SBATCH_LOG" || fail "finish: $(cat "$SBATCH_LOG")"
[[ -f $out/report.md ]] || fail "no report"
grep -q "| Small batches | 2 |" "$out/report.md" || fail "report.md lacks a condition"

# A lost run: the resubmission reruns it alone, to the same bits.
cp "$out/small-batches/seed-2/archive.csv" "$tmp/archive-before.csv"
rm -r "$out/small-batches/seed-2"
: > "$SBATCH_LOG"
bash "$src/scripts/slurm-experiment.sh" submit "$tmp/experiment.toml" "$out" --evals 20000 > "$tmp/submit.log"
[[ $(grep -c "already finished$" "$SBATCH_LOG") == 3 ]] || fail "resubmission: $(cat "$SBATCH_LOG")"
cmp "$tmp/archive-before.csv" "$out/small-batches/seed-2/archive.csv" || fail "the rerun differs"
grep -q "0 runs finished now, 0 resumed, 4 already finished; 1 test phases" "$SBATCH_LOG" || fail "finish after resubmission"
echo "slurm-experiment.sh: plan, array, finish and resubmission behave"

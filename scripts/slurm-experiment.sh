#!/bin/bash
# An experiment on a SLURM cluster: one array task per condition x replicate, each an MPI run
# (mpirun qdmeta run/resume), then one job that runs the test phases and the report.
#
#   scripts/slurm-experiment.sh submit EXPERIMENT.toml OUT [--evals N] [--replicates R]
#
# plans the runs (qdmeta experiment --plan: OUT/plan.tsv and each condition's config), submits
# the array and, after it, the finishing job (qdmeta experiment: finished runs are skipped, any
# unfinished one is resumed or run on that job's own cores, then the tests and the report).
# Submit the same command again after a time limit, a node failure or a cancelled job: finished
# runs are skipped and the others resume from their checkpoints, to the bits of an uninterrupted
# run. Every task and job logs to OUT/slurm/ (task-ARRAYJOB_INDEX.log, finish-JOB.log: a
# resubmission keeps the earlier logs).
#
# The #SBATCH lines below are each array task's defaults (the paper's robot study: 40 cores per
# run); override them with SBATCH_ARRAY_ARGS (e.g. "--ntasks=8 --time=12:00:00 --partition=x"),
# the finishing job's with SBATCH_FINISH_ARGS (default "--ntasks=1 --cpus-per-task=8
# --time=12:00:00"), and cap the tasks running at once with MAX_PARALLEL. QDMETA (default
# build/qdmeta, relative to the submit directory) is the program; QDMETA_LAUNCHER (default mpirun)
# starts each run, "" for none. The internal modes `task OUT` and `finish EXPERIMENT OUT [...]` are
# what the jobs run.
#SBATCH --ntasks=40
#SBATCH --cpus-per-task=1
#SBATCH --mem-per-cpu=1G
#SBATCH --time=7-00:00:00
#SBATCH --signal=B:TERM@300
#SBATCH --requeue
set -euo pipefail

QDMETA=${QDMETA:-build/qdmeta}
LAUNCHER=${QDMETA_LAUNCHER-mpirun}
die() { echo "slurm-experiment: $*" >&2; exit 2; }

run_field() {  # OUT INDEX COLUMN: a field of plan.tsv's line INDEX (1-based, after the header)
  awk -F'\t' -v k="$2" -v c="$3" 'NR == k + 1 { print $c }' "$1/plan.tsv"
}

finished() {  # DIR: true when DIR holds a run that reached its budget
  [[ -f $1/summary.json ]] && grep -q '"stop_reason": *"budget"' "$1/summary.json"
}

mode=${1:-}
case $mode in
  submit)
    [[ $# -ge 3 ]] || die "usage: $0 submit EXPERIMENT.toml OUT [--evals N] [--replicates R]"
    experiment=$2 out=$3
    shift 3
    [[ -x $QDMETA ]] || die "$QDMETA not found: build first, or set QDMETA"
    command -v sbatch > /dev/null || die "sbatch not found: run this on the cluster's login node"
    "$QDMETA" experiment --config "$experiment" --out "$out" --plan "$@"
    runs=$(( $(wc -l < "$out/plan.tsv") - 1 ))
    if (( runs == 0 )); then  # every run's summary is kept (--summaries): nothing to submit
      echo "slurm-experiment: no run to submit"
      exit 0
    fi
    mkdir -p "$out/slurm"
    limit=${MAX_PARALLEL:+%$MAX_PARALLEL}
    # shellcheck disable=SC2086  # the ARGS variables are lists of options
    array=$(sbatch --parsable --job-name="qdmeta-$(basename "$out")" --array="1-$runs$limit" \
      --output="$out/slurm/task-%A_%a.log" ${SBATCH_ARRAY_ARGS:-} "$0" task "$out")
    array=${array%%;*}
    # shellcheck disable=SC2086
    finish=$(sbatch --parsable --job-name="qdmeta-$(basename "$out")-report" --dependency="afterany:$array" \
      --output="$out/slurm/finish-%j.log" ${SBATCH_FINISH_ARGS:---ntasks=1 --cpus-per-task=8 --time=12:00:00} \
      "$0" finish "$experiment" "$out" "$@")
    echo "slurm-experiment: $runs runs as array job $array, then job ${finish%%;*} for the tests and the report"
    ;;
  task)
    [[ $# -eq 2 ]] || die "usage: $0 task OUT (inside a SLURM array job)"
    out=$2
    k=${SLURM_ARRAY_TASK_ID:?not in a SLURM array job}
    config=$(run_field "$out" "$k" 4) seed=$(run_field "$out" "$k" 3) dir=$(run_field "$out" "$k" 5)
    [[ -n $dir ]] || die "$out/plan.tsv has no run $k"
    echo "slurm-experiment: run $k: $(run_field "$out" "$k" 2) seed $seed in $dir ($(date -u +%FT%TZ))"
    # The launcher takes the shell's place, so SLURM's TERM before the time limit reaches the
    # ranks: rank 0 writes a checkpoint and the next submission resumes from it.
    if finished "$dir"; then
      echo "slurm-experiment: already finished"
    elif [[ -e $dir/checkpoint.bin ]]; then
      exec $LAUNCHER "$QDMETA" resume --out "$dir"
    else
      exec $LAUNCHER "$QDMETA" run --config "$config" --seed "$seed" --out "$dir" --overwrite
    fi
    ;;
  finish)
    [[ $# -ge 3 ]] || die "usage: $0 finish EXPERIMENT.toml OUT [--evals N] [--replicates R]"
    experiment=$2 out=$3
    shift 3
    exec "$QDMETA" experiment --config "$experiment" --out "$out" "$@"
    ;;
  *)
    die "usage: $0 submit EXPERIMENT.toml OUT [--evals N] [--replicates R]  (see the comment at its top)"
    ;;
esac

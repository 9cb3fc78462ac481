#!/usr/bin/env bash
# The Rastrigin studies of docs/results/rastrigin.md, one replicate range at a time, resumable
# from what is committed: a study of 100,000,000 evaluations takes hours, so it is run in slices
# (about two hours each) across sessions and machines.
#
#   scripts/rastrigin-study.sh --study NAME [--replicates A-B] [--conditions A,B] [--evals N]
#                              [--jobs J] [--work DIR] [--results DIR] [--report-only] [--config FILE]
#                              [--centroids FILE]
#
# Studies (experiment files in configs/rastrigin/):
#   paper      experiment.toml            the paper's four conditions at the authors' effective
#                                         mutation SD 0.0025, with QD-Meta Translation's
#                                         frozen-CMA-ES control; 20 replicates (the headline study)
#   lambda     experiment-lambda.toml     meta-population size lambda in {1, 2, 3, 5, 10, 20}
#                                         (Fig S1) at SD 0.0025; 20 replicates
#   lambda-stated-sd  experiment-lambda-stated-sd.toml  the same at the stated SD 0.05
#   stated-sd  experiment-stated-sd.toml  the paper's four conditions at its stated SD 0.05;
#                                         20 replicates
#   authors    experiment-authors.toml    the authors' variants (docs/fidelity.md): lambda = 1 as
#                                         their CMA-ES ran it (SD 0.0025 and 0.05), CVT-MAP-Elites
#                                         on their centroid file, QD-Meta with their 2g - 1 database
#                                         inputs; 20 replicates
#   cma-mae-inner  experiment-cma-mae-inner.toml  QD-Meta Translation and Dimension over CMA-MAE's
#                                         emitters (qd_meta.bottom_level = "cma-mae"), and CMA-MAE
#                                         alone; 10 replicates (not the paper's)
#
# --centroids FILE (or QDMETA_AUTHORS_CENTROIDS=FILE), study authors: the authors' centroid file
# centroids_10000_20.dat, which the repository does not hold (docs/fidelity.md says where to get
# it). It is copied to results/authors-centroids/centroids_10000_20.dat, where the experiment file
# reads it; once there, later calls need not name it again. A file whose SHA-256 is not the
# authors' is used with a warning (qdmeta itself refuses one of the wrong shape).
#
# Each run of the range (default: every replicate of the study) writes its summary (kilobytes:
# the numbers and curves the report needs, tools/runs.py) the moment it finishes, with its test
# phases, into RESULTS/summaries/<condition>/seed-<r>.json, beside RESULTS/summaries/
# experiment.toml; commit them as they come. A run whose summary is there is skipped, here or on
# a fresh clone; a run whose directory (WORK/seed-<r>/<condition>/seed-<r>) holds a checkpoint
# is resumed, so an interrupted call loses at most the unfinished runs' progress since their last
# checkpoint, and only on the machine that ran them. Then the study's report (RESULTS/report.md,
# figures/, data/) is built from the summaries present, whatever replicates they are; the script
# says how many. --report-only runs nothing: it refreshes RESULTS/summaries/experiment.toml from
# the experiment file (e.g. after its claims changed) and rebuilds the report.
#
# --conditions runs only the named conditions (their directory names, e.g. cvt-map-elites,aurora)
# of each replicate: the short ones fill the last hour of a session that a long run would not
# finish in (bench/README.md lists each condition's time).
#
# Defaults: --evals 100000000; --jobs 2 (replicates in parallel, one thread each: whole runs in
# parallel scale better than threads inside one run, and every run gives the same bits at any
# thread count); --work results/rastrigin-study/<budget>/<study>; --results
# docs/results/rastrigin/<budget>/<study>, <budget> being the evaluations as 100m, 10m, 20k, ...
# Summaries made with another budget, config or tests are refused (qdmeta experiment --summaries).
# --config runs another experiment file under the study's name (tests/scripts/rastrigin_study_test.sh).
# Paths given are from the current folder; the defaults are in the repository.
set -euo pipefail
caller=$PWD
cd "$(dirname "$0")/.."
BIN=${QDMETA:-build/qdmeta}
usage() { sed -n '6,8p' "$0" | sed 's/^# *//' >&2; exit 2; }
fail() { echo "rastrigin-study: $*" >&2; exit 2; }
from_caller() { [[ -z $1 || $1 == /* ]] && echo "$1" || echo "$caller/$1"; }

study='' replicates='' conditions='' evals=100000000 jobs=2 work='' results='' report_only=0 config=
centroids=${QDMETA_AUTHORS_CENTROIDS:+$(from_caller "$QDMETA_AUTHORS_CENTROIDS")}
while (( $# )); do
  case $1 in
    --study) study=${2:-}; shift 2 || usage ;;
    --replicates) replicates=${2:-}; shift 2 || usage ;;
    --conditions) conditions=${2:-}; shift 2 || usage ;;
    --evals) evals=${2:-}; shift 2 || usage ;;
    --jobs) jobs=${2:-}; shift 2 || usage ;;
    --work) work=$(from_caller "${2:-}"); shift 2 || usage ;;
    --results) results=$(from_caller "${2:-}"); shift 2 || usage ;;
    --report-only) report_only=1; shift ;;
    --config) config=$(from_caller "${2:-}"); shift 2 || usage ;;
    --centroids) centroids=$(from_caller "${2:-}"); shift 2 || usage ;;
    *) usage ;;
  esac
done
case $study in
  paper) config=${config:-configs/rastrigin/experiment.toml} ;;
  lambda) config=${config:-configs/rastrigin/experiment-lambda.toml} ;;
  lambda-stated-sd) config=${config:-configs/rastrigin/experiment-lambda-stated-sd.toml} ;;
  stated-sd) config=${config:-configs/rastrigin/experiment-stated-sd.toml} ;;
  authors) config=${config:-configs/rastrigin/experiment-authors.toml} ;;
  cma-mae-inner) config=${config:-configs/rastrigin/experiment-cma-mae-inner.toml} ;;
  *) echo "rastrigin-study: --study must be paper, lambda, lambda-stated-sd, stated-sd, authors or cma-mae-inner" >&2
     usage ;;
esac
[[ -f $config ]] || fail "$config: no such experiment file"
[[ $evals =~ ^[1-9][0-9]*$ ]] || fail "--evals must be a positive integer"
[[ $jobs =~ ^[1-9][0-9]*$ ]] || fail "--jobs must be a positive integer"
[[ -x $BIN ]] || fail "$BIN not found: build first (make build)"

budget_label() {  # 100000000 -> 100m, 20000 -> 20k
  if (( $1 % 1000000 == 0 )); then echo "$(( $1 / 1000000 ))m"
  elif (( $1 % 1000 == 0 )); then echo "$(( $1 / 1000 ))k"
  else echo "$1"; fi
}
label=$(budget_label "$evals")
work=${work:-results/rastrigin-study/$label/$study}
results=${results:-docs/results/rastrigin/$label/$study}
summaries=$results/summaries
total=$(sed -n 's/^replicates *= *\([0-9][0-9]*\).*/\1/p' "$config" | head -1)
[[ -n $total ]] || fail "$config has no replicates line"
replicates=${replicates:-1-$total}
[[ $replicates =~ ^([1-9][0-9]*)(-([1-9][0-9]*))?$ ]] || fail "--replicates must be A-B or A (1 <= A <= B <= $total)"
first=${BASH_REMATCH[1]} last=${BASH_REMATCH[3]:-${BASH_REMATCH[1]}}
(( first <= last && last <= total )) || fail "--replicates $replicates is not within the study's 1-$total"

# The authors' centroid file where experiment-authors.toml reads it (from the repository root).
authors_centroids=results/authors-centroids/centroids_10000_20.dat
authors_sha256=a1c0c9db8b34418d33d84cb0118345a4841e4b2fa4e57317fc7732e806c17889
if [[ $study == authors ]] && (( ! report_only )); then
  if [[ -n $centroids ]]; then
    [[ -f $centroids ]] || fail "--centroids $centroids: no such file"
    mkdir -p "$(dirname "$authors_centroids")"
    cmp -s "$centroids" "$authors_centroids" 2>/dev/null || cp "$centroids" "$authors_centroids"
  fi
  [[ -f $authors_centroids ]] || fail "--study authors needs the authors' centroid file centroids_10000_20.dat:" \
    "give --centroids FILE or QDMETA_AUTHORS_CENTROIDS=FILE (docs/fidelity.md, CVT-MAP-Elites, says where to get it)"
  sum=$(sha256sum "$authors_centroids" | cut -d' ' -f1)
  [[ $sum == "$authors_sha256" ]] \
    || echo "rastrigin-study: warning: $authors_centroids is not the authors' file (SHA-256 $sum)" >&2
fi

if (( ! report_only )); then
  mkdir -p "$work"
  echo "rastrigin-study: $study, replicates $first-$last of $total${conditions:+ ($conditions only)}," \
       "$evals evaluations, $jobs at a time" \
       "(logs in $work/seed-<r>.log, summaries into $summaries)"
  declare -A seed_of=()  # the experiment running each replicate, by process id
  launch() {  # one replicate: every condition, its tests, each run's summary as it finishes
    "$BIN" experiment --config "$config" --out "$work/seed-$1" --seeds "$1" --evals "$evals" --threads 1 \
      --summaries "$summaries" --no-report ${conditions:+--conditions "$conditions"} > "$work/seed-$1.log" 2>&1 &
    seed_of[$!]=$1
  }
  reap() {  # waits for one replicate; its exit status
    local pid status=0
    wait -n -p pid || status=$?
    local r=${seed_of[$pid]}
    unset "seed_of[$pid]"
    if (( status == 0 )); then
      echo "rastrigin-study: seed $r done ($(tail -1 "$work/seed-$r.log"); $(date -u +%H:%M:%S))"
    else
      echo "rastrigin-study: seed $r stopped (exit $status):" \
           "$(grep -m 1 '^qdmeta: error: ' "$work/seed-$r.log" || tail -1 "$work/seed-$r.log")" >&2
    fi
    return "$status"
  }
  # Ctrl-C or a kill: the runs write a checkpoint and stop (qdmeta handles SIGINT and SIGTERM).
  trap 'kill -TERM "${!seed_of[@]}" 2>/dev/null; wait; exit 130' INT TERM
  start=$(date +%s) status=0
  for (( r = first; r <= last; r++ )); do
    (( ${#seed_of[@]} < jobs )) || reap || status=$?
    launch "$r"
  done
  while (( ${#seed_of[@]} > 0 )); do
    reap || status=$?
  done
  trap - INT TERM
  (( status == 0 )) || fail "a replicate failed (exit $status): its log is in $work; rerun the same command to continue"
  echo "rastrigin-study: replicates $first-$last finished in $(( $(date +%s) - start )) s"
else
  # The experiment file in force (its claims may have changed): --plan runs nothing.
  plan=$(mktemp -d)
  trap 'rm -rf "$plan"' EXIT
  "$BIN" experiment --config "$config" --out "$plan" --evals "$evals" --summaries "$summaries" --plan --quiet
fi

[[ -f $summaries/experiment.toml ]] || fail "no summaries in $summaries yet: run a replicate range first"
present=()
for d in "$summaries"/*/; do
  present+=("$(basename "$d") $(find "$d" -maxdepth 1 -name 'seed-*.json' | wc -l)")
done
"$BIN" report "$summaries" --out "$results" --quiet
echo "rastrigin-study: $results/report.md from the summaries present of $total replicates per condition:" \
     "$(IFS=,; echo "${present[*]}" | sed 's/,/, /g')"

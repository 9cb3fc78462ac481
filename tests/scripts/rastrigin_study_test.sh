#!/bin/bash
# scripts/rastrigin-study.sh end to end at a tiny budget: a replicate range, then another; a
# replicate killed after a run's first checkpoint and continued from its directory; another
# machine (a fresh work folder and a copy of the committed summaries, nothing else) that skips
# every kept run and adds a replicate; the report from whatever summaries are present; a budget
# that does not match the kept summaries refused; one condition of a replicate alone
# (--conditions). A study of two small conditions (QD-Meta and MAP-Elites, --config) stands in
# for the paper's, whose CVT-MAP-Elites spends minutes on its centroids on a machine that has not
# cached them. Last, --study authors on the committed configs/rastrigin/experiment-authors.toml:
# refused without the authors' centroid file (which the repository does not hold); run with a
# generated file of the same shape (a warning says it is not the authors'), which the script puts
# where the experiment file reads it; a file of the wrong shape refused by qdmeta naming the key.
# That part runs the script in a copy of its folder layout, so that the copied centroid file lands
# in the temporary folder, not in the checkout.
# Usage: rastrigin_study_test.sh QDMETA_BINARY SOURCE_DIR
set -euo pipefail
bin=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

export QDMETA=$bin QDMETA_TOOLS_DIR=$src/tools
evals=20000
printf '%s\n' 'algorithm = "qd-meta"' '[checkpoint]' 'every_seconds = 0' '[qd_meta]' 'database_capacity = 100_000' \
  > "$tmp/qd-meta.toml"
printf '%s\n' 'name = "Two conditions"' 'replicates = 6' 'tests = ["dimension", "translation"]' \
  '[[condition]]' 'name = "QD-Meta"' 'config = "qd-meta.toml"' \
  '[[condition]]' 'name = "MAP-Elites"' "config = \"$src/configs/rastrigin/map-elites.toml\"" \
  '[[claim]]' 'text = "MAP-Elites stays under a billion elites"' 'kind = "below"' \
  'measure = "population:num_elites"' 'conditions = ["MAP-Elites"]' 'value = 1e9' > "$tmp/study.toml"
study() { "$src/scripts/rastrigin-study.sh" --study paper --config "$tmp/study.toml" --evals "$evals" "$@"; }
count() { find "$1/summaries" -name 'seed-*.json' | wc -l; }
here=$tmp/here/results there=$tmp/there/results

out=$(study --replicates 1-2 --work "$tmp/here/work" --results "$here") || fail "replicates 1-2: $out"
[[ $(count "$here") == 4 ]] || fail "replicates 1-2 kept $(count "$here") summaries, not 2 conditions x 2"
[[ $out == *"from the summaries present of 6 replicates per condition: map-elites 2, qd-meta 2" ]] \
  || fail "the count of replicates present: $out"
grep -q "^8 of 12 runs are not finished and are left out" "$here/report.md" || fail "report.md: $(head -5 "$here/report.md")"
grep -q "| MAP-Elites | 2 |" "$here/report.md" || fail "report.md has no MAP-Elites row of 2 replicates"
grep -q "| MAP-Elites stays under a billion elites | MAP-Elites .* | \*\*reproduced\*\* |" "$here/report.md" \
  || fail "report.md has no verdict"
grep -q "config = 'qd-meta.toml'" "$here/summaries/experiment.toml" \
  || fail "the kept experiment.toml names its configs as written: $(cat "$here/summaries/experiment.toml")"

out=$(study --replicates 3 --work "$tmp/here/work" --results "$here") || fail "replicate 3: $out"
[[ $(count "$here") == 6 ]] || fail "replicate 3: $(count "$here") summaries"

# Killed (SIGKILL) right after the first checkpoint of its first run: nothing of replicate 4 is
# kept, its first run's directory holds the checkpoint; the same command resumes it.
if out=$(QDMETA_TEST_SIGNAL_AT_CHECKPOINT=1:KILL study --replicates 4 --work "$tmp/here/work" --results "$here" 2>&1); then
  fail "the killed replicate reported success: $out"
fi
[[ $(count "$here") == 6 ]] || fail "a killed replicate kept a summary"
[[ -f $tmp/here/work/seed-4/qd-meta/seed-4/checkpoint.bin ]] || fail "no checkpoint left by the killed run"
out=$(study --replicates 4 --work "$tmp/here/work" --results "$here") || fail "replicate 4 continued: $out"
grep -q "2 runs finished now, 1 resumed, 0 already finished" "$tmp/here/work/seed-4.log" \
  || fail "replicate 4 did not resume its run: $(cat "$tmp/here/work/seed-4.log")"
[[ $(count "$here") == 8 ]] || fail "replicate 4: $(count "$here") summaries"

# Another machine: the committed summaries only.
mkdir -p "$there"
cp -r "$here/summaries" "$there/"
out=$(study --replicates 1-5 --work "$tmp/there/work" --results "$there") || fail "replicates 1-5 elsewhere: $out"
for r in 1 2 3 4; do
  grep -q "0 summaries written, 2 runs skipped" "$tmp/there/work/seed-$r.log" \
    || fail "replicate $r was not skipped: $(cat "$tmp/there/work/seed-$r.log")"
  [[ ! -e $tmp/there/work/seed-$r/map-elites/seed-$r ]] || fail "replicate $r made a run directory"
done
[[ $(count "$there") == 10 ]] || fail "replicate 5 elsewhere: $(count "$there") summaries"
grep -q "^2 of 12 runs are not finished" "$there/report.md" || fail "report.md: $(head -5 "$there/report.md")"
for f in "$here"/summaries/*/seed-*.json; do
  cmp -s "$f" "$there/summaries/${f#"$here"/summaries/}" || fail "$f changed elsewhere"
done

# The report again, from the summaries alone: the same bytes.
cp -r "$there/report.md" "$there/data" "$there/figures" "$tmp/"
study --report-only --work "$tmp/there/work" --results "$there" > /dev/null || fail "--report-only"
for f in report.md data/runs.csv data/curves.csv figures/qd-statistics.png figures/archives.png; do
  cmp -s "$tmp/$f" "$there/$f" || fail "--report-only changed $f"
done

# Summaries of another budget are refused, not mixed.
if out=$(evals=5000 study --replicates 6 --work "$tmp/there/work" --results "$there" 2>&1); then
  fail "a budget of 5000 evaluations was mixed with summaries of $evals"
fi
[[ $out == *"its summaries were made with evaluations = $evals, this experiment has evaluations = 5000"* ]] \
  || fail "the refusal: $out"
[[ $(count "$there") == 10 ]] || fail "the refused call kept a summary"

# Only the short condition of a replicate (--conditions): its summary alone is kept.
out=$(study --replicates 6 --conditions map-elites --work "$tmp/there/work" --results "$there") \
  || fail "replicate 6, map-elites only: $out"
[[ -f $there/summaries/map-elites/seed-6.json && ! -e $there/summaries/qd-meta/seed-6.json ]] \
  || fail "--conditions map-elites kept: $(ls "$there"/summaries/*/seed-6.json 2>&1)"
[[ ! -e $tmp/there/work/seed-6/qd-meta ]] || fail "--conditions map-elites made a QD-Meta run"

# --study authors (see the top).
unset QDMETA_AUTHORS_CENTROIDS
repo=$tmp/repo
mkdir -p "$repo/scripts" "$repo/configs"
cp "$src/scripts/rastrigin-study.sh" "$repo/scripts/"
cp -r "$src/configs/rastrigin" "$repo/configs/"
study() { "$repo/scripts/rastrigin-study.sh" --study authors --evals 20000 --work "$tmp/authors/work" --results "$tmp/authors/results" "$@"; }
placed=$repo/results/authors-centroids/centroids_10000_20.dat

if out=$(study --replicates 1 2>&1); then fail "ran without the centroid file: $out"; fi
[[ $out == *"--study authors needs the authors' centroid file centroids_10000_20.dat: give --centroids FILE"* ]] \
  || fail "the refusal without a file: $out"

# 10,000 x 20 numbers in [0.1, 0.9], the shape of the authors' file.
awk 'BEGIN { srand(7); for (i = 0; i < 10000; i++) { for (j = 0; j < 20; j++) printf "%.6f ", 0.1 + 0.8 * rand(); print "" } }' \
  > "$tmp/centroids.dat"
out=$(study --replicates 1 --centroids "$tmp/centroids.dat" 2>&1) || fail "replicate 1: $out"
[[ $out == *"warning: results/authors-centroids/centroids_10000_20.dat is not the authors' file"* ]] \
  || fail "no warning for a file that is not the authors': $out"
cmp -s "$tmp/centroids.dat" "$placed" || fail "the file was not put where the experiment file reads it"
[[ $(find "$tmp/authors/results/summaries" -name 'seed-1.json' | wc -l) == 5 ]] || fail "not 5 summaries: $out"
for claim in "lambda = 1 yields a meta-fitness of only 900,000" "CVT-MAP-Elites yields just below 3,000 solutions" \
             "QD-Meta's average fitness is about -100"; do
  grep -q "| $claim" "$tmp/authors/results/report.md" || fail "report.md has no claim '$claim'"
done

# Once placed, the file need not be named again; a file of the wrong shape is refused by qdmeta.
head -10 "$tmp/centroids.dat" > "$tmp/short.dat"
if out=$(QDMETA_AUTHORS_CENTROIDS=$tmp/short.dat study --replicates 2 --conditions cvt-map-elites-authors-centroids 2>&1); then
  fail "a 10-line centroid file was accepted: $out"
fi
[[ $out == *"cvt.centroids_file = \"results/authors-centroids/centroids_10000_20.dat\": 10 centroids, expected 10000 (cvt.centroids)"* ]] \
  || fail "the refusal of a short file: $out"
echo "rastrigin study script: ok"

#!/bin/bash
# scripts/rastrigin-study.sh --study authors at a tiny budget, on the committed
# configs/rastrigin/experiment-authors.toml: refused without the authors' centroid file (which the
# repository does not hold); run with a generated file of the same shape (a warning says it is not
# the authors'), which the script puts where the experiment file reads it; a file of the wrong
# shape refused by qdmeta naming the key. The script runs in a copy of its folder layout, so that
# the copied centroid file lands in the temporary folder, not in the checkout.
# Usage: authors_study_test.sh QDMETA_BINARY SOURCE_DIR
set -euo pipefail
bin=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

export QDMETA=$bin QDMETA_TOOLS_DIR=$src/tools
unset QDMETA_AUTHORS_CENTROIDS
repo=$tmp/repo
mkdir -p "$repo/scripts" "$repo/configs"
cp "$src/scripts/rastrigin-study.sh" "$repo/scripts/"
cp -r "$src/configs/rastrigin" "$repo/configs/"
study() { "$repo/scripts/rastrigin-study.sh" --study authors --evals 20000 --work "$tmp/work" --results "$tmp/results" "$@"; }
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
[[ $(find "$tmp/results/summaries" -name 'seed-1.json' | wc -l) == 5 ]] || fail "not 5 summaries: $out"
for claim in "lambda = 1 yields a meta-fitness of only 900,000" "CVT-MAP-Elites yields just below 3,000 solutions" \
             "QD-Meta's average fitness is about -100"; do
  grep -q "| $claim" "$tmp/results/report.md" || fail "report.md has no claim '$claim'"
done

# Once placed, the file need not be named again; a file of the wrong shape is refused by qdmeta.
head -10 "$tmp/centroids.dat" > "$tmp/short.dat"
if out=$(QDMETA_AUTHORS_CENTROIDS=$tmp/short.dat study --replicates 2 --conditions cvt-map-elites-authors-centroids 2>&1); then
  fail "a 10-line centroid file was accepted: $out"
fi
[[ $out == *"cvt.centroids_file = \"results/authors-centroids/centroids_10000_20.dat\": 10 centroids, expected 10000 (cvt.centroids)"* ]] \
  || fail "the refusal of a short file: $out"
echo "authors study script: ok"

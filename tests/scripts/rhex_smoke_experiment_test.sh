#!/bin/bash
# configs/rhex/experiment-smoke.toml end to end: every run, the damage, obstacle and
# generalisation tests, and the report's RHex outputs (Table 2 with its bold best and underlined
# training groups, the recovery curves, Figs S4 and S5, the claims table).
# Usage: rhex_smoke_experiment_test.sh QDMETA_BINARY SOURCE_DIR
set -euo pipefail
bin=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

export QDMETA_TOOLS_DIR=$src/tools XDG_CACHE_HOME=$tmp/cache
"$bin" experiment --config "$src/configs/rhex/experiment-smoke.toml" --out "$tmp/x" --threads 2 --quiet \
  || fail "the experiment failed"
for c in qd-meta-damage-feature-sets qd-meta-obstacle-feature-sets aurora cvt-map-elites; do
  for r in 1 2; do
    d=$tmp/x/$c/seed-$r
    for f in archive.csv adapt-damage.csv adapt-obstacle.csv generalisation.csv; do
      [[ -s $d/$f ]] || fail "$d has no $f"
    done
    # Two solutions drawn for the generalisation test, in each of the 4 groups.
    [[ $(awk -F, 'NR > 1 && $3 == 2' "$d/generalisation.csv" | wc -l) == 4 ]] || fail "$d/generalisation.csv: $(cat "$d/generalisation.csv")"
  done
done
report=$tmp/x/report.md
[[ -s $report ]] || fail "no report.md"
grep -q "Generalisation test (Table 2)" "$report" || fail "report.md has no Table 2"
# The trained groups are underlined: Training-Damages for the Damage condition, Training-Obstacles for Obstacle.
grep "^| Training-Damages" "$report" | awk -F'|' '{exit !($3 ~ /<u>/ && $4 !~ /<u>/ && $5 !~ /<u>/ && $6 !~ /<u>/)}' \
  || fail "Training-Damages row: $(grep '^| Training-Damages' "$report")"
grep "^| Training-Obstacles" "$report" | awk -F'|' '{exit !($4 ~ /<u>/ && $3 !~ /<u>/)}' \
  || fail "Training-Obstacles row: $(grep '^| Training-Obstacles' "$report")"
for row in Training-Damages Training-Obstacles Test-Damages Test-Obstacles; do
  grep "^| $row" "$report" | grep -q '\*\*' || fail "the $row row has no bold best"
done
# Fig S5 from the Obstacle condition, whose G SARSA chooses.
for f in qd-statistics adaptation-damage adaptation-obstacle meta-fitness-running-average generations-and-meta-fitness; do
  [[ -s $tmp/x/figures/$f.png ]] || fail "no figures/$f.png"
done
[[ $(wc -l < "$tmp/x/data/generalisation.csv") == 17 ]] || fail "data/generalisation.csv: 4 conditions x 4 groups expected"
grep -q "QD-Meta generalises better than both baselines" "$report" || fail "the claims table is missing"
# The Damage condition's replicates draw their training damages from their seeds
# (meta_fitness.damage_types): one condition, one config fingerprint, so the same command runs
# again (every run kept) instead of calling seed 2 another config.
grep -q "damage_types = \[" "$tmp/x/qd-meta-damage-feature-sets/seed-1/config.toml" || fail "no drawn damage_types"
[[ $(grep -h config_fingerprint "$tmp"/x/qd-meta-damage-feature-sets/seed-*/config.toml | sort -u | wc -l) == 1 ]] \
  || fail "the Damage condition's replicates carry different config fingerprints"
"$bin" experiment --config "$src/configs/rhex/experiment-smoke.toml" --out "$tmp/x" --threads 2 --quiet --no-report \
  || fail "the same experiment, run again, was refused"
echo "rhex smoke experiment: ok"

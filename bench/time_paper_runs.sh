#!/bin/bash
# Times the paper's Rastrigin conditions as full runs (100,000,000 bottom-level evaluations each,
# the shipped configs) and prints one line per run: wall and CPU seconds, peak memory, and what
# the run reached (meta-generations, elites). Run it on a quiet machine; one run at a time.
#   bench/time_paper_runs.sh [QDMETA_BINARY] [OUT_DIR] [THREADS] [CONDITION...]
# CONDITION is a config name under configs/rastrigin/ without .toml, optionally with keys to
# change after a colon, as an experiment's `set` does: qdmeta-translation-static:
# mutation.sigma=0.0025,qd_meta.meta_population=1 (section.key=value, comma-separated; the key
# must be in the config). The default is the paper's four: qdmeta-translation qdmeta-dimension
# cvt-map-elites aurora. Set EVALS to time a smaller budget. The CVT condition reads its 10,000 centroids from the cache ($XDG_CACHE_HOME or
# ~/.cache/qdmeta/centroids) when an earlier run made them; the line says whether the cache held
# them before the run (else the time includes the k-means).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
bin=${1:-$root/build/qdmeta}
out=${2:-/tmp/qdmeta-paper-runs}
threads=${3:-2}
shift $(($# < 3 ? $# : 3))
conditions=("$@")
[[ ${#conditions[@]} -gt 0 ]] || conditions=(qdmeta-translation qdmeta-dimension cvt-map-elites aurora)
evals=()
[[ -n ${EVALS:-} ]] && evals=(--evals "$EVALS")
mkdir -p "$out"
for spec in "${conditions[@]}"; do
  name=${spec%%:*}
  config=$root/configs/rastrigin/$name.toml
  [[ -f $config ]] || { echo "no config $config" >&2; exit 1; }
  c=$name
  if [[ $spec == *:* ]]; then
    # The changed config beside the results: each section.key=value replaces that key's value.
    c=$name-$(echo "${spec#*:}" | tr ',=.' '__-')
    changed=$out/$c.toml
    cp "$config" "$changed"
    IFS=, read -ra sets <<< "${spec#*:}"
    for set in "${sets[@]}"; do
      section=${set%%.*} rest=${set#*.}
      key=${rest%%=*} value=${rest#*=}
      awk -v section="[$section]" -v key="$key" -v value="$value" '
        /^\[/ { inside = ($1 == section) }
        inside && $1 == key && $2 == "=" { sub(/=[^#]*/, "= " value " "); found = 1 }
        { print }
        END { if (!found) { print "no key " key " in " section > "/dev/stderr"; exit 1 } }' "$changed" > "$changed.new"
      mv "$changed.new" "$changed"
    done
    config=$changed
  fi
  cache=${XDG_CACHE_HOME:-$HOME/.cache}/qdmeta/centroids
  cached=""
  [[ $name == cvt* ]] && cached=$([[ -n $(ls -A "$cache" 2>/dev/null) ]] && echo ", centroids from the cache" || echo ", k-means included")
  /usr/bin/time -o "$out/$c.time" -f "%e %U %S %M" \
    "$bin" run --config "$config" --threads "$threads" --out "$out/$c" --overwrite "${evals[@]}" > "$out/$c.log" 2>&1
  read -r wall user sys rss < "$out/$c.time"
  reached=$(grep -m1 '^reached the budget' "$out/$c.log" || tail -1 "$out/$c.log")
  metagens=""
  [[ -f $out/$c/meta.csv ]] && metagens=", $(($(wc -l < "$out/$c/meta.csv") - 1)) meta-generations"
  printf '%s: %s s wall (%.0f min %02.0f s), %s s user + %s s system, %.0f MB peak%s%s\n  %s\n' \
    "$c" "$wall" "$(echo "$wall / 60" | bc)" "$(echo "$wall % 60" | bc)" "$user" "$sys" "$(echo "$rss / 1024" | bc)" \
    "$metagens" "$cached" "$reached"
done

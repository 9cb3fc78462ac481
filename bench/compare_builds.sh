#!/usr/bin/env bash
# The hot-path benchmarks of two builds, interleaved on this machine (old, new, old, new, ...), so
# that noise from other jobs hits both alike: per benchmark, the median real time of each build
# over N rounds and their ratio new/old. Single-threaded benchmarks run pinned to CPU 1.
#   bench/compare_builds.sh OLD_BUILD NEW_BUILD [N]     (build directories holding bench/)
# A benchmark either build lacks is skipped with a note. Needs python3 for the table.
set -euo pipefail
old=$1 new=$2 rounds=${3:-3}
# binary|filter: the loops a run spends its time in (bench/README.md says what each measures).
benches=(
  "mutation_bench|^BM_GaussianMutation$"
  "mutation_bench|^BM_DiscreteStepMutation$"
  "grid_archive_bench|^BM_GridArchiveAdd$"
  "map_elites_bench|^BM_MapElitesRastrigin/1/"
  "cvt_map_elites_bench|^BM_CvtMapElitesRastrigin/search:0/threads:1/"
  "rebuild_bench|^BM_RebuildTen/threads:1/trend:1/"
  "aurora_bench|^BM_AuroraRastrigin/400000/"
)
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
for round in $(seq "$rounds"); do
  for entry in "${benches[@]}"; do
    binary=${entry%%|*} filter=${entry#*|}
    for side in old new; do
      dir=${!side}
      [[ -x $dir/bench/$binary ]] || { echo "compare_builds: no $dir/bench/$binary" >&2; continue; }
      taskset -c 1 "$dir/bench/$binary" --benchmark_filter="$filter" --benchmark_format=json \
        > "$out/$side-$binary-$round-$(echo "$filter" | tr -c 'A-Za-z0-9' _).json" 2>/dev/null || true
    done
  done
done
python3 - "$out" <<'PY'
import json, pathlib, statistics, sys
times = {}
for f in pathlib.Path(sys.argv[1]).glob("*.json"):
    side = f.name.split("-", 1)[0]
    try:
        data = json.loads(f.read_text())
    except ValueError:
        continue
    for b in data.get("benchmarks", []):
        if b.get("error_occurred"):
            continue
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[b["time_unit"]]
        times.setdefault(b["name"], {}).setdefault(side, []).append(b["real_time"] * scale)
print("| benchmark | old (ms, median) | new (ms, median) | new / old | rounds |")
print("|---|---|---|---|---|")
for name in sorted(times):
    t = times[name]
    if "old" not in t or "new" not in t:
        print(f"| {name} | {'-' if 'old' not in t else ''} | {'-' if 'new' not in t else ''} | missing in one build | |")
        continue
    o, n = statistics.median(t["old"]), statistics.median(t["new"])
    print(f"| {name} | {o:.4g} | {n:.4g} | {n / o:.3f} | {min(len(t['old']), len(t['new']))} |")
PY

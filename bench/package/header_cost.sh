#!/usr/bin/env bash
# What qdmeta's public headers cost a program built against an installed qdmeta: for each file of
# bench/package (task_only.cpp, library_user.cpp), compiled with exactly the command CMake gives a
# consumer of find_package(qdmeta) (the package's interface flags included), the preprocessed size
# (`-E | wc -l`) and the parse time (`-fsyntax-only`, best of 3 runs). Prints markdown table rows.
# Usage: bench/package/header_cost.sh PREFIX [LABEL] [EXTRA_CXX_FLAGS]
#   PREFIX: a `cmake --install` prefix; LABEL: the table's first column; EXTRA_CXX_FLAGS: the
#   consumer's own flags (e.g. -march=native).
set -euo pipefail

here=$(cd "$(dirname "$0")" && pwd)
prefix=$(cd "$1" && pwd)
label=${2:-$prefix}
extra=${3:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

cmake -S "$here" -B "$work" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
      -DCMAKE_CXX_FLAGS="$extra" > "$work/configure.log" 2>&1 || { cat "$work/configure.log"; exit 1; }

for file in task_only.cpp library_user.cpp; do
  # The consumer's compile command for this file, with its output and -c step taken out.
  command=$(python3 - "$work/compile_commands.json" "$file" <<'PY'
import json, shlex, sys
entries = json.load(open(sys.argv[1]))
entry = next(e for e in entries if e["file"].endswith("/" + sys.argv[2]))
words = shlex.split(entry["command"])
out = []
skip = False
for w in words:
    if skip:
        skip = False
        continue
    if w in ("-o", "-c"):
        skip = w == "-o"
        continue
    out.append(w)
print(shlex.join(out))
PY
)
  lines=$(cd "$work" && eval "$command -E" | wc -l)
  best=
  for _ in 1 2 3; do
    start=$(date +%s.%N)
    (cd "$work" && eval "$command -fsyntax-only")
    end=$(date +%s.%N)
    best=$(python3 -c "t = $end - $start; b = '$best'; print(f'{min(t, float(b)) if b else t:.2f}')")
  done
  flags=$(python3 - "$command" <<'PY'
import shlex, sys
keep = [w for w in shlex.split(sys.argv[1]) if w.startswith(("-march", "-DEIGEN", "-DBOOST"))]
print(" ".join(keep) or "(none)")
PY
)
  printf '| %s | %s | %s | %s s | `%s` |\n' "$label" "$file" "$(printf "%'d" "$lines")" "$best" "$flags"
done

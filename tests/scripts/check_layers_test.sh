#!/bin/bash
# scripts/check-layers.py refuses what docs/architecture.md's layer order forbids: in a copy of
# the sources, an upward include, an include within one layer, an include of a folder the order
# does not know, and a folder the order does not place are each refused with the file and line;
# the unchanged copy passes, and so does a downward include.
# Usage: check_layers_test.sh PYTHON SOURCE_DIR
set -euo pipefail
python=$1 src=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

fresh_copy() {
  rm -rf "$tmp/repo"
  mkdir -p "$tmp/repo/docs" "$tmp/repo/src" "$tmp/repo/python"
  cp "$src/docs/architecture.md" "$tmp/repo/docs/"
  cp -r "$src/src/qdmeta" "$tmp/repo/src/"
  cp -r "$src/python/src" "$tmp/repo/python/"
}

# expect_refusal FILE LINE_TO_APPEND EXPECTED_OUTPUT_LINE
expect_refusal() {
  fresh_copy
  mkdir -p "$(dirname "$tmp/repo/$1")"
  echo "$2" >> "$tmp/repo/$1"
  local lines out rc=0
  lines=$(wc -l < "$tmp/repo/$1")
  out=$("$python" "$src/scripts/check-layers.py" "$tmp/repo") || rc=$?
  [[ $rc == 1 ]] || fail "$1 + '$2': exit status $rc, expected 1; output: $out"
  local expected=${3//@LINE@/$lines}
  grep -qxF "$expected" <<< "$out" || fail "$1 + '$2': expected the line
$expected
got:
$out"
}

fresh_copy
"$python" "$src/scripts/check-layers.py" "$tmp/repo" > "$tmp/out" || fail "the sources as they are: $(cat "$tmp/out")"

expect_refusal src/qdmeta/core/types.hpp '#include "qdmeta/run/run.hpp"' \
  'src/qdmeta/core/types.hpp:@LINE@: core includes qdmeta/run/run.hpp, a higher layer (layer 7 >= 0)'
expect_refusal src/qdmeta/io/csv.cpp '#include <qdmeta/algorithms/algorithm.hpp>' \
  'src/qdmeta/io/csv.cpp:@LINE@: io includes qdmeta/algorithms/algorithm.hpp, a higher layer (layer 5 >= 2)'
expect_refusal src/qdmeta/tasks/rastrigin/rastrigin.cpp '  #  include "qdmeta/algorithms/map_elites.hpp"' \
  'src/qdmeta/tasks/rastrigin/rastrigin.cpp:@LINE@: tasks includes qdmeta/algorithms/map_elites.hpp, the same layer (layer 5 >= 5)'
expect_refusal src/qdmeta/algorithms/algorithm.hpp '#include "qdmeta/eval/evaluator.hpp"' \
  'src/qdmeta/algorithms/algorithm.hpp:@LINE@: algorithms includes qdmeta/eval/evaluator.hpp, the same layer (layer 5 >= 5)'
expect_refusal src/qdmeta/plugin/config.hpp '#include "qdmeta/tasks/rastrigin/rastrigin.hpp"' \
  'src/qdmeta/plugin/config.hpp:@LINE@: plugin includes qdmeta/tasks/rastrigin/rastrigin.hpp, a higher layer (layer 5 >= 4)'
expect_refusal src/qdmeta/run/run.cpp '#include "qdmeta/nowhere/x.hpp"' \
  'src/qdmeta/run/run.cpp:@LINE@: includes qdmeta/nowhere/x.hpp, a folder not in docs/architecture.md'"'"'s layer order'
expect_refusal src/qdmeta/newpart/part.hpp '#include "qdmeta/core/types.hpp"' \
  'src/qdmeta/newpart: folder newpart is not in docs/architecture.md'"'"'s layer order'

# A downward include and a comment that mentions an include pass.
fresh_copy
printf '#include "qdmeta/core/types.hpp"\n// #include "qdmeta/cli/run_cli.hpp"\n' >> "$tmp/repo/src/qdmeta/io/csv.cpp"
"$python" "$src/scripts/check-layers.py" "$tmp/repo" > "$tmp/out" || fail "a downward include was refused: $(cat "$tmp/out")"
echo "check-layers: every planted include refused, the real sources accepted"

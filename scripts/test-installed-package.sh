#!/usr/bin/env bash
# The installed CMake package, end to end (run by `make test` after ctest): installs the build
# into a scratch prefix, builds examples/own-task against it with find_package(qdmeta), and runs
# that program's command line on its own task: QD-Meta and MAP-Elites runs, an interrupted run
# resumed to the same archive, the test phase, an experiment with its report (by the installed
# report.py), a misspelt [task] key refused, and `mpirun -np 2` where the build has MPI.
# Usage: scripts/test-installed-package.sh [BUILD_DIR]   (default: build)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-build}" && pwd)
prefix=$build/install-test
example=$build/own-task-test
jobs=${JOBS:-2}

fail() { echo "test-installed-package: FAILED: $*" >&2; exit 1; }
step() { echo "test-installed-package: $*"; }

step "installing into $prefix"
rm -rf "$prefix" "$example"
cmake --install "$build" --prefix "$prefix" > /dev/null
# plugin/: the config reader and the registries; experiment/config.hpp and task_registry.hpp: their
# 0.1 paths, still included by programs written then.
for f in bin/qdmeta share/qdmeta/tools/report.py include/qdmeta/cli/run_cli.hpp lib/cmake/qdmeta/qdmetaConfig.cmake \
         lib/cmake/qdmeta/qdmetaConfigVersion.cmake include/qdmeta/plugin/config.hpp include/qdmeta/plugin/registry.hpp \
         include/qdmeta/plugin/task_registry.hpp include/qdmeta/experiment/config.hpp \
         include/qdmeta/experiment/task_registry.hpp; do
  [[ -e $prefix/$f ]] || fail "the install lacks $f"
done
"$prefix/bin/qdmeta" --version > /dev/null || fail "the installed qdmeta does not start"

step "building examples/own-task against it"
launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
cmake -S "$root/examples/own-task" -B "$example" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
      "${launcher[@]}" > "$example.configure.log" 2>&1 || { cat "$example.configure.log"; fail "configuring the example"; }
cmake --build "$example" -j "$jobs" > "$example.build.log" 2>&1 || { cat "$example.build.log"; fail "building the example"; }
arm=$example/arm-qd
runs=$example/runs
rm -rf "$runs"

# A finished run of the arm: every result file, and the arm's name in its config and summary.
check_run() {
  local dir=$1
  for f in archive.csv metrics.csv config.toml summary.json; do [[ -s $dir/$f ]] || fail "$dir lacks $f"; done
  python3 - "$dir" <<'PY' || fail "$dir is not a finished run of the arm"
import json, sys, tomllib
d = sys.argv[1]
summary = json.load(open(f"{d}/summary.json"))
config = tomllib.load(open(f"{d}/config.toml", "rb"))
assert config["task"]["name"] == "arm", config["task"]
assert summary["task"] == "arm", summary["task"]
assert summary["stop_reason"] == "budget", summary["stop_reason"]
PY
}

step "QD-Meta and MAP-Elites on the arm"
"$arm" run --config "$root/examples/own-task/configs/qd-meta.toml" --out "$runs/qd-meta" --threads "$jobs" --quiet \
  || fail "arm-qd run (qd-meta)"
check_run "$runs/qd-meta"
[[ -s $runs/qd-meta/meta.csv ]] || fail "the QD-Meta run lacks meta.csv"
"$arm" run --config "$root/examples/own-task/configs/map-elites.toml" --out "$runs/map-elites" --threads "$jobs" --quiet \
  || fail "arm-qd run (map-elites)"
check_run "$runs/map-elites"

step "an interrupted run resumes to the same archive"
config=$runs/checkpointing.toml
sed 's/^evaluations = .*/evaluations = 400_000/' "$root/examples/own-task/configs/map-elites.toml" > "$config"
printf '\n[checkpoint]\nevery_seconds = 0\n' >> "$config"
"$arm" run --config "$config" --out "$runs/straight" --threads 1 --quiet || fail "arm-qd run (straight)"
"$arm" run --config "$config" --out "$runs/stopped" --threads 1 --quiet &
pid=$!
for _ in $(seq 200); do [[ -e $runs/stopped/checkpoint.bin ]] && break; sleep 0.05; done
kill -INT "$pid" 2> /dev/null || true
status=0
wait "$pid" || status=$?
if [[ $status -eq 130 ]]; then
  "$arm" resume --out "$runs/stopped" --threads 2 --quiet || fail "arm-qd resume"
  cmp -s "$runs/straight/archive.csv" "$runs/stopped/archive.csv" || fail "the resumed archive differs from the straight one"
elif [[ $status -eq 0 ]]; then
  echo "test-installed-package: note: the run finished before it was interrupted; resume not exercised"
else
  fail "the interrupted run exited with status $status"
fi

step "the test phase (adapt --test locked)"
"$arm" adapt --run "$runs/map-elites" --test locked --budget 10 --threads "$jobs" --quiet || fail "arm-qd adapt"
[[ -s $runs/map-elites/adapt-locked.csv ]] || fail "adapt wrote no adapt-locked.csv"

step "experiment, and report with the installed report.py"
"$arm" experiment --config "$root/examples/own-task/configs/experiment.toml" --out "$runs/study" --threads "$jobs" \
  --replicates 1 --quiet --no-report || fail "arm-qd experiment"
for run in "$runs/study/qd-meta-locked-joint/seed-1" "$runs/study/map-elites/seed-1"; do
  check_run "$run"
  [[ -s $run/adapt-locked.csv ]] || fail "the experiment ran no test phase in $run"
done
status=0
message=$(env -u QDMETA_TOOLS_DIR "$arm" report "$runs/study" --quiet 2>&1) || status=$?
if "${QDMETA_PYTHON:-/usr/bin/python3}" -c "import matplotlib" 2> /dev/null; then  # the interpreter report uses
  [[ $status -eq 0 && -s $runs/study/report.md ]] || fail "arm-qd report: $message"
else  # no matplotlib here: the installed script was found and ran, which is what is tested
  [[ $message == *"$prefix/share/qdmeta/tools/report.py"* ]] || fail "arm-qd report did not use the installed script: $message"
fi

step "a misspelt [task] key is refused"
bad=$runs/bad.toml
sed 's/^joints = /jionts = /' "$root/examples/own-task/configs/map-elites.toml" > "$bad"
status=0
message=$("$arm" run --config "$bad" --out "$runs/bad" --quiet 2>&1) || status=$?
[[ $status -eq 2 && $message == *"task.jionts"* ]] || fail "a misspelt key gave status $status: $message"

if grep -q 'set(qdmeta_WITH_MPI ON)' "$prefix/lib/cmake/qdmeta/qdmetaConfig.cmake" && command -v mpirun > /dev/null; then
  step "mpirun -np 2: the worker rank builds the arm from its own registry, to the same archive"
  as_root=()
  if [[ $(id -u) -eq 0 ]]; then as_root=(env OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1); fi
  "${as_root[@]}" timeout -k 5 120 mpirun --oversubscribe --mca btl self,vader -np 2 "$arm" run \
    --config "$root/examples/own-task/configs/qd-meta.toml" --out "$runs/qd-meta-mpi" --threads 1 --quiet \
    || fail "mpirun -np 2 arm-qd run"
  check_run "$runs/qd-meta-mpi"
  cmp -s "$runs/qd-meta/archive.csv" "$runs/qd-meta-mpi/archive.csv" || fail "the MPI run's archive differs"
fi

step "passed"

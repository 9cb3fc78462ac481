#!/usr/bin/env bash
# The installed CMake package, end to end (run by `make test` after ctest): installs the build
# into a scratch prefix and checks that it serves any consumer: no instruction-set or DART flag in
# its targets' interface, Eigen's settings in it (a consumer may include Eigen first), no DART in
# its headers; a program built for the x86-64 baseline (the library is built with -march=native)
# that includes Eigen before qdmeta and asks for no component, configured where DART and MPI
# cannot be found, runs QD-Meta and MAP-Elites to the archives of the installed `qdmeta`, freeing
# the library's elite tables; a component the installation lacks, or that names nothing, is
# refused in one message, and so is a target that links a component not asked for or uses run_cli without
# qdmeta::cli. Then it builds
# examples/own-task against it (also for the baseline) with find_package(qdmeta), and runs that
# program's command line on its own task: QD-Meta and MAP-Elites runs, an interrupted run resumed
# to the same archive, arm-parts (the task handed to build_run as a value, reading its own [task]
# keys) killed at a checkpoint and resumed to arm-qd's archive, the program's own mutation operator (SBX, checked against its
# definition by sbx-check) and algorithm (random search, killed at a checkpoint and resumed to the
# uninterrupted run's archive) and controller of G ("cycle": its schedule in meta.csv, killed at a
# checkpoint and resumed to the same files), feature-map ("polar": each elite's measures
# recomputed from its genes) and archive ("floor": no elite below it, killed and resumed), the test phase, an experiment with its report (by the installed
# report.py), misspelt [task] and [mutation] keys refused, and `mpirun -np 2` where the build has MPI.
# Usage: scripts/test-installed-package.sh [BUILD_DIR]   (default: build)
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-build}" && pwd)
prefix=$build/install-test
example=$build/own-task-test
consumer=$build/portable-consumer-test
jobs=${JOBS:-2}
# What a program built for any x86-64 CPU is compiled with (no -march reaches it from qdmeta).
portable="-march=x86-64 -mtune=generic"

fail() { echo "test-installed-package: FAILED: $*" >&2; exit 1; }
step() { echo "test-installed-package: $*"; }

step "installing into $prefix"
rm -rf "$prefix" "$example" "$consumer"
cmake --install "$build" --prefix "$prefix" > /dev/null
package=$prefix/lib/cmake/qdmeta
# plugin/: the config reader and the registries; experiment/config.hpp and task_registry.hpp: their
# 0.1 paths, still included by programs written then.
for f in bin/qdmeta share/qdmeta/tools/report.py include/qdmeta/cli/run_cli.hpp lib/cmake/qdmeta/qdmetaConfig.cmake \
         lib/cmake/qdmeta/qdmetaConfigVersion.cmake include/qdmeta/plugin/config.hpp include/qdmeta/plugin/registry.hpp \
         include/qdmeta/plugin/task_registry.hpp include/qdmeta/experiment/config.hpp \
         include/qdmeta/experiment/task_registry.hpp include/qdmeta/core/eigen.hpp; do
  [[ -e $prefix/$f ]] || fail "the install lacks $f"
done
"$prefix/bin/qdmeta" --version > /dev/null || fail "the installed qdmeta does not start"

step "no flag of the building machine or of DART reaches a consumer; Eigen's settings do"
if grep -nE -- '-march|-mtune|BOOST_TEST_DYN_LINK' "$package"/qdmeta*Targets*.cmake; then
  fail "an installed target passes the flags above to its consumers"
fi
# Eigen's settings are definitions of qdmeta::qdmeta, so that a consumer's file may include Eigen
# first (tests/package/portable_consumer.cpp does); no other Eigen definition travels.
definitions=$(grep -A3 'add_library(qdmeta::qdmeta ' "$package/qdmetaTargets.cmake" | grep INTERFACE_COMPILE_DEFINITIONS || true)
for d in EIGEN_MAX_ALIGN_BYTES=16 EIGEN_MAX_STATIC_ALIGN_BYTES=16 EIGEN_MALLOC_ALREADY_ALIGNED=0; do
  [[ $definitions == *"$d"* ]] || fail "qdmeta::qdmeta does not pass $d to its consumers: $definitions"
done
[[ $(grep -o 'EIGEN_[A-Z_]*=' "$package"/qdmeta*Targets*.cmake | sort -u | wc -l) -eq 3 ]] \
  || fail "an installed target passes another Eigen definition: $(grep -o 'EIGEN_[A-Z_]*=[^;\"]*' "$package"/qdmeta*Targets*.cmake)"
if grep -rln '#include <dart/' "$prefix/include"; then fail "the installed headers above include DART"; fi
# A file compiled without the target's definitions: qdmeta/core/eigen.hpp precedes every Eigen header.
while IFS= read -r header; do
  [[ $header == */qdmeta/core/eigen.hpp ]] && continue
  eigen=$(grep -n -m1 '#include <Eigen/' "$header" | cut -d: -f1)
  config=$(grep -n -m1 '#include "qdmeta/core/eigen.hpp"' "$header" | cut -d: -f1 || true)
  [[ -n $config && $config -lt $eigen ]] || fail "$header includes Eigen before qdmeta/core/eigen.hpp"
done < <(grep -rl '#include <Eigen/' "$prefix/include")

launcher=()
if command -v ccache > /dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
# configure SOURCE BINARY [ARGS...]: a Release consumer of the installed package, built for the baseline.
configure() {
  local source=$1 binary=$2
  shift 2
  cmake -S "$source" -B "$binary" -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_CXX_FLAGS="$portable" -DCMAKE_EXPORT_COMPILE_COMMANDS=ON "${launcher[@]}" "$@" \
        > "$binary.configure.log" 2>&1 || { cat "$binary.configure.log"; fail "configuring $source"; }
  if grep -q -- '-march=native' "$binary/compile_commands.json"; then fail "$source is compiled with -march=native"; fi
}

step "a consumer for the x86-64 baseline, without components, where DART and MPI cannot be found"
configure "$root/tests/package" "$consumer" -DCMAKE_DISABLE_FIND_PACKAGE_DART=ON -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON
# CMake reads CMAKE_DISABLE_FIND_PACKAGE_X at each find_package(X): reported unused, neither was looked for.
unused=$(sed -n '/Manually-specified variables were not used/,$p' "$consumer.configure.log")
[[ $unused == *CMAKE_DISABLE_FIND_PACKAGE_DART* && $unused == *CMAKE_DISABLE_FIND_PACKAGE_MPI* ]] \
  || fail "find_package(qdmeta) without components looked for DART or MPI: $(cat "$consumer.configure.log")"
cmake --build "$consumer" -j "$jobs" > "$consumer.build.log" 2>&1 || { cat "$consumer.build.log"; fail "building the consumer"; }
for config in map-elites qdmeta-dimension; do
  # The library's elite tables, freed by the consumer; the archive that of the installed qdmeta.
  "$consumer/portable-consumer" "$root/configs/rastrigin/$config.toml" 20000 "$consumer/$config.csv" \
    || fail "the portable consumer on $config"
  "$prefix/bin/qdmeta" run --config "$root/configs/rastrigin/$config.toml" --evals 20000 --out "$consumer/$config" \
    --threads "$jobs" --quiet || fail "qdmeta run ($config)"
  cmp -s "$consumer/$config.csv" "$consumer/$config/archive.csv" || fail "the portable consumer's $config archive differs"
done

step "a component the installation lacks, or that names nothing, is refused in one message"
wants=$consumer/wants
mkdir -p "$wants/source"
cat > "$wants/source/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(wants LANGUAGES CXX)
find_package(qdmeta REQUIRED COMPONENTS ${WANT})
get_directory_property(definitions COMPILE_DEFINITIONS)
message(STATUS "found: ${WANT}, directory definitions: [${definitions}]")
CMAKE
# ask NAME PREFIX [ARGS...]: prints the configure output; the status is cmake's.
ask() {
  local want=$1 from=$2
  shift 2
  rm -rf "$wants/build"
  # CMake wraps its messages at a width, so where a line breaks depends on the prefix's length:
  # the output as one line, each run of blanks and newlines one space.
  local status=0 output
  output=$(cmake -S "$wants/source" -B "$wants/build" -DWANT="$want" -DCMAKE_PREFIX_PATH="$from" "$@" 2>&1) || status=$?
  tr -s ' \n' ' ' <<< "$output"
  return "$status"
}
# An installation without RHex and MPI: this one without their targets files.
lean=$consumer/lean-prefix
mkdir -p "$lean/lib"
ln -s "$prefix/include" "$prefix/share" "$lean/"
ln -s "$prefix"/lib/*.a "$lean/lib/"
cp -r "$prefix/lib/cmake" "$lean/lib/"
rm -f "$lean"/lib/cmake/qdmeta/qdmeta{Rhex,Mpi}Targets*.cmake "$lean"/lib/cmake/qdmeta/qdmetaMujoco.cmake
message=$(ask rhex "$lean") && fail "a missing rhex component was accepted: $message"
[[ $message == *"has no component rhex: qdmeta was built without DART 6.12"* ]] || fail "missing rhex: $message"
message=$(ask mpi "$lean") && fail "a missing mpi component was accepted: $message"
[[ $message == *"has no component mpi: qdmeta was built without MPI"* ]] || fail "missing mpi: $message"
message=$(ask gpu "$prefix") && fail "component gpu was accepted: $message"
[[ $message == *'qdmeta has no component "gpu" (its components: rhex, mujoco, mpi)'* ]] || fail "component gpu: $message"
if [[ -e $package/qdmetaMpiTargets.cmake ]]; then
  message=$(ask mpi "$prefix" -DCMAKE_DISABLE_FIND_PACKAGE_MPI=ON) && fail "mpi was found without MPI: $message"
  [[ $message == *"component mpi needs MPI (C++), which was not found"* ]] || fail "mpi without MPI: $message"
fi
message=$(ask mujoco "$lean") && fail "a missing mujoco component was accepted: $message"
[[ $message == *"has no component mujoco: qdmeta was built without MuJoCo"* ]] || fail "missing mujoco: $message"
if [[ -e $package/qdmetaMujoco.cmake ]]; then
  message=$(ask mujoco "$prefix") || fail "component mujoco: $message"
  [[ $message == *"found: mujoco"* ]] || fail "finding mujoco: $message"
fi
if [[ -e $package/qdmetaRhexTargets.cmake ]]; then
  message=$(ask rhex "$prefix") || fail "component rhex: $message"
  [[ $message == *"found: rhex, directory definitions: []"* ]] || fail "finding rhex left definitions: $message"
fi

step "a target that links a component not asked for, or uses run_cli without qdmeta::cli, is named"
links=$consumer/links
mkdir -p "$links/source"
cat > "$links/source/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(links LANGUAGES CXX)
find_package(qdmeta REQUIRED)
add_subdirectory(program)
CMAKE
mkdir -p "$links/source/program"
cat > "$links/source/program/CMakeLists.txt" <<'CMAKE'
add_executable(my-program main.cpp)
target_link_libraries(my-program PRIVATE qdmeta::qdmeta ${EXTRA})
CMAKE
# links MAIN_CPP EXTRA_TARGETS: prints the configure output as one line; the status is cmake's.
configure_links() {
  rm -rf "$links/build"
  printf '%s\n' "$1" > "$links/source/program/main.cpp"
  local status=0 output
  output=$(cmake -S "$links/source" -B "$links/build" -DCMAKE_PREFIX_PATH="$prefix" -DEXTRA="$2" 2>&1) || status=$?
  tr -s ' \n' ' ' <<< "$output"
  return "$status"
}
plain='int main() { return 0; }'
cli='#include <qdmeta/cli/run_cli.hpp>
int main(int argc, char** argv) { return qdmeta::run_cli(argc, argv); }'
message=$(configure_links "$plain" qdmeta::mpi) && fail "qdmeta::mpi linked without its component: $message"
[[ $message == *"qdmeta: target my-program links qdmeta::mpi, but find_package(qdmeta) did not ask for its component: write find_package(qdmeta REQUIRED COMPONENTS mpi)"* ]] \
  || fail "qdmeta::mpi without its component: $message"
message=$(configure_links "$plain" qdmeta::gpu) && fail "qdmeta::gpu was linked: $message"
[[ $message == *"target my-program links qdmeta::gpu, which qdmeta does not have"* ]] || fail "qdmeta::gpu: $message"
message=$(configure_links "$cli" "") && fail "run_cli was used without qdmeta::cli: $message"
[[ $message == *"target my-program compiles main.cpp, which includes qdmeta's command line (qdmeta/cli/), but does not link qdmeta::cli: write target_link_libraries(my-program PRIVATE qdmeta::cli)"* ]] \
  || fail "run_cli without qdmeta::cli: $message"
message=$(configure_links "$cli" qdmeta::cli) || fail "run_cli with qdmeta::cli was refused: $message"

step "a program that asks for qdmeta 0.1 or 0.2 is refused: 0.2 and 0.3 broke their APIs (CHANGELOG.md)"
versioned=$consumer/versioned
mkdir -p "$versioned/source"
cat > "$versioned/source/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(versioned LANGUAGES CXX)
find_package(qdmeta ${WANT_VERSION} REQUIRED)
message(STATUS "found qdmeta ${qdmeta_VERSION}")
CMAKE
# SameMinorVersion (cmake/install.cmake): 0.x accepts only its own minor version.
asks_version() {
  rm -rf "$versioned/build"
  cmake -S "$versioned/source" -B "$versioned/build" -DWANT_VERSION="$1" -DCMAKE_PREFIX_PATH="$prefix" 2>&1 | tr -s ' \n' ' '
  return "${PIPESTATUS[0]}"
}
for old in 0.1 0.2; do
  message=$(asks_version $old) && fail "find_package(qdmeta $old) accepted this installation: $message"
  [[ $message == *"qdmetaConfig.cmake, version: 0.3."* ]] || fail "find_package(qdmeta $old): $message"
done
message=$(asks_version 0.3) || fail "find_package(qdmeta 0.3): $message"
[[ $message == *"found qdmeta 0.3."* ]] || fail "find_package(qdmeta 0.3): $message"

step "building examples/own-task against it, for the x86-64 baseline"
configure "$root/examples/own-task" "$example"
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

# refuses_misspelt_key NAME KEY MISSPELT MESSAGE: arm-qd refuses examples/own-task/configs/NAME.toml
# with KEY spelt MISSPELT, with status 2 and MESSAGE in its one line.
refuses_misspelt_key() {
  local name=$1 key=$2 misspelt=$3 expected=$4 status=0 message
  sed "s/^$key = /$misspelt = /" "$root/examples/own-task/configs/$name.toml" > "$runs/bad-$name.toml"
  message=$("$arm" run --config "$runs/bad-$name.toml" --out "$runs/bad-$name" --quiet 2>&1) || status=$?
  [[ $status -eq 2 && $message == *"$expected"* ]] || fail "a misspelt $name key gave status $status: $message"
}

# killed_and_resumed CONFIG WHAT FILES...: arm-qd runs CONFIG (a checkpoint after every step) into
# runs/WHAT-straight, then again into runs/WHAT, killed at its first checkpoint and resumed with
# more threads; each of FILES must be the same in both.
killed_and_resumed() {
  local config=$1 what=$2 status=0
  shift 2
  "$arm" run --config "$config" --out "$runs/$what-straight" --threads 1 --quiet || fail "arm-qd run ($what)"
  check_run "$runs/$what-straight"
  QDMETA_TEST_SIGNAL_AT_CHECKPOINT=1:KILL "$arm" run --config "$config" --out "$runs/$what" --threads 1 --quiet \
    || status=$?
  [[ $status -eq 137 && -e $runs/$what/checkpoint.bin ]] || fail "the $what run was not killed at its checkpoint ($status)"
  "$arm" resume --out "$runs/$what" --threads "$jobs" --quiet || fail "arm-qd resume ($what)"
  check_run "$runs/$what"
  for f in "$@"; do
    cmp -s "$runs/$what-straight/$f" "$runs/$what/$f" || fail "the resumed $what run's $f differs from the uninterrupted run's"
  done
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

step "a program that registers nothing (arm-parts): arm-qd's config, killed at its first checkpoint, resumed"
parts_config=$runs/parts.toml  # QD-Meta's config as it is: the task part reads [task] joints
cp "$root/examples/own-task/configs/qd-meta.toml" "$parts_config"
printf '\n[checkpoint]\nevery_seconds = 0\n' >> "$parts_config"
sed 's/^joints = /jionts = /' "$root/examples/own-task/configs/qd-meta.toml" > "$runs/parts-misspelt.toml"
status=0
message=$("$example/arm-parts" run "$runs/parts-misspelt.toml" "$runs/parts-keys" 2>&1) || status=$?
[[ $status -eq 2 && $message == *"unknown key 'task.jionts' in [task] (valid keys: joints, name)"* ]] \
  || fail "arm-parts and a misspelt [task] key: $status $message"
status=0
QDMETA_TEST_SIGNAL_AT_CHECKPOINT=1:KILL "$example/arm-parts" run "$parts_config" "$runs/parts" || status=$?
[[ $status -eq 137 && -e $runs/parts/checkpoint.bin ]] || fail "arm-parts was not killed at its checkpoint ($status)"
"$example/arm-parts" resume "$runs/parts" || fail "arm-parts resume"
check_run "$runs/parts"
cmp -s "$runs/qd-meta/archive.csv" "$runs/parts/archive.csv" || fail "arm-parts's archive differs from arm-qd's"

step "the program's own mutation operator: [mutation] kind = \"sbx\""
"$example/sbx-check" || fail "sbx-check: the SBX operator's offspring do not follow its definition"
"$arm" run --config "$root/examples/own-task/configs/sbx.toml" --out "$runs/sbx" --threads "$jobs" --quiet \
  || fail "arm-qd run (sbx)"
check_run "$runs/sbx"
python3 - "$runs/sbx" <<'PY' || fail "the SBX run did not record its operator or found no elite"
import json, sys, tomllib
d = sys.argv[1]
mutation = tomllib.load(open(f"{d}/config.toml", "rb"))["mutation"]
assert mutation == {"kind": "sbx", "eta": 20.0}, mutation
assert json.load(open(f"{d}/summary.json"))["num_elites"] > 0
assert sum(1 for _ in open(f"{d}/archive.csv")) > 1, "archive.csv has no elite"
PY
refuses_misspelt_key sbx eta etta "unknown key 'mutation.etta' in [mutation]"

step "the program's own algorithm (random-search): killed at its first checkpoint, resumed"
random_config=$runs/random-search.toml
cp "$root/examples/own-task/configs/random-search.toml" "$random_config"
printf '\n[checkpoint]\nevery_seconds = 0\n' >> "$random_config"
killed_and_resumed "$random_config" random archive.csv

step "the program's own controller of G: [control] kind = \"cycle\" (docs/tutorials/controller.md)"
cycle_config=$runs/cycle.toml
cp "$root/examples/own-task/configs/cycle.toml" "$cycle_config"
printf '\n[checkpoint]\nevery_seconds = 0\n' >> "$cycle_config"
killed_and_resumed "$cycle_config" cycle archive.csv meta.csv
python3 - "$runs/cycle-straight/meta.csv" <<'PY' || fail "the cycle run's meta-generations did not follow its schedule"
import csv, sys
g = [int(row["generations"]) for row in csv.DictReader(open(sys.argv[1]))]
assert len(g) >= 6 and g == [(1, 2, 4)[i % 3] for i in range(len(g))], g
PY
refuses_misspelt_key cycle generations generation "unknown key 'control.generation' in [control]"

step "the program's own feature-map: [feature_map] kind = \"polar\" (docs/tutorials/feature-map.md)"
"$arm" run --config "$root/examples/own-task/configs/polar.toml" --out "$runs/polar" --threads "$jobs" --quiet \
  || fail "arm-qd run (polar)"
check_run "$runs/polar"
# Each elite's measures, from its genes: the arm's end effector (10 links of length 1/10, each
# gene an angle in [-pi, pi] relative to the link before), its distance from the base and direction.
python3 - "$runs/polar/archive.csv" <<'PY' || fail "the polar run's measures are not its elites' distances and directions"
import csv, math, sys
rows = list(csv.DictReader(open(sys.argv[1])))
assert len(rows) > 100, len(rows)
for row in rows:
    genes = [float(row[f"solution_{j}"]) for j in range(10)]
    heading = x = y = 0.0
    for g in genes:
        heading += (g - 0.5) * 2 * math.pi
        x += math.cos(heading) / 10
        y += math.sin(heading) / 10
    # The task's base features are float32: (x + 1) / 2 rounded, so compare within float precision.
    distance = min(math.hypot(x, y), 1.0)
    direction = (math.atan2(y, x) + math.pi) / (2 * math.pi)
    assert abs(float(row["measures_0"]) - distance) < 1e-5, (row, distance)
    assert min(abs(float(row["measures_1"]) - direction), 1 - abs(float(row["measures_1"]) - direction)) < 1e-5, (row, direction)
PY
refuses_misspelt_key polar reach raech "unknown key 'feature_map.raech' in [feature_map] (valid keys: kind, reach)"

step "the program's own archive: [archive] kind = \"floor\" (docs/tutorials/archive.md)"
floor_config=$runs/floor.toml
cp "$root/examples/own-task/configs/floor.toml" "$floor_config"
printf '\n[checkpoint]\nevery_seconds = 0\n' >> "$floor_config"
killed_and_resumed "$floor_config" floor archive.csv
# Every elite reaches the floor, and the floor mattered: the unfloored run (same grid) keeps some below it.
python3 - "$runs/floor-straight/archive.csv" "$runs/map-elites/archive.csv" <<'PY' || fail "the floor archive kept an elite below its floor"
import csv, sys
floored = [float(r["objective"]) for r in csv.DictReader(open(sys.argv[1]))]
plain = [float(r["objective"]) for r in csv.DictReader(open(sys.argv[2]))]
assert len(floored) > 50 and min(floored) >= -1.0, (len(floored), min(floored))
assert min(plain) < -1.0, min(plain)
PY
refuses_misspelt_key floor floor flor "unknown key 'archive.flor' in [archive]"

step "CMA-MAE: the emitter API by hand (arm-emitters) and algorithm = \"cma-mae\" on the arm"
"$example/arm-emitters" || fail "arm-emitters"
"$arm" run --config "$root/examples/own-task/configs/cma-mae.toml" --out "$runs/cma-mae" --threads "$jobs" --quiet \
  || fail "arm-qd run (cma-mae)"
check_run "$runs/cma-mae"

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

step "arm-qd --help lists the arm beside the built-in parts"
message=$("$arm" --help)
[[ $message == *'[task] name = "arm": [meta_fitness] kind locked-joint; adapt --test locked'* &&
   $message == *'[task] name = "rastrigin"'* ]] || fail "arm-qd --help: $message"

step "a misspelt [task] key is refused"
bad=$runs/bad.toml
sed 's/^joints = /jionts = /' "$root/examples/own-task/configs/map-elites.toml" > "$bad"
status=0
message=$("$arm" run --config "$bad" --out "$runs/bad" --quiet 2>&1) || status=$?
[[ $status -eq 2 && $message == *"task.jionts"* ]] || fail "a misspelt key gave status $status: $message"

if grep -q 'libqdmeta_mpi.a' "$example/build.ninja" && command -v mpirun > /dev/null; then
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

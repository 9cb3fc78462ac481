#!/usr/bin/env bash
# scripts/slurm-experiment.sh on a real SLURM (make test-slurm): installs Debian's SLURM and MUNGE
# when missing, starts munged, slurmctld and slurmd on this machine as one 2-CPU node (its own
# slurm.conf, state and sockets in a temporary directory; no systemd needed), submits a small
# RHex-on-MuJoCo experiment (2 conditions x 2 replicates, 2 MPI ranks per array task), cancels
# one array task in the middle of its run (scancel, as a time limit or a node failure would) with
# the report job, submits the same command again, and checks that the finished report (less its
# wall time column) and every run's files equal a local `qdmeta experiment` of the same file,
# byte for byte. Stops exactly the daemons it started, also on failure (its jobs first: they
# would outlive slurmd). Run it as root, as CI does (slurmd and the jobs then run as root; another
# user is untried).
#
#   scripts/test-slurm.sh [BUILD_DIR]   (default build; the qdmeta target is built there)
#   QDMETA=path/to/qdmeta scripts/test-slurm.sh   (that program, already built, instead)
set -euo pipefail
src=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "$src" && mkdir -p "${1:-build}" && cd "${1:-build}" && pwd)
fail() { echo "test-slurm: FAIL: $*" >&2; exit 1; }
say() { echo "test-slurm: $*"; }

# --- Dependencies and the program -----------------------------------------------------------
bash "$src/scripts/install-deps.sh"
slurm_packages=(slurmctld slurmd slurm-client munge)
missing=()
for p in "${slurm_packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if (( ${#missing[@]} )); then
  if [[ $(id -u) -eq 0 ]]; then sudo=""; else sudo="sudo"; fi
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
if [[ -n ${QDMETA:-} ]]; then
  qdmeta=$(realpath "$QDMETA")
  build=$(dirname "$qdmeta")
else
  [[ -f $build/build.ninja ]] || cmake -S "$src" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release
  cmake --build "$build" -j "${JOBS:-2}" --target qdmeta
  qdmeta=$build/qdmeta
fi
grep -q '^QDMETA_WITH_MUJOCO:BOOL=ON' "$build/CMakeCache.txt" || fail "$build is configured without MuJoCo (QDMETA_WITH_MUJOCO)"
grep -q '^QDMETA_WITH_MPI:BOOL=ON' "$build/CMakeCache.txt" || fail "$build is configured without MPI (QDMETA_WITH_MPI)"

# --- A one-node cluster ---------------------------------------------------------------------
tmp=$(mktemp -d /tmp/qdmeta-slurm.XXXXXX)
pids=()
stop_daemons() {  # this cluster's jobs, then the daemons this script started, newest first
  local status=$?
  if (( ${#pids[@]} == 3 )) && kill -0 "${pids[1]}" 2>/dev/null; then
    # Jobs outlive slurmd (slurmstepd runs them): end them first. Every job here is this script's.
    local jobs
    jobs=$(squeue -h -o %i 2>/dev/null || true)
    if [[ -n $jobs ]]; then
      # shellcheck disable=SC2086  # a list of job ids
      scancel $jobs 2>/dev/null || true
      for _ in $(seq 600); do [[ -z $(squeue -h -o %i 2>/dev/null) ]] && break; sleep 0.1; done
    fi
  fi
  for (( i = ${#pids[@]} - 1; i >= 0; i-- )); do
    kill "${pids[i]}" 2>/dev/null || true
    wait "${pids[i]}" 2>/dev/null || true
  done
  if (( status != 0 )); then
    for log in "$tmp"/*.log "$tmp"/work/out/slurm/*.log; do
      [[ -f $log ]] && { echo "== $log"; tail -n 30 "$log"; }
    done
  fi
  rm -rf "$tmp"
  exit "$status"
}
trap stop_daemons EXIT
trap 'exit 130' INT TERM

free_port() { /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
node=$(hostname -s)
user=$(id -un)
memory=$(awk '/MemTotal/ { print int($2 / 1024) }' /proc/meminfo)
mkdir -p "$tmp/state" "$tmp/spool" "$tmp/work"
head -c 1024 /dev/urandom > "$tmp/munge.key"
chmod 400 "$tmp/munge.key"
cat > "$tmp/slurm.conf" <<CONF
ClusterName=qdmeta-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$tmp/munge.sock
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/slurmctld.pid
SlurmdPidFile=$tmp/slurmd.pid
SlurmctldLogFile=$tmp/slurmctld.log
SlurmdLogFile=$tmp/slurmd.log
MailProg=/bin/true
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
NodeName=$node NodeAddr=127.0.0.1 CPUs=2 RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$tmp/slurm.conf
munged --foreground --force --socket="$tmp/munge.sock" --key-file="$tmp/munge.key" \
  --pid-file="$tmp/munged.pid" --log-file="$tmp/munged.log" --seed-file="$tmp/munged.seed" \
  > "$tmp/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 100); do [[ -S $tmp/munge.sock ]] && break; sleep 0.1; done
slurmctld -D -f "$SLURM_CONF" > "$tmp/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" > "$tmp/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 300); do
  [[ $(sinfo -h -n "$node" -o %T 2>/dev/null) == idle ]] && break
  sleep 0.2
done
[[ $(sinfo -h -n "$node" -o %T) == idle ]] || fail "the node did not come up: $(sinfo 2>&1)"
say "SLURM $(sinfo -V | cut -d' ' -f2) up: node $node, 2 CPUs"

# --- The experiment -------------------------------------------------------------------------
# A checkpoint after every generation makes the cancelled run's progress visible at once;
# checkpoints never change results (docs/config.md). The damage types stay drawn from the seed
# (damage_type_count, as the study's configs): a planned run's config differs from seed to seed,
# while its fingerprint is the condition's (README, "Experiments").
cat > "$tmp/work/experiment.toml" <<TOML
name = "RHex on MuJoCo under SLURM"
replicates = 2
evaluations = 400
tests = ["damage"]
[[condition]]
name = "QD-Meta Damage Feature-sets"
config = "$src/configs/rhex/smoke-damage.toml"
set = { task = { engine = "mujoco" }, checkpoint = { every_seconds = 0 } }
[[condition]]
name = "CVT-MAP-Elites"
config = "$src/configs/rhex/smoke-cvt.toml"
set = { task = { engine = "mujoco" }, checkpoint = { every_seconds = 0 }, cvt = { cache = false, samples = 16, init_samples = 16, centroids = 8 } }
TOML
cd "$tmp/work"
export QDMETA=$qdmeta SBATCH_ARRAY_ARGS="--ntasks=2 --time=1:00:00" SBATCH_FINISH_ARGS="--ntasks=1 --cpus-per-task=2 --time=1:00:00"
# Debian's OpenMPI refuses root unless told; a cluster user never needs these.
[[ $(id -u) -ne 0 ]] || export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
submit() { bash "$src/scripts/slurm-experiment.sh" submit experiment.toml out | tee "$tmp/submit.log"; }
jobs_of() { sed -n 's/.* as array job \([0-9]*\), then job \([0-9]*\) .*/\1 \2/p' "$tmp/submit.log"; }
wait_jobs() {  # JOB...: until none of them is pending or running
  local ids
  ids=$(IFS=,; echo "$*")
  while [[ -n $(squeue -h -j "$ids" -o %i 2>/dev/null) ]]; do sleep 1; done
}
start=$SECONDS
submit
read -r array finish < <(jobs_of)
[[ -n $array && -n $finish ]] || fail "submit printed no job ids"
runs=$(( $(wc -l < out/plan.tsv) - 1 ))
(( runs == 4 )) || fail "plan.tsv has $runs runs, not 4"

# The first run with a checkpoint is mid-run: cancel its array task, and the report job with it.
victim=""
while [[ -z $victim ]]; do
  for k in $(seq "$runs"); do
    dir=$(awk -F'\t' -v k="$k" 'NR == k + 1 { print $5 }' out/plan.tsv)
    if [[ -e $dir/checkpoint.bin ]]; then victim=$k; break; fi
  done
  [[ -n $(squeue -h -j "$array" -o %i) ]] || fail "the array ended before any checkpoint"
  sleep 0.1
done
scancel "${array}_$victim" "$finish"
say "cancelled array task ${array}_$victim (run $dir) and job $finish"
wait_jobs "$array" "$finish"
[[ -e $dir/checkpoint.bin && ! -e $dir/summary.json ]] || fail "run $dir finished before the cancel reached it"
for k in $(seq "$runs"); do
  other=$(awk -F'\t' -v k="$k" 'NR == k + 1 { print $5 }' out/plan.tsv)
  [[ $k == "$victim" ]] || grep -q '"stop_reason": "budget"' "$other/summary.json" || fail "$other did not finish"
done
[[ ! -e out/report.md ]] || fail "a report was written before the resubmission"

# The same command again: the finished runs' tasks skip them, the cancelled run resumes.
submit
read -r array finish < <(jobs_of)
wait_jobs "$array" "$finish"
for k in $(seq "$runs"); do
  if [[ $k == "$victim" ]]; then expected="resuming from checkpoint"; else expected="already finished"; fi
  grep -q "$expected" out/slurm/task-"${array}_$k".log || fail "task $k of the resubmission: not '$expected'"
done
grep -q "0 runs finished now, 0 resumed, 4 already finished; 4 test phases" out/slurm/finish-"$finish".log ||
  fail "the report job: $(tail -n 5 out/slurm/finish-"$finish".log)"
say "SLURM: the experiment and its report in $((SECONDS - start)) s"

# --- The same file, locally -----------------------------------------------------------------
start=$SECONDS
"$qdmeta" experiment --config experiment.toml --out local > local.log 2>&1 || fail "local experiment: $(tail -n 5 local.log)"
say "locally: $((SECONDS - start)) s"
for run in $(cd local && ls -d ./*/seed-*); do
  for file in archive.csv metrics.csv meta.csv adapt-damage.csv; do
    [[ ! -e local/$run/$file ]] || cmp "local/$run/$file" "out/$run/$file" || fail "$run/$file differs"
  done
done
# The one measured quantity: the final-archive table's wall time column (time spent, which no
# two runs share) is blanked in both reports; every other byte must agree.
without_wall_time() {
  awk -F'|' -v OFS='|' '
    /\| wall time \(s\) \|/ { for (i = 1; i <= NF; i++) if ($i == " wall time (s) ") column = i }
    !/^\|/ { column = 0 }
    column && /^\| / && !/wall time/ { $column = " - " }
    { print }' "$1"
}
without_wall_time local/report.md > local-report.md
without_wall_time out/report.md > slurm-report.md
grep -q "| wall time (s) |" local-report.md || fail "report.md has no wall time column to leave out"
cmp local-report.md slurm-report.md || fail "report.md differs: $(diff local-report.md slurm-report.md | head -n 20)"
say "the report (less its wall times) and every run's files equal a local run's, byte for byte"

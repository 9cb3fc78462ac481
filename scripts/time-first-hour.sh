#!/usr/bin/env bash
# A newcomer's first two commands, timed: clones this repository's HEAD into a fresh folder, then
# `time make run` and `time make test` there, sampling the 1-minute load average every 30 s so
# that a figure taken on a busy machine says so. Prints one line per command and the load; the
# README's timing paragraph quotes these lines.
#
#   scripts/time-first-hour.sh [FOLDER]     (default: a new folder under ${TMPDIR:-/tmp})
#
# The clone builds without ccache (as a fresh machine would). The Debian packages `make run`
# installs are whatever this machine already has: on a machine without them, add apt's time.
set -euo pipefail

repo=$(git -C "$(dirname "$0")/.." rev-parse --show-toplevel)
folder=${1:-$(mktemp -d "${TMPDIR:-/tmp}/qdmeta-first-hour.XXXXXX")}
[[ -e $folder/.git ]] && { echo "time-first-hour: $folder already holds a clone: give a new folder" >&2; exit 2; }
git clone --quiet "$repo" "$folder/qdmeta"
cd "$folder/qdmeta"
commit=$(git rev-parse --short HEAD)

loads=$folder/load.txt
(while true; do cut -d' ' -f1 /proc/loadavg >> "$loads"; sleep 30; done) &
sampler=$!
trap 'kill $sampler 2>/dev/null || true' EXIT

timed() {
  local name=$1 start end
  shift
  start=$(date +%s)
  if ! env -u CMAKE_CXX_COMPILER_LAUNCHER "$@" > "$folder/$name.log" 2>&1; then
    echo "time-first-hour: $name failed (log: $folder/$name.log)" >&2
    exit 1
  fi
  end=$(date +%s)
  echo "${name/-/ }: $((end - start)) s"
}

echo "time-first-hour: fresh clone of $commit in $folder/qdmeta, $(nproc) cores, $(date -u '+%Y-%m-%d %H:%M UTC')"
timed make-run make run
timed make-test make test
kill $sampler 2>/dev/null || true
awk '{ s += $1; n++; if ($1 > m) m = $1 } END { if (n) printf "1-minute load average: mean %.2f, max %.2f over %d samples\n", s / n, m, n }' "$loads"

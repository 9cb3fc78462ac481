#!/usr/bin/env bash
# Side-by-side benchmark of qdmeta against pyribs and QDax (bench/peers/README.md).
#   bench/peers/run.sh [--evals N] [--repeats R] [any option of peers.py]
# Creates build/peers-venv with Debian's python3 and pinned peers, builds qdmeta if needed, then
# runs peers.py. The only part of the project that uses the Python package index; a peer that
# cannot be installed is skipped with a one-line reason and the others still run.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/../.." && pwd)"
VENV="$ROOT/build/peers-venv"
PYTHON="${PEERS_PYTHON:-/usr/bin/python3}"
# Pinned versions (the ones measured in bench/README.md).
RIBS="ribs==0.12.0"
QDAX=("qdax==0.5.0" "jax[cpu]==0.10.2")

if [[ ! -x "$VENV/bin/python" ]]; then
  if ! "$PYTHON" -m venv "$VENV" 2>/dev/null; then
    echo "cannot create a virtual environment with $PYTHON -m venv: install python3-venv (apt-get install python3-venv)" >&2
    exit 1
  fi
fi
pip_install() {  # name, packages...: installs quietly; a failure skips the peer
  local name=$1; shift
  if ! "$VENV/bin/pip" install -q --disable-pip-version-check "$@" >"$VENV/pip-$name.log" 2>&1; then
    echo "skipping $name: pip install $* failed (see $VENV/pip-$name.log: $(tail -n 1 "$VENV/pip-$name.log"))"
  fi
}
pip_install pyribs "$RIBS"
pip_install qdax "${QDAX[@]}"

if [[ ! -x "$ROOT/build/qdmeta" ]]; then
  make -C "$ROOT" build >/dev/null
fi
exec "$VENV/bin/python" "$ROOT/bench/peers/peers.py" "$@"

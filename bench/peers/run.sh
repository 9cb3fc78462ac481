#!/usr/bin/env bash
# Side-by-side benchmark of qdmeta against pyribs and QDax (bench/peers/README.md).
#   bench/peers/run.sh [--evals N] [--repeats R] [any option of peers.py]
#   bench/peers/run.sh --cma [any option of cma_peers.py]   (CMA-ME / CMA-MAE against pyribs)
# Creates build/peers-venv with Debian's python3 and pinned peers, builds qdmeta if needed and
# the arm's command line (examples/own-task against an install of the build, in
# build/peers-arm), then runs peers.py. The only part of the project that uses the Python
# package index; a peer that cannot be installed is skipped with a one-line reason and the
# others still run. JOBS (default 2) caps the example's build.
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
if [[ "${1:-}" == "--cma" ]]; then
  # The CMA-MAE paper's comparison needs pyribs and the C++ peer only (README.md, "CMA-ME and CMA-MAE").
  shift
  cmake --build "$ROOT/build" -j "${JOBS:-2}" --target cma_peer >/dev/null
  exec "$VENV/bin/python" "$ROOT/bench/peers/cma_peers.py" "$@"
fi
pip_install qdax "${QDAX[@]}"

if [[ ! -x "$ROOT/build/qdmeta" ]]; then
  make -C "$ROOT" build >/dev/null
fi
# The arm exists as a C++ task only in examples/own-task: built against this build's install, as
# scripts/test-installed-package.sh does (re-run each time, so the arm follows the build).
ARM_PREFIX="$ROOT/build/peers-install"
ARM_BUILD="$ROOT/build/peers-arm"
launcher=()
if command -v ccache >/dev/null; then launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache); fi
if ! { cmake --install "$ROOT/build" --prefix "$ARM_PREFIX" >"$ROOT/build/peers-arm.log" 2>&1 &&
       cmake -S "$ROOT/examples/own-task" -B "$ARM_BUILD" -G Ninja -DCMAKE_BUILD_TYPE=Release \
             -DCMAKE_PREFIX_PATH="$ARM_PREFIX" "${launcher[@]}" >>"$ROOT/build/peers-arm.log" 2>&1 &&
       cmake --build "$ARM_BUILD" -j "${JOBS:-2}" --target arm-qd >>"$ROOT/build/peers-arm.log" 2>&1; }; then
  echo "skipping qdmeta's CLI on the arm: building examples/own-task failed (see build/peers-arm.log)"
  rm -f "$ARM_BUILD/arm-qd"
fi
exec "$VENV/bin/python" "$ROOT/bench/peers/peers.py" "$@"

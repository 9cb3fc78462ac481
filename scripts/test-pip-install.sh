#!/usr/bin/env bash
# `pip install .` as a user would: a fresh virtual environment of Debian's python3 (python3-venv),
# the package built from this checkout by scikit-build-core (fetched from the Python package
# index, with numpy), then the Python suite run against the installed package from outside the
# source tree. Needs the network; `make test` does not run it (it uses Debian's packages only),
# `make test-pip` does.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
scratch=${1:-$root/build-pip}
step() { echo "test-pip-install: $*"; }
fail() { echo "test-pip-install: FAILED: $*" >&2; exit 1; }

# A fresh environment each time; the CMake build folder is kept, so a second run rebuilds only
# what changed.
rm -rf "$scratch/venv" "$scratch/tests" "$scratch/docs" "$scratch/bench" "$scratch/README.md"
mkdir -p "$scratch"
step "a fresh virtual environment in $scratch/venv"
/usr/bin/python3 -m venv "$scratch/venv" || fail "python3 -m venv (Debian: python3-venv)"
py="$scratch/venv/bin/python"
"$py" -m pip install -q --upgrade pip
step "pip install $root (builds the C++ library and the module; minutes on 2 cores)"
# A build folder of its own, so that the checkout's build/ is left alone.
"$py" -m pip install -q "$root[test,pandas]" --config-settings=build-dir="$scratch/cmake" \
  --config-settings=cmake.define.QDMETA_WITH_RHEX=OFF || fail "pip install"
step "import, version and build options"
(cd "$scratch" && "$py" -c "
import qdmeta, numpy
assert qdmeta.__file__.startswith('$scratch/venv'), qdmeta.__file__
print('qdmeta', qdmeta.__version__, qdmeta.build_info, 'numpy', numpy.__version__)
") || fail "import qdmeta"
step "the Python suite against the installed package"
mkdir -p "$scratch/tests" && cp -r "$root/tests/python" "$scratch/tests/python"
mkdir -p "$scratch/docs/tutorials" && cp "$root/docs/python.md" "$scratch/docs/" && cp "$root/README.md" "$scratch/"
cp "$root/docs/tutorials/pyribs-cma-mae.md" "$scratch/docs/tutorials/"  # tests/python/test_tutorials.py runs it
# tests/python/test_peer_cma_runner.py runs the CMA peers' runner on the installed module.
mkdir -p "$scratch/bench/peers" && cp "$root/bench/peers/common.py" "$root/bench/peers/peer_qdmeta_python_cma.py" "$scratch/bench/peers/"
(cd "$scratch" && "$py" -m pytest -q -p no:cacheprovider tests/python) || fail "pytest"
step "passed"

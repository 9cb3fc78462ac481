#!/usr/bin/env bash
# The Python suite under numpy 2, against the module of this checkout's build (build/python, as
# `make build` makes it: Debian's pybind11 and python3), in a fresh virtual environment with
# numpy 2 (and pytest, pandas, matplotlib) from the Python package index. ctest runs the same
# suite under Debian's numpy 1; a module that gets numpy 2's integer or boolean arrays wrong
# fails here (or refuses to import). Needs the network; `make test-pip` runs it.
# Usage: scripts/test-numpy2.sh [BUILD_DIR]   (default: build)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
build=$(cd "${1:-$root/build}" && pwd)
scratch=$build/numpy2
step() { echo "test-numpy2: $*"; }
fail() { echo "test-numpy2: FAILED: $*" >&2; exit 1; }

[[ -d $build/python/qdmeta ]] || fail "no module in $build/python: run make build first"
# The interpreter the module was built for (its ABI), as CMake found it.
python=$(sed -n 's/^Python_EXECUTABLE:[A-Z]*=//p' "$build/CMakeCache.txt" 2> /dev/null || true)
python=${python:-/usr/bin/python3}

rm -rf "$scratch"
step "a fresh virtual environment of $python in $scratch/venv"
"$python" -m venv "$scratch/venv" || fail "$python -m venv (Debian: python3-venv)"
py=$scratch/venv/bin/python
"$py" -m pip install -q "numpy>=2" pytest pandas matplotlib || fail "pip install numpy>=2 pytest pandas matplotlib"
"$py" -c "import numpy, sys; sys.exit(int(numpy.__version__.split('.')[0]) < 2)" || fail "numpy 2 was not installed"

export PYTHONPATH=$build/python
[[ -x $build/qdmeta ]] && export QDMETA_BINARY=$build/qdmeta
step "import under $("$py" -c 'import numpy; print("numpy", numpy.__version__)')"
(cd "$scratch" && "$py" -c "
import qdmeta
assert qdmeta.__file__.startswith('$build/python'), qdmeta.__file__
print('qdmeta', qdmeta.__version__, qdmeta.build_info)
") || fail "import qdmeta"
step "the Python suite"
(cd "$root" && "$py" -m pytest -q -p no:cacheprovider tests/python) || fail "pytest under numpy 2"
step "passed"

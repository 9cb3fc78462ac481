#!/usr/bin/env bash
# Installs the Debian 12 packages qdmeta needs to build, test and plot. Idempotent: packages
# already installed are skipped, and nothing is done when all are present. Uses sudo when not
# root. Set QDMETA_DEPS=core to skip the optional components (DART robot task, MuJoCo, MPI).
set -euo pipefail

core=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libtbb-dev libtomlplusplus-dev libcli11-dev nlohmann-json3-dev libfmt-dev libspdlog-dev
  libgtest-dev libgmock-dev libbenchmark-dev libnanoflann-dev
  python3 python3-dev python3-matplotlib python3-numpy python3-pytest pybind11-dev
)
# Optional components (robot task in DART, MPI evaluator). The RHex task needs
# DART with its Bullet collision detector; ikfast's headers are needed or dart.hpp won't compile.
# MuJoCo 2.2.2 is the RHex task's second engine ([task] engine = "mujoco", docs/fidelity.md).
# OpenMPI (mpirun and the headers) builds the MPI evaluator and runs its 3-rank test. pandas gives
# the Python archives their as_pandas(); python3-venv is for make test-pip and bench/peers.
optional=(libdart-dev libdart-collision-bullet-dev libdart-external-ikfast-dev libmujoco-dev
          openmpi-bin libopenmpi-dev python3-pandas python3-venv)

packages=("${core[@]}")
if [ "${QDMETA_DEPS:-all}" != core ]; then packages+=("${optional[@]}"); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then missing+=("$p"); fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then sudo=""; else sudo="sudo"; fi
echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: done"

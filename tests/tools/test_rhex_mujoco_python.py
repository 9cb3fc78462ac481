"""The GPU route's first step (docs/scaling.md): the `mujoco` Python package loads qdmeta's MJCF
model (`qdmeta-rhex-gait --mjcf`) and tools/rhex_mujoco_episode.py runs the tripod's episode on it
as the C++ engine does. Skipped where the package is absent, or QDMETA_RHEX_GAIT (the
qdmeta-rhex-gait binary; ctest's rhex_mujoco_python sets it) is not given.

The C++ engine is Debian's MuJoCo 2.2.2; the Python package is whichever is installed (4.0.1 when
this was written). The same model, controller and step give the same body positions for the first
0.05 s to 1e-9 m (a wrong gene decoding, servo, torque sign, start pose or step order shows from
the first step); after that two MuJoCo versions drift apart through the contacts (measured with
4.0.1: 2 mm by 0.5 s; tripod distance 3.248 m against 3.394 m with rigid legs, 4%, and 3.334 m
against 3.328 m with compliant legs), so the distance is compared
within 10% and exactly only on the C++ engine's own version."""
import csv
import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import rhex_mujoco_episode as episode  # noqa: E402

GAIT = os.environ.get("QDMETA_RHEX_GAIT")
# The tripod (rhex::tripod_genes): legs 1, 3, 5 half a period after 0, 2, 4.
TRIPOD = [0.5] + [0.5] * 6 + [0.35] * 6 + [0.5] * 6 + [1, 0, 1, 0, 1]


@pytest.mark.parametrize("legs", ["rigid", "compliant"])
def test_python_episode_walks_as_the_cpp_engine(tmp_path, legs):
    mujoco = pytest.importorskip("mujoco")  # in the test, so that a skip is a skip, not "no tests"
    if not GAIT:
        pytest.skip("QDMETA_RHEX_GAIT (the qdmeta-rhex-gait binary) not given")
    model, poses = tmp_path / "rhex.xml", tmp_path / "gait.csv"
    printed = subprocess.run([GAIT, "--engine", "mujoco", "--legs", legs, "--genes", ",".join(map(str, TRIPOD)),
                              "--out", str(poses), "--mjcf", str(model)], check=True, capture_output=True,
                             text=True).stdout
    cpp_distance = float(re.search(r"distance (\S+) m", printed).group(1))
    distance, dead, positions, plate_range = episode.run_episode(model.read_text(), TRIPOD)
    with open(poses, newline="") as f:
        cpp_positions = [(float(r["x"]), float(r["y"]), float(r["z"])) for r in csv.DictReader(f)]
    for step in range(10):
        assert positions[step] == pytest.approx(cpp_positions[step], abs=1e-9), step
    assert not dead
    # Plate springs of 152,000-202,672 N m/rad under a 7 kg robot: deflections of 1e-5-1e-3 rad.
    assert (plate_range == (0.0, 0.0)) == (legs == "rigid")
    assert max(abs(a) for a in plate_range) < 0.01
    if mujoco.__version__ == "2.2.2":
        assert distance == pytest.approx(cpp_distance, abs=1e-9)
    else:
        assert distance == pytest.approx(cpp_distance, rel=0.10)

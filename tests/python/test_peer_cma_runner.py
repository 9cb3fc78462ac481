"""bench/peers/peer_qdmeta_python_cma.py, the CMA-MAE peers' runner on qdmeta's module: its JSON
line counts what the archive holds, and a run pinned to one core (the scheduler then asks and
tells its emitters on one thread) ends with the QD-score of a run on every core."""
import json
import os
import pathlib
import subprocess
import sys

import pytest

RUNNER = pathlib.Path(__file__).resolve().parents[2] / "bench" / "peers" / "peer_qdmeta_python_cma.py"


def run(domain, one_core):
    def pin():
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})

    out = subprocess.run([sys.executable, str(RUNNER), "--domain", domain, "--algorithm", "cma-mae",
                          "--iterations", "12", "--seed", "3"],
                         check=True, capture_output=True, text=True, preexec_fn=pin if one_core else None)
    return json.loads(out.stdout)


@pytest.mark.parametrize("domain", ["sphere", "arm"])
def test_counts_and_the_same_qd_score_on_one_core_or_all(domain):
    everywhere, pinned = run(domain, False), run(domain, True)
    assert pinned["note"].endswith("1 core(s)")
    assert everywhere["evals"] == 12 * 15 * 36
    assert 0 < everywhere["num_elites"] <= everywhere["evals"]
    assert everywhere["coverage"] == pytest.approx(everywhere["num_elites"] / 100)
    assert 0 < everywhere["qd_score"] <= everywhere["coverage"]  # objectives at most 100 per cell
    for key in ("num_elites", "qd_score", "obj_max"):
        assert pinned[key] == everywhere[key]

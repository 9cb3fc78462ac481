"""qdmeta.ProximityArchive against pyribs 0.12's ProximityArchive on the same batches
(pyribs_reference/proximity.json, written by pyribs_reference/make_proximity_reference.py):
each add's statuses, novelty, local competition and values, the threshold's decay, and the
elites left, in pyribs's order; then its refusals."""

import json
import pathlib

import numpy as np
import pytest

import qdmeta
from refusals import refusal

REFERENCE = json.loads((pathlib.Path(__file__).parent / "pyribs_reference" / "proximity.json").read_text())
BATCHES = [[np.array(part) for part in batch] for batch in REFERENCE["batches"]]


@pytest.mark.parametrize("run", REFERENCE["runs"], ids=lambda r: ", ".join(f"{k}={v}" for k, v in r["settings"].items()))
def test_every_add_and_the_final_elites_are_pyribss(run):
    archive = qdmeta.ProximityArchive(solution_dim=3, measure_dim=2, **run["settings"])
    for i, ((solution, objective, measures), expected) in enumerate(zip(BATCHES, run["adds"])):
        info = archive.add(solution, objective, measures)
        assert info["status"].tolist() == expected["status"], f"add {i}"
        np.testing.assert_allclose(info["novelty"], expected["novelty"], rtol=1e-12, atol=1e-15, err_msg=f"add {i}")
        assert sorted(info) == sorted(k for k in expected if k != "threshold_after"), f"add {i}"
        if "local_competition" in expected:
            assert info["local_competition"].tolist() == expected["local_competition"], f"add {i}"
            np.testing.assert_array_equal(info["value"], expected["value"], err_msg=f"add {i}")
        assert archive.novelty_threshold == pytest.approx(expected["threshold_after"], rel=1e-15), f"add {i}"
    for field, values in run["final"].items():
        np.testing.assert_array_equal(archive.data(field), np.array(values), err_msg=field)
    assert len(archive) == len(run["final"]["objective"]) == archive.stats.num_elites
    assert archive.stats.qd_score == pytest.approx(sum(run["final"]["objective"]), rel=1e-12)


def test_measures_index_of_and_the_cqd_score_work_on_it():
    archive = qdmeta.ProximityArchive(solution_dim=3, measure_dim=2, k_neighbors=2, novelty_threshold=0.1)
    solution, objective, measures = BATCHES[0]
    archive.add(solution, objective, measures)
    assert archive.index_of(archive.data("measures")).tolist() == list(range(len(archive)))
    targets = np.random.default_rng(3).random((1, 20, 2))
    cqd = qdmeta.cqd_score(archive, iterations=1, target_points=targets, penalties=3, obj_min=-4, obj_max=4,
                           dist_max=np.sqrt(2))
    assert np.isfinite(cqd.mean) and cqd.mean > 0


def test_refuses_bad_settings_and_batches_in_one_line_naming_them():
    def archive(**settings):
        return qdmeta.ProximityArchive(**{"solution_dim": 3, "measure_dim": 2, "k_neighbors": 2,
                                          "novelty_threshold": 0.1, **settings})

    assert "k_neighbors (0)" in refusal(lambda: archive(k_neighbors=0))
    assert "novelty_threshold (-1)" in refusal(lambda: archive(novelty_threshold=-1.0))
    assert "threshold_decay_rate (2)" in refusal(lambda: archive(threshold_decay_rate=2.0))
    a = archive()
    assert "measures must have shape (n, 2), not (4, 3)" in refusal(lambda: a.add(np.zeros((4, 3)), np.zeros(4), np.zeros((4, 3))))
    assert "solution must have shape (4, 3)" in refusal(lambda: a.add(np.zeros((3, 3)), np.zeros(4), np.zeros((4, 2))))
    assert "objective must be finite" in refusal(lambda: a.add(np.zeros((1, 3)), [np.nan], np.zeros((1, 2))))
    assert "objective must be given" in refusal(lambda: archive(local_competition=True).add(np.zeros((1, 3)), None, np.zeros((1, 2))))
    assert "index_of needs at least one elite" in refusal(lambda: a.index_of(np.zeros((1, 2))))
    assert "unknown field 'fitness'" in refusal(lambda: a.data("fitness"))
    assert len(a) == 0 and a.empty

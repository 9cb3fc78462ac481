"""qdmeta.cqd_score against pyribs 0.12's cqd_score on the same archives and target points
(pyribs_reference/cqd.json, written by pyribs_reference/make_cqd_reference.py), and its
refusals."""

import json
import pathlib

import numpy as np
import pytest

import qdmeta

REFERENCE = json.loads((pathlib.Path(__file__).parent / "pyribs_reference" / "cqd.json").read_text())


def reference_archive():
    measures = np.array(REFERENCE["measures"])
    archive = qdmeta.GridArchive(solution_dim=2, dims=[10, 10], ranges=[(0, 1), (0, 1)])
    archive.add(measures, np.array(REFERENCE["objectives"]), measures)
    assert len(archive) == len(REFERENCE["objectives"])
    return archive


def score(archive, case):
    order = case["dist_ord"]
    return qdmeta.cqd_score(
        archive,
        iterations=case["iterations"],
        target_points=np.array(case["target_points"]),
        penalties=case["penalties"],
        obj_min=case["obj_min"],
        obj_max=case["obj_max"],
        dist_max=case["dist_max"],
        dist_ord=np.inf if order == "inf" else order,
    )


@pytest.mark.parametrize("case", [c for c in REFERENCE["cases"] if c["obj_min"] == 0], ids=lambda c: c["name"])
def test_equals_pyribs_where_obj_min_is_zero(case):
    result = score(reference_archive(), case)
    np.testing.assert_allclose(result.scores, case["pyribs_scores"], rtol=1e-12, atol=0)
    assert result.mean == pytest.approx(case["pyribs_mean"], rel=1e-12)
    assert result.iterations == case["iterations"] and result.target_points.shape[0] == case["iterations"]


def test_differs_from_pyribs_by_its_missing_obj_min_term_otherwise():
    # pyribs normalises f / (obj_max - obj_min); qdmeta (f - obj_min) / (obj_max - obj_min): each
    # (target, penalty) term is larger by -obj_min / (obj_max - obj_min).
    (case,) = [c for c in REFERENCE["cases"] if c["obj_min"] != 0]
    result = score(reference_archive(), case)
    targets = len(case["target_points"][0])
    shift = -case["obj_min"] / (case["obj_max"] - case["obj_min"]) * targets * len(result.penalties)
    assert shift != 0
    np.testing.assert_allclose(result.scores, np.array(case["pyribs_scores"]) + shift, rtol=1e-12, atol=0)


def test_penalties_given_as_a_count_are_spread_over_zero_to_one():
    result = score(reference_archive(), REFERENCE["cases"][0])
    np.testing.assert_array_equal(result.penalties, np.linspace(0, 1, 5))


def test_refuses_bad_arguments_in_one_line_naming_them():
    archive = reference_archive()
    good = dict(iterations=1, target_points=np.zeros((1, 3, 2)), penalties=2, obj_min=0, obj_max=1, dist_max=1)
    cases = [
        (dict(target_points=np.zeros((1, 3, 3))), "target_points must have shape (1, n, 2)"),
        (dict(iterations=2), "target_points must have shape (2, n, 2)"),
        (dict(penalties=0), "penalties (0) must be a count >= 1"),
        (dict(penalties=np.zeros((2, 2))), "penalties must be a count or a 1-D array"),
        (dict(penalties=[0.5, 2.0]), "penalty 2 is outside [0, 1]"),
        (dict(obj_max=0), "obj_max (0) must be finite and above obj_min (0)"),
        (dict(dist_max=-1), "dist_max (-1) must be finite and > 0"),
        (dict(dist_ord="fro"), "dist_ord 'fro' is not a vector norm's order"),
        (dict(dist_ord=0.5), "dist_ord (0.5) must be a norm's order"),
        (dict(target_points=np.full((1, 3, 2), np.nan)), "target_points must be finite"),
    ]
    for change, words in cases:
        with pytest.raises(qdmeta.InputError) as caught:
            qdmeta.cqd_score(archive, **{**good, **change})
        message = str(caught.value)
        assert words in message and "\n" not in message, (change, message)
    empty = qdmeta.GridArchive(solution_dim=2, dims=[10, 10], ranges=[(0, 1), (0, 1)])
    with pytest.raises(qdmeta.InputError, match="no elite"):
        qdmeta.cqd_score(empty, **good)

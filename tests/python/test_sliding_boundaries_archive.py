"""qdmeta.SlidingBoundariesArchive against pyribs 0.12's SlidingBoundariesArchive on the same
batches (pyribs_reference/sliding.json, written by pyribs_reference/make_sliding_reference.py):
each add's statuses and values, the boundaries after it (through remaps with a full, rolling
buffer), and the elites left, in pyribs's order; then its refusals."""

import json
import pathlib

import numpy as np
import pytest

import qdmeta
from refusals import refusal

REFERENCE = json.loads((pathlib.Path(__file__).parent / "pyribs_reference" / "sliding.json").read_text())


@pytest.mark.parametrize("run", REFERENCE["runs"], ids=lambda r: f"dims={r['settings']['dims']}")
def test_every_add_the_boundaries_and_the_final_elites_are_pyribss(run):
    archive = qdmeta.SlidingBoundariesArchive(solution_dim=2, **run["settings"])
    for i, (batch, expected) in enumerate(zip(run["batches"], run["adds"])):
        info = archive.add(*(np.array(part) for part in batch))
        assert info["status"].tolist() == expected["status"], f"add {i}"
        np.testing.assert_array_equal(info["value"], expected["value"], err_msg=f"add {i}")
        for mine, theirs in zip(archive.boundaries, expected["boundaries"]):
            np.testing.assert_array_equal(mine, np.array(theirs, dtype=float)[: len(mine)], err_msg=f"add {i}")
    for field, values in run["final"].items():
        np.testing.assert_array_equal(archive.data(field), np.array(values), err_msg=field)
    assert archive.stats.num_elites == len(archive) == len(run["final"]["index"])
    assert archive.stats.coverage == len(archive) / np.prod(run["settings"]["dims"])


def test_before_a_remap_the_cells_are_the_even_grid_of_the_ranges():
    archive = qdmeta.SlidingBoundariesArchive(solution_dim=1, dims=[4, 2], ranges=[(0, 4), (0, 1)])
    assert archive.boundaries[0].tolist() == [0, 1, 2, 3, 4] and archive.boundaries[1].tolist() == [0, 0.5, 1]
    # Row-major cells, the last measure fastest; outside the ranges goes to the edge cells; on a
    # boundary, to the cell above it (cell (2, 1)).
    assert archive.index_of(np.array([[0.5, 0.2], [3.5, 0.9], [-9, 9], [2.0, 0.5]])).tolist() == [0, 7, 1, 5]


def test_refuses_bad_settings_and_batches_in_one_line_naming_them():
    def archive(**settings):
        return qdmeta.SlidingBoundariesArchive(**{"solution_dim": 2, "dims": [3, 3], "ranges": [(0, 1), (0, 1)],
                                                  **settings})

    assert "ranges has 1 pairs, dims 2 measures" in refusal(lambda: archive(ranges=[(0, 1)]))
    assert "ranges[1] (1, 0)" in refusal(lambda: archive(ranges=[(0, 1), (1, 0)]))
    assert "dims[0] (0)" in refusal(lambda: archive(dims=[0, 3]))
    assert "remap_frequency (0)" in refusal(lambda: archive(remap_frequency=0))
    assert "buffer_capacity (0)" in refusal(lambda: archive(buffer_capacity=0))
    a = archive()
    assert "measures must have shape (n, 2), not (2, 3)" in refusal(lambda: a.add(np.zeros((2, 2)), np.zeros(2), np.zeros((2, 3))))
    assert "objective must be finite" in refusal(lambda: a.add(np.zeros((1, 2)), [np.inf], np.zeros((1, 2))))
    assert "unknown field 'fitness'" in refusal(lambda: a.data("fitness"))
    assert len(a) == 0 and a.empty

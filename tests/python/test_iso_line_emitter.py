"""qdmeta.IsoLineEmitter against pyribs's IsoLineEmitter: the mean and covariance of its rows over
a fixed archive (pyribs_reference/iso_line.json, written by make_iso_line_reference.py with
pyribs 0.12), with bounds and from x0 on an empty archive; same seed same bits, pickling, and
the arguments refused."""
import json
import pathlib
import pickle

import numpy as np
import pytest

import qdmeta

REFERENCE = json.loads((pathlib.Path(__file__).parent / "pyribs_reference" / "iso_line.json").read_text())
ROWS = 400_000


def archive(filled=True):
    a = qdmeta.GridArchive(solution_dim=2, dims=[3], ranges=[(0.0, 3.0)])
    if filled:
        a.add(np.array(REFERENCE["elites"]), [1.0, 2.0, 3.0], [[0.5], [1.5], [2.5]])
    return a


def rows(case, seed=1, batch_size=ROWS):
    kwargs = REFERENCE[case]["kwargs"]
    a = archive(case != "empty")
    emitter = qdmeta.IsoLineEmitter(a, x0=[0.5, -0.5], batch_size=batch_size, seed=seed, **kwargs)
    return qdmeta.Scheduler(a, [emitter]).ask().astype(np.float64)


@pytest.mark.parametrize("case", ["unbounded", "bounded", "empty"])
def test_the_rows_mean_and_covariance_are_pyribss(case):
    # Standard errors at 400,000 rows each: about 0.005 for a mean, under 0.05 for a covariance
    # here. A line normal drawn per gene would give cov[0, 1] = -0.89 unbounded, not -2.62.
    x = rows(case)
    ref = REFERENCE[case]
    assert ref["rows"] == ROWS
    np.testing.assert_allclose(x.mean(axis=0), ref["mean"], atol=0.04)
    np.testing.assert_allclose(np.cov(x.T, bias=True), ref["cov"], atol=0.3)
    if case == "bounded":
        assert x.min() == -1.0 and x.max() == 3.0


def test_the_same_seed_gives_the_same_bits_and_a_pickled_emitter_continues_them():
    assert np.array_equal(rows("unbounded", 5, 50), rows("unbounded", 5, 50))
    assert not np.array_equal(rows("unbounded", 5, 50), rows("unbounded", 6, 50))
    a = archive()
    scheduler = qdmeta.Scheduler(a, [qdmeta.IsoLineEmitter(a, x0=[0.0, 0.0], batch_size=8, seed=3)])
    scheduler.ask()
    scheduler.tell(np.ones(8), np.full((8, 1), 1.5))
    twin = pickle.loads(pickle.dumps(scheduler))
    assert np.array_equal(twin.ask(), scheduler.ask())


def test_refuses_bad_arguments_naming_them():
    a = archive()
    with pytest.raises(qdmeta.InputError, match="x0 is None: give the first parent"):
        qdmeta.IsoLineEmitter(a)
    with pytest.raises(qdmeta.InputError, match=r"^emitters\.iso_sigma = -1 is out of range: must be a number >= 0$"):
        qdmeta.IsoLineEmitter(a, x0=[0.0, 0.0], iso_sigma=-1.0)
    with pytest.raises(qdmeta.InputError, match="x0 has 3 values; the archive's solution_dim is 2"):
        qdmeta.IsoLineEmitter(a, x0=[0.0, 0.0, 0.0])
    with pytest.raises(qdmeta.InputError, match="bounds differ between genes"):
        qdmeta.IsoLineEmitter(a, x0=[0.0, 0.0], bounds=[(0.0, 1.0), (0.0, 2.0)])

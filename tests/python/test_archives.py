"""The Python archives: statistics computed by hand, pyribs's cell numbering and column names,
statuses of a batch add, and errors that name the argument."""
import importlib.util
import math

import numpy as np
import pytest

import qdmeta


def grid(**kw):
    args = dict(solution_dim=3, dims=[4, 5], lower=0.0, upper=1.0, qd_offset=0.0)
    args.update(kw)
    return qdmeta.GridArchive(**args)


def test_statuses_and_statistics_by_hand():
    a = grid(qd_offset=-10.0)
    solutions = np.arange(15, dtype=np.float32).reshape(5, 3) / 15
    objectives = np.array([-3.0, -1.0, -2.0, -5.0, -4.0], dtype=np.float32)
    # Rows 0, 1 and 2 share cell (0, 0); row 3 is in (3, 4); row 4 in (1, 2).
    measures = np.array([[0.1, 0.1], [0.2, 0.05], [0.0, 0.0], [0.99, 1.0], [0.3, 0.5]], dtype=np.float32)
    status = a.add(solutions, objectives, measures)
    assert status.tolist() == [2, 1, 0, 2, 2]  # new, improved (-1 > -3), not added (-2 < -1), new, new
    s = a.stats
    assert s.num_elites == 3 and len(a) == 3
    assert s.coverage == pytest.approx(3 / 20)
    kept = [-1.0, -5.0, -4.0]
    assert s.qd_score == pytest.approx(sum(f + 10.0 for f in kept))
    assert s.norm_qd_score == pytest.approx(sum(f + 10.0 for f in kept) / 20)
    assert s.obj_max == pytest.approx(-1.0)
    assert s.obj_mean == pytest.approx(np.mean(kept))
    assert s.as_dict()["num_elites"] == 3


def test_cells_are_row_major_as_in_pyribs():
    a = grid()
    m = np.array([[0.0, 0.0], [0.0, 0.99], [0.26, 0.0], [0.99, 0.99]], dtype=np.float32)
    assert a.index_of(m).tolist() == [0, 4, 5, 19]
    a.add(np.zeros((4, 3)), np.zeros(4), m)
    d = a.data()
    assert d["index"].tolist() == [0, 4, 5, 19]
    assert d["measures"].shape == (4, 2) and d["solution"].shape == (4, 3)
    assert d["objective"].dtype == np.float32


def test_invalid_rows_never_enter_and_better_rows_replace():
    a = grid()
    m = np.full((3, 2), 0.5, dtype=np.float32)
    status = a.add(np.array([[0.1] * 3, [0.2] * 3, [0.3] * 3]), np.array([1.0, 5.0, 5.0]), m,
                   valid=np.array([True, False, True]))
    assert status.tolist() == [2, 0, 1]
    assert a.data()["solution"][0].tolist() == pytest.approx([0.3] * 3)


def test_add_names_the_wrong_argument():
    a = grid()
    with pytest.raises(ValueError, match=r"solutions must have shape \(n, 3\), got \(2, 4\)"):
        a.add(np.zeros((2, 4)), np.zeros(2), np.zeros((2, 2)))
    with pytest.raises(ValueError, match=r"objectives must have shape \(2,\), got \(3,\)"):
        a.add(np.zeros((2, 3)), np.zeros(3), np.zeros((2, 2)))
    with pytest.raises(TypeError, match="measures must hold numbers"):
        a.add(np.zeros((2, 3)), np.zeros(2), np.array([["a", "b"], ["c", "d"]]))
    with pytest.raises(qdmeta.InputError, match="objective"):
        a.add(np.zeros((2, 3)), np.array([0.0, math.nan]), np.zeros((2, 2)))
    assert isinstance(qdmeta.InputError("x"), ValueError) and isinstance(qdmeta.InputError("x"), qdmeta.Error)
    assert len(a) == 0, "a refused batch adds nothing"


def test_as_pandas_has_pyribs_columns():
    pytest.importorskip("pandas")
    a = grid()
    a.add(np.full((1, 3), 0.25), np.array([2.0]), np.array([[0.5, 0.5]]))
    df = a.as_pandas()
    assert list(df.columns) == ["index", "objective", "measures_0", "measures_1", "solution_0", "solution_1",
                                "solution_2"]
    assert df["objective"].tolist() == [2.0]


def test_cvt_archive_puts_each_elite_in_its_nearest_centroids_cell(tmp_path):
    centroids = qdmeta.cvt_centroids(2, cells=40, samples=4000, seed=3, cache_dir=tmp_path)
    assert centroids.shape == (40, 2)
    again = qdmeta.cvt_centroids(2, cells=40, samples=4000, seed=3, cache_dir=tmp_path)  # from the cache
    assert np.array_equal(centroids, again)
    assert len(list(tmp_path.iterdir())) == 1
    a = qdmeta.CvtArchive(solution_dim=2, centroids=centroids)
    rng = np.random.default_rng(1)
    m = rng.random((500, 2), dtype=np.float32)
    a.add(m, -np.sum(m, axis=1), m)
    d = a.data()
    nearest = np.argmin(((d["measures"][:, None, :] - centroids[None, :, :]) ** 2).sum(axis=2), axis=1)
    assert np.array_equal(nearest, d["index"])
    assert a.stats.num_elites == len(d["index"]) == 40
    with pytest.raises(ValueError, match="centroids"):
        qdmeta.CvtArchive(solution_dim=2, centroids=np.zeros(3))


def test_unstructured_archive_adds_far_points_and_rejects_near_ones():
    a = qdmeta.UnstructuredArchive(solution_dim=2, measure_dim=2, target_size=100)
    far = np.array([[0, 0], [1, 0], [0, 1]], dtype=np.float32)
    assert a.add(far, np.zeros(3), far, threshold=0.5).tolist() == [2, 2, 2]
    near = np.array([[0.01, 0.0]], dtype=np.float32)
    assert a.add(near, np.array([-1.0]), near, threshold=0.5).tolist() == [0]
    assert a.stats.num_elites == 3 and a.stats.coverage == pytest.approx(0.03)
    assert a.data()["index"].tolist() == [0, 1, 2]
    if importlib.util.find_spec("pandas"):
        assert list(a.as_pandas().columns)[:4] == ["index", "objective", "measures_0", "measures_1"]
    with pytest.raises(ValueError, match="threshold"):
        a.add(far, np.zeros(3), far, threshold=0.0)


def test_a_range_too_narrow_to_bin_is_refused_at_construction():
    # Its bins' width underflows: index_of once gave -9223372036854775808 for a measure at lower.
    with pytest.raises(qdmeta.InputError) as info:
        qdmeta.GridArchive(solution_dim=1, dims=[10], lower=0.0, upper=1e-320)
    assert str(info.value).startswith("archive range [0, 1e-320] is too narrow: upper - lower = 1e-320 is below")
    with pytest.raises(qdmeta.InputError, match="too wide"):
        qdmeta.GridArchive(solution_dim=1, dims=[10], lower=-1e308, upper=1e308)
    # A narrow range that can be binned is kept (1e-301 is 0 as a float32 measure: bin 0).
    narrow = qdmeta.GridArchive(solution_dim=1, dims=[10], lower=0.0, upper=1e-300)
    assert narrow.index_of(np.array([[0.0], [1e-301], [1.0]])).tolist() == [0, 0, 9]


def test_a_seed_out_of_range_is_named_with_its_range(tmp_path):
    for seed in (2**70, -1):
        with pytest.raises(qdmeta.InputError) as info:
            qdmeta.cvt_centroids(2, cells=4, samples=100, seed=seed, cache_dir=tmp_path)
        assert str(info.value) == f"seed = {seed} is out of range: must be in [0, 9223372036854775807]"
    with pytest.raises(TypeError, match="^seed must be an integer, got <class 'float'>$"):
        qdmeta.cvt_centroids(2, cells=4, samples=100, seed=1.5, cache_dir=tmp_path)
    assert qdmeta.cvt_centroids(2, cells=4, samples=100, seed=np.int64(3), cache_dir=tmp_path).shape == (4, 2)

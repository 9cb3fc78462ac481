"""What a pyribs user asks of an archive besides add(): iteration over the elites, retrieve() by
measures (checked against cells and nearest points computed here with numpy), sample_elites()
(seeded, uniform over the elites) and Algorithm.archive / Algorithm.retrieve."""
import numpy as np
import pytest

import qdmeta

FIELDS = {"index", "objective", "measures", "solution"}


def filled_grid(seed=1):
    a = qdmeta.GridArchive(solution_dim=3, dims=[4, 5], seed=seed)
    rng = np.random.default_rng(0)
    a.add(rng.random((60, 3), dtype=np.float32), rng.normal(size=60).astype(np.float32),
          rng.random((60, 2), dtype=np.float32) * np.array([1.0, 0.55], dtype=np.float32))
    return a


def test_iteration_gives_each_elite_with_pyribs_fields_in_cell_order():
    a = filled_grid()
    elites = list(a)
    d = a.data()
    assert len(elites) == len(a) == len(d["index"]) > 5
    for i, e in enumerate(elites):
        assert set(e) == FIELDS
        assert isinstance(e["index"], int) and isinstance(e["objective"], float)
        assert e["index"] == d["index"][i] and e["objective"] == d["objective"][i]
        assert e["solution"].shape == (3,) and np.array_equal(e["solution"], d["solution"][i])
        assert np.array_equal(e["measures"], d["measures"][i])
    assert [e["index"] for e in elites] == sorted(e["index"] for e in elites)
    # A snapshot: adding while iterating changes neither the iteration nor fails it.
    it = iter(a)
    first = next(it)
    a.add(np.zeros((1, 3)), np.array([100.0]), np.array([[0.99, 0.99]]))
    assert len([first] + list(it)) == len(elites)
    with_base = qdmeta.GridArchive(solution_dim=2, dims=[3], base_feature_dim=2)
    with_base.add(np.zeros((1, 2)), np.ones(1), np.array([[0.5]]), base_features=np.array([[0.25, 0.75]]))
    (only,) = list(with_base)
    assert set(only) == FIELDS | {"base_features"} and only["base_features"].tolist() == [0.25, 0.75]


def test_grid_retrieve_gives_the_elite_of_each_rows_cell_and_sentinels_elsewhere():
    a = filled_grid()
    d = a.data()
    by_cell = {int(c): i for i, c in enumerate(d["index"])}
    # Every cell's centre: 4 x 5 = 20 rows, cell (i, j) = 5 i + j in pyribs's row-major order.
    centres = np.array([[(i + 0.5) / 4, (j + 0.5) / 5] for i in range(4) for j in range(5)], dtype=np.float32)
    occupied, elites = a.retrieve(centres)
    assert occupied.dtype == bool and occupied.shape == (20,) and set(elites) == FIELDS
    assert 0 < occupied.sum() < 20  # measures_1 < 0.55 leaves the top cells empty
    for cell in range(20):
        if cell in by_cell:
            row = by_cell[cell]
            assert occupied[cell] and elites["index"][cell] == cell
            assert elites["objective"][cell] == d["objective"][row]
            assert np.array_equal(elites["solution"][cell], d["solution"][row])
            assert np.array_equal(elites["measures"][cell], d["measures"][row])  # the elite's, not the query
        else:
            assert not occupied[cell] and elites["index"][cell] == -1
            assert np.isnan(elites["objective"][cell]) and np.isnan(elites["solution"][cell]).all()
            assert np.isnan(elites["measures"][cell]).all()
    hit, single = a.retrieve_single(centres[int(d["index"][0])])
    assert hit is True and single["index"] == d["index"][0] and single["objective"] == d["objective"][0]
    miss, empty = a.retrieve_single([0.99, 0.99])
    assert miss is False and empty["index"] == -1 and np.isnan(empty["objective"])


def test_cvt_retrieve_finds_the_nearest_centroids_elite():
    rng = np.random.default_rng(5)
    centroids = rng.random((40, 3)).astype(np.float32)
    a = qdmeta.CvtArchive(solution_dim=4, centroids=centroids)
    measures = rng.random((200, 3), dtype=np.float32)
    a.add(rng.random((200, 4), dtype=np.float32), rng.normal(size=200).astype(np.float32), measures)
    queries = rng.random((500, 3), dtype=np.float32)
    nearest = np.argmin(((queries[:, None, :] - centroids[None, :, :]) ** 2).sum(axis=2), axis=1)
    assert np.array_equal(a.index_of(queries), nearest)
    occupied, elites = a.retrieve(queries)
    d = a.data()
    filled = set(d["index"].tolist())
    assert occupied.tolist() == [int(c) in filled for c in nearest]
    assert np.array_equal(elites["index"], np.where(occupied, nearest, -1))
    objective_of = dict(zip(d["index"].tolist(), d["objective"].tolist()))
    for q in np.flatnonzero(occupied):
        assert elites["objective"][q] == objective_of[int(nearest[q])]


def test_unstructured_retrieve_finds_the_nearest_member():
    rng = np.random.default_rng(6)
    a = qdmeta.UnstructuredArchive(solution_dim=2, measure_dim=2, target_size=100)
    empty_occupied, _ = a.retrieve(np.zeros((3, 2)))
    assert not empty_occupied.any()
    a.add(rng.random((300, 2), dtype=np.float32), rng.normal(size=300).astype(np.float32),
          rng.random((300, 2), dtype=np.float32), threshold=0.05)
    d = a.data()
    queries = rng.random((100, 2), dtype=np.float32)
    nearest = np.argmin(((queries[:, None, :] - d["measures"][None, :, :]) ** 2).sum(axis=2), axis=1)
    occupied, elites = a.retrieve(queries)
    assert occupied.all()
    assert np.array_equal(elites["index"], d["index"][nearest])
    assert np.array_equal(elites["measures"], d["measures"][nearest])
    assert [e["index"] for e in a] == list(range(len(a)))


def test_retrieve_names_bad_measures():
    a = filled_grid()
    with pytest.raises(ValueError, match=r"measures must have shape \(n, 2\), got \(3, 3\)"):
        a.retrieve(np.zeros((3, 3)))
    with pytest.raises(qdmeta.InputError, match="measures row 1 column 0 is nan"):
        a.retrieve(np.array([[0.1, 0.1], [np.nan, 0.2]]))
    with pytest.raises(qdmeta.InputError, match="measures row 0 column 1 is inf"):
        a.index_of(np.array([[0.1, np.inf]]))


def test_sample_elites_is_seeded_and_uniform_over_the_elites():
    a, b, c = filled_grid(seed=3), filled_grid(seed=3), filled_grid(seed=4)
    s = a.sample_elites(1000)
    assert set(s) == FIELDS and s["solution"].shape == (1000, 3)
    assert np.array_equal(s["index"], b.sample_elites(1000)["index"])  # the same seed, the same draws
    assert not np.array_equal(s["index"], c.sample_elites(1000)["index"])
    assert not np.array_equal(s["index"], a.sample_elites(1000)["index"])  # the next call, the next stream
    d = a.data()
    row_of = {int(i): r for r, i in enumerate(d["index"])}
    for k in range(0, 1000, 97):  # each sample is a whole elite
        r = row_of[int(s["index"][k])]
        assert s["objective"][k] == d["objective"][r] and np.array_equal(s["solution"][k], d["solution"][r])
    counts = np.bincount([row_of[int(i)] for i in a.sample_elites(200_000)["index"]], minlength=len(a))
    expected = 200_000 / len(a)
    assert np.all(np.abs(counts - expected) < 6 * np.sqrt(expected))  # every elite drawn about equally


def test_sample_elites_without_replacement_and_its_errors():
    a = filled_grid()
    everyone = a.sample_elites(len(a), replace=False)
    assert sorted(everyone["index"].tolist()) == a.data()["index"].tolist()
    with pytest.raises(qdmeta.InputError, match="more than the archive's"):
        a.sample_elites(len(a) + 1, replace=False)
    with pytest.raises(qdmeta.InputError, match="the archive is empty"):
        qdmeta.GridArchive(solution_dim=3, dims=[4]).sample_elites(1)
    assert a.sample_elites(0)["index"].shape == (0,)


def sphere(x):
    return -np.sum((x - 0.5) ** 2, axis=1), x[:, :2].copy()


def sphere_task():
    return qdmeta.Task(sphere, genotype_size=5, base_feature_size=2, name="sphere")


def test_algorithm_archive_is_a_copy_of_the_grid_it_runs():
    algo = qdmeta.Algorithm({"algorithm": "map-elites", "seed": 9, "archive": {"bins": [8, 6]},
                             "map_elites": {"batch_size": 50, "initial_population": 100}}, task=sphere_task())
    for _ in range(5):
        algo.step(threads=1)
    archive = algo.archive
    assert isinstance(archive, qdmeta.GridArchive) and archive.dims == [8, 6] and archive.seed == 9
    d, e = archive.data(), algo.data()
    assert all(np.array_equal(d[k], e[k]) for k in e)
    queries = np.random.default_rng(0).random((50, 2), dtype=np.float32)
    for x, y in zip(algo.retrieve(queries), archive.retrieve(queries)):
        if isinstance(x, dict):
            assert all(np.array_equal(x[k], y[k], equal_nan=True) for k in x)
        else:
            assert np.array_equal(x, y)
    archive.clear()
    assert len(algo.archive) == algo.stats.num_elites > 0


def test_cvt_map_elites_archive_has_its_centroids_before_the_first_step(tmp_path):
    cvt = {"centroids": 30, "samples": 3000, "seed": 4, "cache_dir": str(tmp_path)}
    algo = qdmeta.Algorithm({"algorithm": "cvt-map-elites", "seed": 2, "cvt": cvt,
                             "map_elites": {"batch_size": 50, "initial_population": 100}}, task=sphere_task())
    before = algo.archive
    assert isinstance(before, qdmeta.CvtArchive) and len(before) == 0
    centroids = qdmeta.cvt_centroids(2, cells=30, samples=3000, seed=4, cache_dir=tmp_path)
    assert np.array_equal(before.centroids, centroids)
    for _ in range(4):
        algo.step(threads=1)
    after = algo.archive
    assert len(after) == algo.stats.num_elites > 5
    d = after.data()
    nearest = np.argmin(((d["measures"][:, None, :] - centroids[None]) ** 2).sum(axis=2), axis=1)
    assert np.array_equal(d["index"], nearest)
    occupied, elites = algo.retrieve(d["measures"])
    assert occupied.all() and np.array_equal(elites["index"], d["index"])


def test_aurora_and_qd_meta_archives():
    aurora = qdmeta.Algorithm({"algorithm": "aurora", "seed": 3,
                               "aurora": {"batch_size": 50, "initial_population": 200, "max_epochs": 3}},
                              task=sphere_task())
    for _ in range(3):
        aurora.step(threads=1)
    a = aurora.archive
    assert isinstance(a, qdmeta.UnstructuredArchive) and len(a) == aurora.stats.num_elites > 0
    assert a.measure_dim == 2 and "base_features" in a.data()  # latent codes; the base features kept
    qd = qdmeta.Algorithm({"algorithm": "qd-meta", "seed": 3, "archive": {"bins": [5, 5]},
                           "control": {"kind": "static", "generations": 2},
                           "qd_meta": {"meta_population": 2, "batch_size": 30, "initial_population": 100,
                                       "database_capacity": 2000},
                           "task": {"name": "rastrigin", "dimensions": 4}})
    qd.step(threads=1)
    best = qd.archive
    assert isinstance(best, qdmeta.GridArchive) and best.dims == [5, 5]
    d, e = best.data(), qd.data()
    assert all(np.array_equal(d[k], e[k]) for k in e) and len(d["index"]) > 0

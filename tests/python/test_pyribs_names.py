"""pyribs's names on qdmeta's archives, with pyribs's meanings: data(fields, return_type),
field_list, dtypes, best_elite, empty, add_single, qd_score_offset, and a GridArchive's
boundaries, interval_size, index_of_single, grid_to_int_index and int_to_grid_index."""
import pickle

import numpy as np
import pytest

import qdmeta


def filled_grid():
    archive = qdmeta.GridArchive(solution_dim=2, dims=[4, 5], lower=-1.0, upper=1.0, qd_offset=-3.0)
    archive.add(np.array([[0.1, 0.2], [0.3, 0.4], [0.5, 0.6]]), np.array([1.0, 7.0, 7.0]),
                np.array([[-0.9, -0.9], [0.9, 0.9], [0.9, -0.9]]))
    return archive


def test_data_selects_fields_and_return_types_as_pyribs():
    archive = filled_grid()
    assert archive.field_list == ["solution", "objective", "measures", "index"]
    assert archive.dtypes == {"solution": np.float32, "objective": np.float32, "measures": np.float32,
                              "index": np.int64}
    everything = archive.data()
    assert list(everything) == ["solution", "objective", "measures", "index"]
    assert everything["index"].tolist() == [0, 15, 19]
    assert archive.data("objective").tolist() == [1.0, 7.0, 7.0]
    objective, index = archive.data(["objective", "index"], return_type="tuple")
    assert objective.tolist() == [1.0, 7.0, 7.0] and index.tolist() == [0, 15, 19]
    assert list(archive.data(("measures",))) == ["measures"]
    with pytest.raises(ValueError, match=r"^data\(\): no field 'threshold': the fields are solution, objective, "):
        archive.data(["threshold"])
    with pytest.raises(ValueError, match="return_type must be"):
        archive.data(return_type="list")


def test_data_as_pandas_keeps_the_fields_asked_for():
    pytest.importorskip("pandas")
    frame = filled_grid().data(["objective", "measures"], return_type="pandas")
    assert list(frame.columns) == ["objective", "measures_0", "measures_1"]
    assert frame["objective"].tolist() == [1.0, 7.0, 7.0]


def test_best_elite_empty_and_qd_score_offset():
    archive = filled_grid()
    best = archive.best_elite
    assert best["index"] == 15 and best["objective"] == 7.0  # the lower index of two equals
    assert np.allclose(best["solution"], [0.5, 0.6]) and np.allclose(best["measures"], [0.9, -0.9])
    assert not archive.empty and archive.qd_score_offset == -3.0
    archive.clear()
    assert archive.empty and archive.best_elite is None
    assert qdmeta.UnstructuredArchive(solution_dim=2, measure_dim=2).empty


def test_add_single_adds_one_solution_and_returns_its_status():
    archive = qdmeta.GridArchive(solution_dim=2, dims=[4, 4])
    assert archive.add_single([0.1, 0.2], 1.0, [0.5, 0.5]) == 2
    assert archive.add_single(np.array([0.3, 0.3]), 2.0, np.array([0.5, 0.5])) == 1
    assert archive.add_single([0.9, 0.9], 0.5, [0.5, 0.5]) == 0
    assert len(archive) == 1 and archive.best_elite["objective"] == 2.0


def test_a_grids_boundaries_and_index_conversions():
    archive = filled_grid()
    edges = archive.boundaries
    assert len(edges) == 2 and np.allclose(edges[0], [-1, -0.5, 0, 0.5, 1]) and len(edges[1]) == 6
    assert archive.interval_size.tolist() == [2.0, 2.0]
    assert archive.index_of_single([0.9, -0.9]) == 15 and isinstance(archive.index_of_single([0, 0]), int)
    grid = archive.int_to_grid_index([0, 15, 19])
    assert grid.tolist() == [[0, 0], [3, 0], [3, 4]]
    assert archive.grid_to_int_index(grid).tolist() == [0, 15, 19]
    # The same cell numbering as index_of: measure 0 is the slower-varying coordinate.
    assert archive.grid_to_int_index([[2, 3]])[0] == archive.index_of_single([0.2, 0.3])
    with pytest.raises(ValueError, match=r"must be \(n, 2\)"):
        archive.grid_to_int_index([1, 2])


def test_an_algorithms_archive_has_the_names_too():
    task = qdmeta.Task(lambda x: (-np.sum(x * x, axis=1), x[:, :2].copy()), genotype_size=3, base_feature_size=2,
                       name="t")
    algo = qdmeta.Algorithm({"algorithm": "map-elites", "archive": {"bins": [4, 4]},
                             "map_elites": {"batch_size": 10, "initial_population": 10}}, task=task)
    algo.step()
    archive = algo.archive
    assert not archive.empty and archive.best_elite["objective"] == archive.data("objective").max()


def test_a_grid_takes_pyribs_ranges_one_pair_per_measure():
    archive = qdmeta.GridArchive(solution_dim=1, dims=[4, 10], ranges=[(-2.0, 2.0), (0.0, 100.0)])
    assert archive.lower_bounds == [-2.0, 0.0] and archive.upper_bounds == [2.0, 100.0]
    # No one bound is shared: lower/upper say which property to read, rather than the default 0/1.
    with pytest.raises(ValueError, match=r"^GridArchive\.lower: the measures have different ranges; read lower_bounds$"):
        archive.lower
    with pytest.raises(ValueError, match=r"^GridArchive\.upper: .* read upper_bounds$"):
        archive.upper
    shared = qdmeta.GridArchive(solution_dim=1, dims=[4, 4], ranges=[(-3.0, 5.0), (-3.0, 5.0)])
    assert (shared.lower, shared.upper) == (-3.0, 5.0)
    assert archive.interval_size.tolist() == [4.0, 100.0]
    measures = np.array([[-1.5, 95.0], [1.5, 5.0], [3.0, -7.0]])
    assert archive.index_of(measures).tolist() == [0 * 10 + 9, 3 * 10 + 0, 3 * 10 + 0]  # outside: edge bins
    status = archive.add(np.zeros((3, 1)), np.array([1.0, 2.0, 3.0]), measures)
    assert status.tolist() == [2, 2, 1]
    stored = archive.data()
    assert np.array_equal(stored["measures"], np.float32([[-1.5, 95.0], [3.0, -7.0]]))  # kept as given
    occupied, found = archive.retrieve([[-1.9, 99.0], [0.1, 50.0]])
    assert occupied.tolist() == [True, False] and found["index"].tolist() == [9, -1]
    assert np.allclose(archive.boundaries[1], np.linspace(0, 100, 11))
    restored = pickle.loads(pickle.dumps(archive))
    assert restored.lower_bounds == [-2.0, 0.0] and restored.index_of(measures).tolist() == [9, 30, 30]


def test_ranges_are_refused_when_they_do_not_fit():
    with pytest.raises(qdmeta.InputError, match=r"archive ranges: 1 lower and 1 upper bounds for 2 target features"):
        qdmeta.GridArchive(solution_dim=1, dims=[4, 4], ranges=[(0.0, 1.0)])
    with pytest.raises(qdmeta.InputError, match=r"archive range \[1, 0\] is invalid"):
        qdmeta.GridArchive(solution_dim=1, dims=[4, 4], ranges=[(0.0, 1.0), (1.0, 0.0)])
    with pytest.raises(ValueError, match=r"give ranges= or lower=/upper=, not both"):
        qdmeta.GridArchive(solution_dim=1, dims=[4, 4], lower=-1.0, ranges=[(0.0, 1.0), (0.0, 1.0)])

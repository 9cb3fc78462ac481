"""Integer and boolean arrays in and out of the module, element by element: a module built with
an old pybind11 once returned them with a zero stride under numpy 2 (every element read as the
first) while floats were right. scripts/test-numpy2.sh runs this file under numpy 2 too."""
import types

import numpy as np
import pytest

import qdmeta
from qdmeta import _numpy_check

CELLS = [0, 10, 99, 52]


def hundred_bins():
    return qdmeta.GridArchive(solution_dim=2, dims=[100], lower=0.0, upper=100.0)


def measures_of(cells):
    return np.array([[c + 0.5] for c in cells], dtype=np.float32)


def assert_elements(array, expected, dtype):
    assert array.dtype == dtype and array.shape == (len(expected),)
    assert array.strides == (array.itemsize,), "C-contiguous, one item apart"
    for i, want in enumerate(expected):
        assert array[i] == want, f"element {i}: {array[i]} != {want}"


def test_index_of_returns_each_rows_cell():
    assert_elements(hundred_bins().index_of(measures_of(CELLS)), CELLS, np.int64)


def test_the_elites_index_and_the_add_statuses_are_each_rows_own():
    a = hundred_bins()
    status = a.add(np.zeros((4, 2)), np.arange(4.0), measures_of(CELLS))
    assert_elements(status, [2, 2, 2, 2], np.uint8)
    status = a.add(np.zeros((3, 2)), np.array([5.0, -1.0, 0.0]), measures_of([10, 99, 7]))
    assert_elements(status, [1, 0, 2], np.uint8)  # improved, not added, new cell
    assert_elements(a.data()["index"], [0, 7, 10, 52, 99], np.int64)


def test_as_pandas_index_is_each_elites_cell():
    pytest.importorskip("pandas")
    a = hundred_bins()
    a.add(np.zeros((4, 2)), np.arange(4.0), measures_of(CELLS))
    df = a.as_pandas()
    assert df["index"].tolist() == sorted(CELLS)
    assert df["objective"].tolist() == [0.0, 1.0, 3.0, 2.0]


def test_task_evaluate_returns_each_rows_valid_flag():
    flags = [True, False, True, True, False, False, True]

    def half_valid(x):
        return x[:, 0], x, np.array(flags)

    task = qdmeta.Task(half_valid, genotype_size=1, base_feature_size=1, name="flags")
    _, _, valid = task.evaluate(np.full((len(flags), 1), 0.5, dtype=np.float32))
    assert_elements(valid, flags, np.bool_)
    _, _, builtin_valid = qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 3}).evaluate(np.zeros((5, 3)))
    assert_elements(builtin_valid, [True] * 5, np.bool_)


@pytest.mark.parametrize("valid", [np.array([False, True, False, True]), np.array([0, 7, 0, -1]),
                                   np.array([0, 1, 0, 1], dtype=np.uint8), [False, True, False, True]],
                         ids=["bool", "int64", "uint8", "list"])
def test_add_keeps_exactly_the_valid_rows(valid):
    a = hundred_bins()
    status = a.add(np.zeros((4, 2)), np.zeros(4), measures_of(CELLS), valid=valid)
    assert_elements(status, [0, 2, 0, 2], np.uint8)
    assert_elements(a.data()["index"], [10, 52], np.int64)


def test_tell_keeps_exactly_the_valid_rows():
    config = {"algorithm": "map-elites", "seed": 1, "archive": {"bins": [100]},
              "map_elites": {"batch_size": 4, "initial_population": 4}}
    task = qdmeta.Task(lambda x: (x[:, 0], x), genotype_size=1, base_feature_size=1, name="line")
    algo = qdmeta.Algorithm(config, task=task)
    algo.ask()
    algo.tell(np.zeros(4), measures_of(CELLS) / 100, np.array([True, False, False, True]))
    assert_elements(algo.data()["index"], [0, 52], np.int64)


def test_a_module_that_gets_the_arrays_wrong_refuses_to_import():
    _numpy_check.check(qdmeta._qdmeta, np)  # this build passes

    class StrideZeroGrid(qdmeta.GridArchive):
        def index_of(self, measures):
            return np.zeros(len(measures), dtype=np.int64)  # what numpy 2 saw: [0 0 0 0]

    broken = types.SimpleNamespace(**{n: getattr(qdmeta._qdmeta, n) for n in ("Task", "build_info")},
                                   GridArchive=StrideZeroGrid)
    with pytest.raises(ImportError) as info:
        _numpy_check.check(broken, np)
    message = str(info.value)
    assert "\n" not in message
    assert f"numpy {np.__version__}" in message and "GridArchive.index_of gave [0, 0, 0, 0]" in message
    assert "pip install ." in message


def test_the_module_sources_make_arrays_only_with_explicit_strides():
    """Under numpy 1 an array_t made from a shape alone is right; under numpy 2 and this pybind11 its
    strides are 0. ctest runs numpy 1, so the constructor itself is refused here (numpy_arrays.hpp's
    new_array gives the strides)."""
    import pathlib
    import re
    sources = pathlib.Path(__file__).resolve().parents[2] / "python" / "src"
    # A variable made from one argument: `py::array_t<double> out(n);` (two or more carry strides).
    shape_only = re.compile(r"array_t<[^>;]*>\s+\w+\s*[({]([^,;]*)[)}]\s*;")
    found = [f"{p.name}:{n}: {line.strip()}" for p in sorted(sources.glob("*.[ch]pp"))
             for n, line in enumerate(p.read_text().splitlines(), 1) if shape_only.search(line)]
    assert not found, "\n".join(found)

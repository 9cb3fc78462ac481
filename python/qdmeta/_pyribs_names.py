"""pyribs's names on qdmeta's archives, with pyribs's meanings, written over what the C++ archive
already answers (its data(), index_of(), len()): data(fields, return_type), field_list, dtypes,
best_elite, empty, add_single, qd_score_offset; a GridArchive also has boundaries,
interval_size, index_of_single, grid_to_int_index and int_to_grid_index."""
import numpy as np


def _field_list(self):
    """The fields data() gives, as pyribs 0.12 lists them ("index" last; no "threshold": qdmeta keeps none)."""
    fields = ["solution", "objective", "measures"]
    return fields + (["base_features"] if "base_features" in self._elite_arrays() else []) + ["index"]


def _dtypes(self):
    return {name: np.dtype(np.int64 if name == "index" else np.float32) for name in self.field_list}


def _data(self, fields=None, return_type="dict"):
    """pyribs's data(): every field and "index" (fields=None), the listed ones, or one field's
    array alone (fields a str); return_type "dict", "tuple" or "pandas"."""
    if return_type not in ("dict", "tuple", "pandas"):
        raise ValueError(f"data(): return_type must be 'dict', 'tuple' or 'pandas', got {return_type!r}")
    arrays = self._elite_arrays()
    names = [fields] if isinstance(fields, str) else self.field_list if fields is None else list(fields)
    unknown = [n for n in names if n not in arrays]
    if unknown:
        raise ValueError(f"data(): no field {unknown[0]!r}: the fields are {', '.join(self.field_list)}")
    if return_type == "pandas":
        frame = self.as_pandas()
        return frame[[c for c in frame.columns if any(c == n or c.startswith(n + "_") for n in names)]]
    if isinstance(fields, str):
        return arrays[fields]
    return {n: arrays[n] for n in names} if return_type == "dict" else tuple(arrays[n] for n in names)


def _best_elite(self):
    """The elite of highest objective (the lowest index among equals) as a dict, or None when empty."""
    arrays = self._elite_arrays()
    if len(arrays["index"]) == 0:
        return None
    best = int(np.argmax(arrays["objective"]))
    return {name: values[best] for name, values in arrays.items()}


def _add_single(self, solution, objective, measures, *rest, **named):
    """add() for one solution: its status (0, 1 or 2) as an int."""
    solution = np.asarray(solution, dtype=np.float32)[None]
    measures = np.asarray(measures, dtype=np.float32)[None]
    return int(self.add(solution, np.array([objective], dtype=np.float32), measures, *rest, **named)[0])


def _boundaries(self):
    """Per measure, the dims[i] + 1 edges of its bins, from lower to upper bound."""
    return [np.linspace(lo, hi, d + 1) for d, lo, hi in zip(self.dims, self.lower_bounds, self.upper_bounds)]


def _interval_size(self):
    return np.asarray(self.upper_bounds, dtype=np.float64) - np.asarray(self.lower_bounds, dtype=np.float64)


def _index_of_single(self, measures):
    return int(self.index_of(np.asarray(measures, dtype=np.float32)[None])[0])


def _grid_to_int_index(self, grid_indices):
    """(n, measure_dim) grid coordinates -> (n,) cell indices, row-major as the archive numbers them."""
    grid = np.asarray(grid_indices)
    if grid.ndim != 2 or grid.shape[1] != len(self.dims):
        raise ValueError(f"grid_to_int_index(): grid_indices must be (n, {len(self.dims)}), got {grid.shape}")
    return np.ravel_multi_index(tuple(grid.T), self.dims).astype(np.int64)


def _int_to_grid_index(self, int_indices):
    """(n,) cell indices -> (n, measure_dim) grid coordinates."""
    return np.stack(np.unravel_index(np.asarray(int_indices), self.dims), axis=1).astype(np.int64)


def add_pyribs_names(archive_classes, grid_class):
    for cls in archive_classes:
        cls._elite_arrays = cls.data
        cls.data = _data
        cls.field_list = property(_field_list)
        cls.dtypes = property(_dtypes)
        cls.best_elite = property(_best_elite)
        cls.empty = property(lambda self: len(self) == 0)
        cls.add_single = _add_single
    grid_class.boundaries = property(_boundaries)
    grid_class.interval_size = property(_interval_size)
    grid_class.index_of_single = _index_of_single
    grid_class.grid_to_int_index = _grid_to_int_index
    grid_class.int_to_grid_index = _int_to_grid_index

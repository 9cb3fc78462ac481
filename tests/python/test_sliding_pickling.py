"""A pickled qdmeta.SlidingBoundariesArchive continues, in a new process too, to the bits the
original reaches: every later add's result, the boundaries through the remaps after it and the
elites (the batches and settings of pyribs_reference/sliding.json, pickled mid-way between two
remaps with a full buffer); a damaged pickle is refused."""
import multiprocessing
import pickle

import numpy as np
import pytest

import qdmeta
from test_sliding_boundaries_archive import REFERENCE

SPLIT = 3  # batches of 60 before the pickle


def continue_adds(data, batches):
    """Unpickles, adds `batches` and returns every result and boundary, then the elites."""
    archive = pickle.loads(data)
    results = []
    for batch in batches:
        info = archive.add(*(np.array(part) for part in batch))
        results.append(({k: v.tobytes() for k, v in info.items()}, [b.tobytes() for b in archive.boundaries]))
    return results, {k: v.tobytes() for k, v in archive.data().items()}


@pytest.mark.parametrize("run", REFERENCE["runs"], ids=lambda r: f"dims={r['settings']['dims']}")
def test_a_pickled_archive_continues_to_the_same_bits_in_a_new_process(run):
    archive = qdmeta.SlidingBoundariesArchive(solution_dim=2, **run["settings"])
    for batch in run["batches"][:SPLIT]:
        archive.add(*(np.array(part) for part in batch))
    data = pickle.dumps(archive)
    twin = pickle.loads(data)
    assert len(twin) == len(archive) and all(np.array_equal(a, b) for a, b in zip(twin.boundaries, archive.boundaries))
    rest = run["batches"][SPLIT:]
    mine = continue_adds(pickle.dumps(archive), rest)
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        there = pool.apply(continue_adds, (data, rest))
    assert mine == there
    # The continuation remapped: the boundaries moved after the pickle.
    assert mine[0][-1][1] != [b.tobytes() for b in twin.boundaries]


def test_a_damaged_pickle_is_refused():
    run = REFERENCE["runs"][1]
    archive = qdmeta.SlidingBoundariesArchive(solution_dim=2, **run["settings"])
    archive.add(*(np.array(part) for part in run["batches"][0]))
    fmt, params, state, checksum = archive.__getstate__()
    damaged = bytearray(state)
    damaged[len(damaged) // 2] ^= 1
    fresh = qdmeta.SlidingBoundariesArchive.__new__(qdmeta.SlidingBoundariesArchive)
    with pytest.raises(qdmeta.InputError, match="unpickling a qdmeta.SlidingBoundariesArchive"):
        fresh.__setstate__((fmt, params, bytes(damaged), checksum))

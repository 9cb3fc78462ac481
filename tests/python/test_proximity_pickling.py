"""A pickled qdmeta.ProximityArchive continues, in a new process too, to the bits the original
reaches: every later add's result, the decayed threshold and the elites (the batches and
settings of pyribs_reference/proximity.json); a damaged pickle is refused."""
import multiprocessing
import pickle

import numpy as np
import pytest

import qdmeta
from test_proximity_archive import BATCHES, REFERENCE

SPLIT = 4  # adds before the pickle


def continue_adds(data):
    """Unpickles, adds the batches after SPLIT and returns every result, threshold and the elites."""
    archive = pickle.loads(data)
    results = []
    for solution, objective, measures in BATCHES[SPLIT:]:
        info = archive.add(solution, objective, measures)
        results.append(({k: v.tolist() for k, v in info.items()}, archive.novelty_threshold))
    return results, {k: v.tobytes() for k, v in archive.data().items()}


@pytest.mark.parametrize("settings", [r["settings"] for r in REFERENCE["runs"]], ids=str)
def test_a_pickled_archive_continues_to_the_same_bits_in_a_new_process(settings):
    archive = qdmeta.ProximityArchive(solution_dim=3, measure_dim=2, **settings)
    for solution, objective, measures in BATCHES[:SPLIT]:
        archive.add(solution, objective, measures)
    data = pickle.dumps(archive)
    twin = pickle.loads(data)
    assert (twin.novelty_threshold, twin.k_neighbors, twin.local_competition, len(twin)) == (
        archive.novelty_threshold, archive.k_neighbors, archive.local_competition, len(archive))
    mine = continue_adds(pickle.dumps(archive))
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        there = pool.apply(continue_adds, (data,))
    assert mine == there
    assert len(mine[1]["objective"]) > 8 * len(pickle.loads(data))  # float64: 8 bytes an elite; it added some


def test_a_damaged_pickle_is_refused():
    archive = qdmeta.ProximityArchive(solution_dim=3, measure_dim=2, k_neighbors=2, novelty_threshold=0.1)
    archive.add(*BATCHES[0])
    fmt, params, state, checksum = archive.__getstate__()
    damaged = bytearray(state)
    damaged[len(damaged) // 2] ^= 1
    fresh = qdmeta.ProximityArchive.__new__(qdmeta.ProximityArchive)
    with pytest.raises(qdmeta.InputError, match="unpickling a qdmeta.ProximityArchive"):
        fresh.__setstate__((fmt, params, bytes(damaged), checksum))

"""Pickling the emitter classes: a Scheduler pickled with its archives and emitters (after a tell
or with a batch pending) continues, in a new process too, to the bits the original reaches; a
damaged pickle is refused or loads as the original."""
import copy
import multiprocessing
import pickle

import numpy as np
import pytest

import qdmeta
from emitter_loop import DIM, grid, run, sphere_projection


def mixed_scheduler():
    archive, result = grid(0.02, 0.0), grid()
    emitters = [
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker="imp", selection_rule="mu",
                                        restart_rule=5, batch_size=8, seed=11),
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.3, ranker="2rd", batch_size=6, seed=12),
        qdmeta.GaussianEmitter(archive, sigma=0.4, x0=np.zeros(DIM), batch_size=5, seed=13),
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.4, es="sep_cma_es", restart_rule=4,
                                        batch_size=7, seed=14),
    ]
    return run(qdmeta.Scheduler(archive, emitters, result_archive=result), 17)


def fingerprint(scheduler, rounds):
    """What `rounds` more rounds reach: every elite of both archives, the thresholds, the next
    batch and the emitters' counters."""
    run(scheduler, rounds)
    arrays = [a.data()[k] for a in (scheduler.archive, scheduler.result_archive)
              for k in ("index", "objective", "measures", "solution")]
    counters = [(e.itrs, e.restarts) for e in scheduler.emitters if isinstance(e, qdmeta.EvolutionStrategyEmitter)]
    return arrays + [scheduler.thresholds, scheduler.ask()], counters


def continue_in_worker(data, rounds, pending):
    """The unpickled scheduler tells `pending` (the rows asked before pickling) first, if any."""
    scheduler = pickle.loads(data)
    if pending is not None:
        scheduler.tell(*sphere_projection(pending))
    return fingerprint(scheduler, rounds)


def assert_same(a, b):
    (arrays_a, counters_a), (arrays_b, counters_b) = a, b
    assert counters_a == counters_b
    assert len(arrays_a) == len(arrays_b)
    for x, y in zip(arrays_a, arrays_b):
        assert x.dtype == y.dtype and np.array_equal(x, y)


@pytest.mark.parametrize("pending", [False, True], ids=["after-tell", "batch-pending"])
def test_a_pickled_scheduler_continues_in_a_new_process_to_the_same_bits(pending):
    original = mixed_scheduler()
    x = original.ask() if pending else None
    data = pickle.dumps(original)
    if pending:  # every copy tells the pending batch first
        original.tell(*sphere_projection(x))
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        there = pool.apply(continue_in_worker, (data, 12, x))
    mine = fingerprint(original, 12)
    assert_same(mine, there)
    assert_same(mine, continue_in_worker(data, 12, x))
    assert mine[1][0][1] >= 5  # the every-5 emitter restarted across the pickle


def test_an_unpickled_scheduler_shares_one_archive_with_its_emitters():
    loaded = pickle.loads(pickle.dumps(mixed_scheduler()))
    assert all(e.archive is loaded.archive for e in loaded.emitters)
    assert loaded.result_archive is not loaded.archive
    assert (loaded.archive.learning_rate, loaded.archive.threshold_min) == (0.02, 0.0)
    twin = copy.deepcopy(mixed_scheduler())
    assert all(e.archive is twin.archive for e in twin.emitters)
    assert_same(fingerprint(twin, 3), fingerprint(mixed_scheduler(), 3))


def test_an_emitter_pickles_alone_with_its_archive():
    scheduler = mixed_scheduler()
    emitter = pickle.loads(pickle.dumps(scheduler.emitters[0]))
    assert emitter.itrs == scheduler.emitters[0].itrs and emitter.batch_size == 8
    assert len(emitter.archive) == len(scheduler.archive)
    alone, original = qdmeta.Scheduler(emitter.archive, [emitter]), qdmeta.Scheduler(scheduler.archive,
                                                                                     [scheduler.emitters[0]])
    assert np.array_equal(alone.ask(), original.ask())


def loaded_or_refused(data):
    try:
        loaded = pickle.loads(data)
    except Exception:  # noqa: BLE001 (every refusal is fine here; loading other data is not)
        return None
    return loaded if type(loaded) is qdmeta.Scheduler else None


def test_a_scheduler_pickle_with_a_bit_flipped_is_refused_or_the_same():
    data = pickle.dumps(mixed_scheduler())
    reference = fingerprint(pickle.loads(data), 2)
    same = 0
    for bit in range(5, 8 * len(data), 8 * len(data) // 160):
        flipped = bytearray(data)
        flipped[bit // 8] ^= 1 << (bit % 8)
        twin = loaded_or_refused(bytes(flipped))
        if twin is not None:
            assert_same(fingerprint(twin, 2), reference)
            same += 1
    assert same < 10  # a flip in pickle's own framing may leave the data as it was; no more


def test_a_scheduler_state_whose_bytes_changed_is_refused_by_its_checksum():
    state = mixed_scheduler().__getstate__()
    raw = bytearray(state[4])
    raw[len(raw) // 2] ^= 0x10
    fresh = qdmeta.Scheduler.__new__(qdmeta.Scheduler)
    with pytest.raises(qdmeta.InputError, match=r"^unpickling a qdmeta\.Scheduler: the state is damaged \(checksum"):
        fresh.__setstate__(state[:4] + (bytes(raw),) + state[5:])
    with pytest.raises(qdmeta.InputError, match=r"^unpickling a qdmeta\.Scheduler: the state is not one qdmeta made"):
        fresh.__setstate__((99,) + state[1:])
    emitter_state = mixed_scheduler().emitters[1].__getstate__()
    changed = (emitter_state[:3] + ((emitter_state[3][0], 0.6) + emitter_state[3][2:],) + emitter_state[4:])
    with pytest.raises(qdmeta.InputError, match=r"^unpickling a qdmeta emitter: the state is damaged"):
        qdmeta.EvolutionStrategyEmitter.__new__(qdmeta.EvolutionStrategyEmitter).__setstate__(changed)

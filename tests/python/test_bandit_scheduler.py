"""qdmeta.BanditScheduler with pyribs's names: num_active emitters of the pool asked at a time,
the choice UCB1's (tests/emitters/emitter_bandit_test.cpp replays pyribs's choices on the C++
side), the same seeds the same bits, pickled continuation and the arguments refused."""
import pickle

import numpy as np
import pytest

import qdmeta
from emitter_loop import DIM, grid, sphere_projection

BATCH = 6


def bandit(seed, num_active=2, reselect="terminated", pool=5):
    archive = grid(0.1, 0.0)
    emitters = [qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker="imp",
                                                restart_rule=3, batch_size=BATCH, seed=seed * 100 + i)
                for i in range(pool)]
    return qdmeta.BanditScheduler(archive, emitters, num_active=num_active, reselect=reselect)


def steps(scheduler, n, active_log=None):
    for _ in range(n):
        x = scheduler.ask()
        if active_log is not None:
            active_log.append(scheduler.active.copy())
        scheduler.tell(*sphere_projection(x))
    return scheduler


@pytest.mark.parametrize("reselect", ["terminated", "all"])
def test_asks_num_active_emitters_and_tells_only_them(reselect):
    log = []
    s = steps(bandit(1, reselect=reselect), 30, log)
    assert all(a.dtype == bool and a.sum() == 2 for a in log)
    times = np.sum(log, axis=0)
    assert np.all(times > 0)  # UCB1 tries every emitter
    assert [e.itrs for e in s.emitter_pool] == times.tolist()
    assert s.ask().shape == (2 * BATCH, DIM)


def test_the_first_ask_takes_the_pools_first_emitters():
    s = bandit(2, num_active=3)
    assert not s.active.any()
    s.ask()
    assert s.active.tolist() == [True, True, True, False, False]


def test_the_same_seeds_give_the_same_bits_and_a_pickled_one_continues_them():
    a, b = steps(bandit(3), 15), steps(bandit(3), 15)
    assert np.array_equal(a.thresholds, b.thresholds)
    twin = pickle.loads(pickle.dumps(a))
    for _ in range(15):
        x, y = a.ask(), twin.ask()
        assert np.array_equal(x, y) and np.array_equal(a.active, twin.active)
        a.tell(*sphere_projection(x))
        twin.tell(*sphere_projection(y))
    assert np.array_equal(a.thresholds, twin.thresholds)
    fresh = bandit(4)  # pickled before its first ask
    assert np.array_equal(pickle.loads(pickle.dumps(fresh)).ask(), fresh.ask())


def test_refuses_bad_arguments_naming_them():
    archive = grid()
    pool = [qdmeta.GaussianEmitter(archive, sigma=0.1, x0=np.zeros(DIM), seed=i) for i in range(2)]
    with pytest.raises(qdmeta.InputError, match=r"BanditParams.num_active = 3 is out of range: must be in \[1, 2\]"):
        qdmeta.BanditScheduler(archive, pool, num_active=3)
    with pytest.raises(qdmeta.InputError, match="reselect = 'some' is not 'terminated' or 'all'"):
        qdmeta.BanditScheduler(archive, pool, num_active=1, reselect="some")
    with pytest.raises(qdmeta.InputError, match=r"emitter_pool\[1\] is emitter_pool\[0\]: give each emitter once"):
        qdmeta.BanditScheduler(archive, [pool[0], pool[0]], num_active=1)
    s = qdmeta.BanditScheduler(archive, pool, num_active=1)
    s.ask()
    with pytest.raises(qdmeta.InputError, match=r"BanditScheduler.tell: objective\[0\] = nan is invalid"):
        s.tell(np.full(64, np.nan), np.zeros((64, 2)))

"""Scheduler(add_mode="batch"), pyribs's default: every told row is scored against the thresholds
before the batch, and each cell that k rows beat moves once, to (1 - alpha)^k t + (1 - (1 -
alpha)^k) mean(f) (CMA-MAE paper's appendix; the best f under threshold_min = -inf). Checked by
hand-worked batches, against that rule replayed here in numpy over a run's told rows, through
pickles, and, where pyribs (ribs) can be imported, against pyribs's GridArchive.add on the same
batches (skipped otherwise)."""
import pickle

import numpy as np
import pytest

import qdmeta
from emitter_loop import DIM, grid, sphere_projection


def scheduler(learning_rate, threshold_min, add_mode="batch", dims=(4, 1), seed=1, batch_size=6, **bandit):
    archive = qdmeta.GridArchive(solution_dim=DIM, dims=list(dims), ranges=[(0.0, 1.0)] * len(dims),
                                 learning_rate=learning_rate, threshold_min=threshold_min)
    emitters = [qdmeta.GaussianEmitter(archive, sigma=0.1, x0=np.zeros(DIM), batch_size=batch_size, seed=seed)]
    if bandit:
        return qdmeta.BanditScheduler(archive, emitters, add_mode=add_mode, **bandit)
    return qdmeta.Scheduler(archive, emitters, add_mode=add_mode)


def tell_cells(s, cells, objective, dims=4):
    """Tells the pending batch the given objectives, each row at the centre of the given cell."""
    s.ask()
    measures = np.stack([(np.asarray(cells) + 0.5) / dims, np.full(len(cells), 0.5)], axis=1)
    s.tell(np.asarray(objective, dtype=np.float32), measures.astype(np.float32))


def test_several_rows_into_one_cell_are_scored_before_the_batch_and_move_it_once():
    s = scheduler(0.5, 0.0)
    tell_cells(s, [1, 1, 2, 1, 0, 3], [4.0, 2.0, -1.0, 6.0, 1.0, 0.0])
    info = s.add_info
    assert info["status"].tolist() == [2, 2, 0, 2, 2, 0]  # new, new (one at a time: refused), -, new, new, tie
    assert info["value"].tolist() == [4.0, 2.0, -1.0, 6.0, 1.0, 0.0]
    # cell 1: k = 3, mean 4 -> 0.125 * 0 + 0.875 * 4; cell 0: 0.5 * 1; cells 2 and 3 unreached.
    assert s.thresholds.tolist() == [0.5, 3.5, 0.0, 0.0]
    tell_cells(s, [1, 1, 1, 1, 0, 0], [3.5, 5.5, 7.5, 1.0, 0.5, 0.75])
    assert s.add_info["status"].tolist() == [0, 1, 1, 0, 0, 1]
    assert s.add_info["value"].tolist() == [0.0, 2.0, 4.0, -2.5, 0.0, 0.25]
    assert s.thresholds.tolist() == [0.625, 5.75, 0.0, 0.0]  # 0.25 * 3.5 + 0.75 * 6.5; 0.5 * 0.5 + 0.5 * 0.75


def test_single_mode_offers_the_same_rows_one_at_a_time():
    s = scheduler(0.5, 0.0, add_mode="single")
    tell_cells(s, [1, 1, 2, 1, 0, 3], [4.0, 2.0, -1.0, 6.0, 1.0, 0.0])
    assert s.add_info["status"].tolist() == [2, 0, 0, 1, 2, 0]
    assert s.add_info["value"].tolist() == [4.0, 0.0, -1.0, 4.0, 1.0, 0.0]
    assert s.thresholds.tolist() == [0.5, 4.0, 0.0, 0.0]


def test_learning_rate_001_and_minus_infinity_by_hand():
    s = scheduler(0.01, 0.0)
    tell_cells(s, [0, 0, 3, 3, 3, 3], [1.0, 3.0, 2.0, 2.0, 2.0, 2.0])
    assert s.thresholds[0] == pytest.approx(2 * (1 - 0.99 ** 2), rel=1e-15)  # 0.0398
    assert s.thresholds[3] == pytest.approx(2 * (1 - 0.99 ** 4), rel=1e-15)  # ties: their mean is 2
    me = scheduler(None, -np.inf)
    tell_cells(me, [0, 0, 0, 2, 2, 2], [2.0, 5.0, 3.0, -4.0, -6.0, -5.0])
    assert me.add_info["status"].tolist() == [2] * 6
    assert me.add_info["value"].tolist() == [2.0, 5.0, 3.0, -4.0, -6.0, -5.0]  # new cells against 0
    assert me.thresholds[[0, 2]].tolist() == [5.0, -4.0]  # the best objective
    assert me.archive.data()["objective"].tolist() == [5.0, -4.0]


def replay_batch_rule(archive, log, alpha, threshold_min):
    """The batch rule replayed over each told batch with numpy, from the thresholds before it."""
    t = np.full(archive.cells, threshold_min)
    for objective, measures in log:
        cells = archive.index_of(measures)
        f = objective.astype(np.float64)
        took = f > t[cells]
        new = t.copy()
        for cell in np.unique(cells[took]):
            rows = f[took & (cells == cell)]
            keep = (1.0 - alpha) ** len(rows)
            new[cell] = keep * t[cell] + rows.mean() * (1.0 - keep)
        t = new
    return t


def test_a_run_follows_the_batch_rule_and_differs_from_the_single_mode():
    log = []
    archive = grid(0.05, 0.0, dims=(8, 8))
    s = qdmeta.Scheduler(archive, [qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker="imp",
                                                                   selection_rule="mu", restart_rule="basic",
                                                                   batch_size=12, seed=i) for i in range(3)],
                         add_mode="batch")
    for _ in range(30):
        objective, measures = sphere_projection(s.ask())
        s.tell(objective, measures)
        log.append((objective, measures))
    reference = replay_batch_rule(archive, log, 0.05, 0.0)
    np.testing.assert_allclose(s.thresholds, reference, rtol=1e-13, atol=1e-13)
    single = np.full(archive.cells, 0.0)
    for objective, measures in log:  # the same rows one at a time differ somewhere
        for cell, f in zip(archive.index_of(measures), objective.astype(np.float64)):
            if f > single[cell]:
                single[cell] = 0.95 * single[cell] + 0.05 * f
    assert np.max(np.abs(single - reference)) > 1e-3


@pytest.mark.parametrize("bandit", [{}, {"num_active": 1}])
def test_a_pickled_batch_scheduler_continues_to_the_same_bits(bandit):
    def run(s, n):
        for _ in range(n):
            objective, measures = sphere_projection(s.ask())
            s.tell(objective, (measures / 51.2 + 0.5).clip(0, 1))
        return s
    a = run(scheduler(0.1, 0.0, dims=(6, 6), **bandit), 5)
    b = pickle.loads(pickle.dumps(a))
    run(a, 5)
    run(b, 5)
    assert np.array_equal(a.thresholds, b.thresholds)
    assert np.array_equal(a.add_info["value"], b.add_info["value"])
    single = run(scheduler(0.1, 0.0, add_mode="single", dims=(6, 6), **bandit), 10)
    assert not np.array_equal(a.thresholds, single.thresholds)


def pyribs_batches(seed, batches, rows, dims):
    """Random batches at cell centres (so both libraries bin them alike), many rows per cell."""
    rng = np.random.default_rng(seed)
    for _ in range(batches):
        cells = rng.integers(0, dims, size=(rows, 2))
        measures = ((cells + 0.5) / dims).astype(np.float32)
        objective = rng.normal(0.5, 1.0, size=rows).astype(np.float32)
        yield objective, measures


@pytest.mark.parametrize("learning_rate,threshold_min", [(0.01, 0.0), (0.5, -0.5), (1.0, 0.0), (None, -np.inf)])
def test_statuses_values_and_thresholds_are_pyribs_batch_adds(learning_rate, threshold_min):
    ribs = pytest.importorskip("ribs.archives")
    dims, rows = 5, 40
    ours = scheduler(learning_rate, threshold_min, dims=(dims, dims), batch_size=rows)
    theirs = ribs.GridArchive(solution_dim=DIM, dims=[dims, dims], ranges=[(0.0, 1.0)] * 2,
                              learning_rate=learning_rate, threshold_min=threshold_min)
    floor = theirs.threshold_min
    for objective, measures in pyribs_batches(7, 30, rows, dims):
        solutions = ours.ask()
        ours.tell(objective, measures)
        info = theirs.add(solutions.astype(np.float64), objective.astype(np.float64), measures.astype(np.float64))
        assert np.array_equal(ours.add_info["status"], info["status"])
        np.testing.assert_allclose(ours.add_info["value"], info["value"], rtol=1e-14, atol=1e-14)
        expected = np.full(dims * dims, floor, dtype=np.float64)
        data = theirs.data(["index", "threshold"])
        expected[data["index"]] = data["threshold"]
        # numpy's power and the C library's may differ in the last bit of (1 - alpha)^k.
        np.testing.assert_allclose(ours.thresholds, expected, rtol=1e-14, atol=1e-14)

"""archive.clear() resets the CMA-MAE thresholds a Scheduler holds for that archive, as pyribs's
clear() does (its emptied cells score against threshold_min again). The expected values are
pyribs 0.12's for the same adds: learning_rate 0.5, threshold_min 0, objective 4 then clear()
then objective 1 in the same cell gives status new, value 1 and threshold 0.5; learning_rate 1
gives status new, value 1 and threshold 1."""
import pickle

import numpy as np

import qdmeta

DIM = 2


def one_row_scheduler(learning_rate, threshold_min):
    archive = qdmeta.GridArchive(solution_dim=DIM, dims=[4], ranges=[(0.0, 4.0)], learning_rate=learning_rate,
                                 threshold_min=threshold_min)
    emitter = qdmeta.GaussianEmitter(archive, sigma=0.1, x0=np.zeros(DIM), batch_size=1, seed=1)
    return qdmeta.Scheduler(archive, [emitter])


def tell(scheduler, objective, measure=1.5):
    scheduler.ask()
    scheduler.tell([objective], [[measure]])


def test_clear_resets_cma_mae_thresholds_to_threshold_min():
    s = one_row_scheduler(0.5, 0.0)
    tell(s, 4.0)
    assert s.thresholds[1] == 2.0
    s.archive.clear()
    assert np.array_equal(s.thresholds, np.zeros(4))
    tell(s, 1.0)  # below the 2 the cell had before the clear
    assert s.thresholds[1] == 0.5
    assert len(s.archive) == 1


def test_clear_resets_cma_me_thresholds_to_minus_infinity():
    s = one_row_scheduler(None, -np.inf)
    tell(s, 4.0)
    s.archive.clear()
    assert np.all(s.thresholds == -np.inf)
    tell(s, 1.0)
    assert s.thresholds[1] == 1.0


def test_a_scheduler_pickled_after_a_clear_keeps_the_reset_thresholds():
    s = one_row_scheduler(0.5, 0.0)
    tell(s, 4.0)
    s.archive.clear()
    t = pickle.loads(pickle.dumps(s))
    assert np.array_equal(t.thresholds, np.zeros(4))
    tell(s, 1.0)
    tell(t, 1.0)
    assert np.array_equal(t.thresholds, s.thresholds) and t.thresholds[1] == 0.5

"""CMA-ME and CMA-MAE from Python with pyribs's names: the archive's learning_rate and
threshold_min, EvolutionStrategyEmitter, GaussianEmitter and Scheduler. Checked: the ask/tell
shapes, determinism per seed, the thresholds against a reference computed here from the told
rows, alpha = 1 as CMA-ME, and CMA-MAE's QD score above Gaussian MAP-Elites at equal evaluations."""
from fractions import Fraction

import numpy as np
import pytest

import qdmeta
from emitter_loop import DIM, cma_mae, cma_me, gaussian_map_elites, grid, run, sphere_projection


def test_ask_stacks_every_emitters_batch_as_float32_rows():
    archive = grid(0.1, 0.0)
    emitters = [qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.3, batch_size=5, seed=1),
                qdmeta.GaussianEmitter(archive, sigma=0.2, x0=np.ones(DIM), batch_size=7, seed=2)]
    scheduler = qdmeta.Scheduler(archive, emitters)
    x = scheduler.ask()
    assert x.shape == (12, DIM) and x.dtype == np.float32
    # The Gaussian emitter's rows are x0 + noise while the archive is empty: around 1, not 0.
    assert abs(x[5:].mean() - 1.0) < 0.3 and abs(x[:5].mean()) < 0.3
    assert [e.batch_size for e in scheduler.emitters] == [5, 7] and scheduler.archive is archive
    assert (archive.learning_rate, archive.threshold_min) == (0.1, 0.0)


def test_the_default_batch_size_is_cma_es_lambda():
    archive = grid()
    assert qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=1.0).batch_size == 4 + int(3 * np.log(DIM))


def test_the_same_seeds_give_the_same_bits_and_other_seeds_differ():
    a, b, c = run(cma_mae(1), 40), run(cma_mae(1), 40), run(cma_mae(2), 40)
    assert np.array_equal(a.ask(), b.ask())
    assert np.array_equal(a.thresholds, b.thresholds)
    assert not np.array_equal(a.thresholds, c.thresholds)


def reference_thresholds(archive, log, alpha, threshold_min):
    """Algorithm 1's update, t <- (1 - alpha) t + alpha f on f > t, replayed row by row in exact
    arithmetic and rounded once (a fused multiply-add) and in plain double arithmetic (no fma)."""
    fused = np.full(archive.cells, threshold_min)
    plain = fused.copy()
    for objective, measures in log:
        for cell, f in zip(archive.index_of(measures), objective.astype(np.float64)):
            if f > fused[cell]:
                fused[cell] = float(Fraction(alpha) * Fraction(f) + Fraction((1.0 - alpha) * fused[cell]))
            if f > plain[cell]:
                plain[cell] = alpha * f + (1.0 - alpha) * plain[cell]
    return fused, plain


def test_the_thresholds_follow_cma_mae_row_by_row():
    log = []
    scheduler = run(cma_mae(3, learning_rate=0.05), 30, log)
    fused, plain = reference_thresholds(scheduler.archive, log, 0.05, 0.0)
    assert not np.array_equal(fused, plain)  # the replay tells the two roundings apart
    assert np.array_equal(scheduler.thresholds, fused) or np.array_equal(scheduler.thresholds, plain)
    # The archive keeps each cell's best elite: never below that cell's threshold.
    data = scheduler.archive.data()
    assert np.all(data["objective"] >= scheduler.thresholds[data["index"]])


def test_learning_rate_one_is_cma_me_whose_thresholds_are_the_elites():
    scheduler = run(cma_mae(4, learning_rate=1.0), 30)
    archive = scheduler.archive
    data = archive.data()
    expected = np.full(archive.cells, -np.inf)
    expected[data["index"]] = data["objective"]
    # threshold_min = 0 here: a cell never reached keeps 0, a reached one its best objective.
    expected[np.isinf(expected)] = 0.0
    assert np.array_equal(scheduler.thresholds, expected)
    me = grid()  # learning_rate None, threshold_min -inf: pyribs's CMA-ME archive
    assert (me.learning_rate, me.threshold_min) == (1.0, -np.inf)


def test_cma_mae_beats_cma_me_beats_gaussian_map_elites_at_equal_evaluations_on_every_seed():
    # The ordering of Fontaine & Nikolaidis (2023) on this task. Equal evaluations: every
    # scheduler asks 3 x 12 rows per round, for 500 rounds (18,000 evaluations), on seeds 1-5.
    for seed in range(1, 6):
        mae, me, gaussian = (run(make(seed), 500).archive.stats.qd_score
                             for make in (cma_mae, cma_me, gaussian_map_elites))
        assert mae > me > gaussian, f"seed {seed}: CMA-MAE {mae}, CMA-ME {me}, Gaussian MAP-Elites {gaussian}"


def test_a_result_archive_gets_every_told_row():
    archive, result = grid(0.01, 0.0), grid()
    scheduler = qdmeta.Scheduler(archive, [qdmeta.GaussianEmitter(archive, sigma=0.5, x0=np.zeros(DIM), seed=1)],
                                 result_archive=result)
    x = scheduler.ask()
    objective, measures = sphere_projection(x)
    scheduler.tell(objective, measures)
    twin = grid()
    twin.add(x, objective, measures)
    assert scheduler.result_archive is result
    assert np.array_equal(result.data()["objective"], twin.data()["objective"])
    assert np.array_equal(result.data()["solution"], twin.data()["solution"])


@pytest.mark.parametrize("ranker", ["imp", "2imp", "obj", "2obj", "rd", "2rd", "two-stage-improvement"])
@pytest.mark.parametrize("restart_rule", ["no_improvement", "basic", 5])
def test_every_ranker_and_restart_rule_runs_and_fills_the_archive(ranker, restart_rule):
    archive = grid(0.01, 0.0)
    emitter = qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker=ranker,
                                              restart_rule=restart_rule, batch_size=10, seed=1)
    run(qdmeta.Scheduler(archive, [emitter]), 30)
    assert len(archive) > 10 and emitter.itrs == 30
    if restart_rule == 5:
        assert emitter.restarts >= 30 // 5 - 1  # the restart fires at the ask after every 5th tell


def separable_cma_mae(seed, es="sep_cma_es"):
    archive = grid(0.01, 0.0)
    return qdmeta.Scheduler(archive, [
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker="imp", es=es,
                                        selection_rule="mu", restart_rule="basic", batch_size=12, seed=seed * 100 + i)
        for i in range(3)])


def test_es_sep_cma_es_runs_the_separable_cma_es_under_each_of_its_names():
    """pyribs's es="sep_cma_es", its class name and qdmeta's name are one emitter (same bits); it
    fills the archive as the full CMA-ES does, along another path."""
    runs = [run(separable_cma_mae(4, es), 60) for es in ("sep_cma_es", "SeparableCMAEvolutionStrategy", "sep-cma-es")]
    batches = [r.ask() for r in runs]
    for other, batch in zip(runs[1:], batches[1:]):
        assert np.array_equal(runs[0].thresholds, other.thresholds)
        assert np.array_equal(batches[0], batch)
    full = run(separable_cma_mae(4, "cma_es"), 60)
    assert not np.array_equal(full.thresholds, runs[0].thresholds)
    assert np.array_equal(full.thresholds, run(cma_mae(4), 60).thresholds)  # es="cma_es" is the default
    sep_cells = len(runs[0].archive.data()["index"])
    assert sep_cells > 0.5 * len(full.archive.data()["index"]) and sep_cells > 60

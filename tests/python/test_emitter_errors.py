"""Errors of the emitter classes: one line naming the argument, and nothing changed by a refused
call (a scheduler goes on after a refused tell)."""
import numpy as np
import pytest

import qdmeta
from emitter_loop import DIM, grid, run


def es(archive, **named):
    return qdmeta.EvolutionStrategyEmitter(archive, **{"x0": np.zeros(DIM), "sigma0": 0.5, **named})


ARCHIVE_ERRORS = [
    (dict(learning_rate=1.5, threshold_min=0.0), r"^learning_rate = 1\.5 is outside \[0, 1\] \(CMA-MAE's alpha\)$"),
    (dict(learning_rate=-0.1, threshold_min=0.0), r"^learning_rate = -0\.1 is outside \[0, 1\]"),
    (dict(learning_rate=float("nan"), threshold_min=0.0), r"^learning_rate = nan is outside \[0, 1\]"),
    (dict(learning_rate=0.5), r"^threshold_min = -inf needs learning_rate = 1 \(got 0\.5\)"),
    (dict(learning_rate=0.5, threshold_min=float("nan")), r"^threshold_min = nan is invalid"),
]


@pytest.mark.parametrize("named,message", ARCHIVE_ERRORS)
def test_the_archives_threshold_arguments_are_checked(named, message):
    with pytest.raises(qdmeta.InputError, match=message):
        grid(**named)
    with pytest.raises(qdmeta.InputError, match=message):
        qdmeta.CvtArchive(DIM, np.random.default_rng(1).random((5, 2)), **named)


EMITTER_ERRORS = [
    (dict(batch_size=0), r"^batch_size = 0 is invalid: must be an integer in \[1, 1000000\]$"),
    (dict(batch_size=10**6 + 1), r"^batch_size = 1000001 is invalid: must be an integer in \[1, 1000000\]$"),
    (dict(sigma0=0.0), r"^emitters\.sigma0 = 0 is out of range: must be a positive number$"),
    (dict(sigma0=-1.0), r"^emitters\.sigma0 = -1 is out of range"),
    (dict(x0=np.zeros(3)), r"^x0 has 3 values; the archive's solution_dim is 10$"),
    (dict(ranker="nov"), r"^ranker = 'nov' is not one of imp, 2imp, obj, 2obj, rd, 2rd$"),
    (dict(restart_rule="never"), r"^restart_rule = 'never' is not 'no_improvement', 'basic' or an integer >= 1$"),
    (dict(restart_rule=0), r"^restart_rule = 0 is invalid: must be an integer in \[1, 1000000000\]$"),
    (dict(restart_rule=True), r"^restart_rule = True is not 'no_improvement', 'basic' or an integer >= 1$"),
    (dict(selection_rule="best"), r"^selection_rule = 'best' is not 'filter' or 'mu'$"),
    (dict(es="lm_ma_es"), r"^es = 'lm_ma_es' is not 'cma_es' or 'sep_cma_es' \(qdmeta has no other evolution strategy\)$"),
    (dict(es_kwargs={"lr": 1}), r"^es_kwargs must be None: qdmeta's evolution strategies take no options$"),
    (dict(bounds=[(0, 1)] * DIM), r"^bounds must be None"),
    (dict(seed=-1), r"^seed = -1 is out of range"),
    (dict(seed=2**70), r"^seed = 1180591620717411303424 is out of range: must be in \[0, 9223372036854775807\]$"),
]


@pytest.mark.parametrize("named,message", EMITTER_ERRORS)
def test_the_evolution_strategy_emitters_arguments_are_checked(named, message):
    with pytest.raises(qdmeta.InputError, match=message):
        es(grid(), **named)


def test_integer_arguments_of_another_type_are_one_line_type_errors():
    with pytest.raises(TypeError, match=r"^batch_size must be an integer, got <class 'float'>$"):
        es(grid(), batch_size=1.5)
    with pytest.raises(TypeError, match=r"^seed must be an integer, got <class 'str'>$"):
        es(grid(), seed="x")
    assert es(grid(), batch_size=np.int64(6), restart_rule=np.int32(3), seed=np.uint8(2)).batch_size == 6


def test_the_gaussian_emitters_arguments_are_checked():
    archive = grid()
    with pytest.raises(qdmeta.InputError, match=r"^emitters\.sigma = 0 is out of range: must be a positive number$"):
        qdmeta.GaussianEmitter(archive, sigma=0.0, x0=np.zeros(DIM))
    with pytest.raises(qdmeta.InputError, match=r"^batch_size = 0 is invalid: must be an integer in \[1, "):
        qdmeta.GaussianEmitter(archive, sigma=1.0, x0=np.zeros(DIM), batch_size=0)
    with pytest.raises(qdmeta.InputError, match=r"^x0 is None"):
        qdmeta.GaussianEmitter(archive, sigma=1.0)
    with pytest.raises(qdmeta.InputError, match=r"^bounds differ between genes"):
        qdmeta.GaussianEmitter(archive, sigma=1.0, x0=np.zeros(DIM), bounds=[(0, 1)] * (DIM - 1) + [(0, 2)])
    with pytest.raises(TypeError, match=r"^archive must be a qdmeta\.GridArchive or qdmeta\.CvtArchive"):
        qdmeta.GaussianEmitter(qdmeta.UnstructuredArchive(DIM, 2), sigma=1.0, x0=np.zeros(DIM))


def test_the_schedulers_emitters_are_checked():
    archive = grid()
    emitter = es(archive, batch_size=4, seed=1)
    with pytest.raises(qdmeta.InputError, match=r"^emitters is empty: give the Scheduler at least one emitter$"):
        qdmeta.Scheduler(archive, [])
    with pytest.raises(qdmeta.InputError, match=r"^emitters\[0\] was made over another archive"):
        qdmeta.Scheduler(grid(), [emitter])
    with pytest.raises(qdmeta.InputError, match=r"^emitters\[1\] is emitters\[0\]: give each emitter once$"):
        qdmeta.Scheduler(archive, [emitter, emitter])
    with pytest.raises(TypeError, match=r"^emitters\[0\] is not a qdmeta emitter$"):
        qdmeta.Scheduler(archive, [1])
    with pytest.raises(qdmeta.InputError, match=r"^result_archive is the archive"):
        qdmeta.Scheduler(archive, [emitter], result_archive=archive)
    with pytest.raises(qdmeta.InputError, match=r"^result_archive has another solution_dim or measure_dim"):
        qdmeta.Scheduler(archive, [emitter], result_archive=qdmeta.GridArchive(3, [2, 2]))


def test_add_mode_defaults_to_single_and_takes_batch_and_nothing_else():
    """qdmeta's default is pyribs's "single" (rows offered one at a time): add_mode="single" is the
    same scheduler as no add_mode; "batch" (tests/python/test_batch_add_mode.py) is taken by both
    schedulers; any other name is refused in one line."""
    runs = []
    for named in ({}, {"add_mode": "single"}):
        archive = grid(0.1, 0.0)
        scheduler = qdmeta.Scheduler(archive, [es(archive, batch_size=6, seed=3)], **named)
        runs.append(run(scheduler, 10).thresholds)
    assert np.array_equal(runs[0], runs[1])
    archive = grid()
    emitter = es(archive, batch_size=4, seed=1)
    with pytest.raises(qdmeta.InputError, match=r"^add_mode = 'many' is not 'single' or 'batch'$"):
        qdmeta.Scheduler(archive, [emitter], add_mode="many")
    with pytest.raises(qdmeta.InputError, match=r"^add_mode = 'Batch' is not 'single' or 'batch'$"):
        qdmeta.BanditScheduler(archive, [emitter], num_active=1, add_mode="Batch")
    for add_mode in ("single", "batch"):  # each over a fresh emitter (an asked one awaits its tell)
        assert qdmeta.BanditScheduler(archive, [es(archive, batch_size=4, seed=1)], num_active=1,
                                      add_mode=add_mode).ask().shape == (4, DIM)
    assert qdmeta.Scheduler(archive, [es(archive, batch_size=4, seed=1)], add_mode="batch").ask().shape == (4, DIM)


def test_a_refused_tell_names_the_argument_and_changes_nothing():
    archive = grid(0.1, 0.0)
    scheduler = qdmeta.Scheduler(archive, [es(archive, batch_size=4, seed=1)])
    with pytest.raises(qdmeta.InputError, match=r"^Scheduler::tell: called without a pending ask"):
        scheduler.tell(np.zeros(4), np.zeros((4, 2)))
    scheduler.ask()
    with pytest.raises(qdmeta.InputError, match=r"^Scheduler::ask: called twice without tell"):
        scheduler.ask()
    refused = [
        ((np.zeros(3), np.zeros((4, 2))), ValueError, r"^objective must have shape \(4,\), got \(3,\)$"),
        ((np.zeros((4, 1)), np.zeros((4, 2))), ValueError, r"^objective must have shape \(4,\), got \(4, 1\)$"),
        ((np.zeros(4), np.zeros((4, 3))), ValueError, r"^measures must have shape \(4, 2\), got \(4, 3\)$"),
        ((np.array([0, np.nan, 0, 0]), np.zeros((4, 2))), qdmeta.InputError,
         r"^Scheduler\.tell: objective\[1\] = nan is invalid: must be finite$"),
        ((np.zeros(4), np.array([[0, 0], [0, np.inf], [0, 0], [0, 0]])), qdmeta.InputError,
         r"^Scheduler\.tell: measures\[1, 1\] = inf is invalid: must be finite$"),
    ]
    for arguments, error, message in refused:
        with pytest.raises(error, match=message):
            scheduler.tell(*arguments)
    assert len(archive) == 0 and np.all(scheduler.thresholds == 0.0)
    with pytest.raises(TypeError, match=r"^Scheduler\.tell\(\) takes \(objective, measures\); it was given "
                                        r"objective=, measure=$"):
        scheduler.tell(objective=np.zeros(4), measure=np.zeros((4, 2)))
    scheduler.tell(np.ones(4), np.zeros((4, 2)))  # the pending batch is still the one to tell
    # Four rows of objective 1 in one cell, annealed in turn from 0: 1 - 0.9^4.
    assert len(archive) == 1 and scheduler.thresholds.max() == pytest.approx(1 - 0.9**4, rel=1e-12)

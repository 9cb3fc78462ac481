"""Algorithms from Python: ask/tell gives the bits of step(), a numpy task matches the built-in
one, protocol errors say what was expected, a task's exception reaches the caller with its
traceback, and a Python meta-objective drives QD-Meta."""
import traceback

import numpy as np
import pytest

import qdmeta

ME = {"algorithm": "map-elites", "seed": 5, "archive": {"bins": [20, 20]},
      "map_elites": {"batch_size": 50, "initial_population": 200}}


def rastrigin(x):
    """The paper's Rastrigin in numpy: genes in [0, 1] mapped to [-5.12, 5.12]; the base
    features are the genes themselves."""
    z = -5.12 + 10.24 * x.astype(np.float64)
    f = -(10.0 * x.shape[1] + np.sum(z * z - 10.0 * np.cos(2 * np.pi * z), axis=1))
    return f.astype(np.float32), x, np.ones(len(x), dtype=bool)


def numpy_rastrigin(n=20):
    return qdmeta.Task(rastrigin, genotype_size=n, base_feature_size=n, name="numpy-rastrigin")


def test_ask_tell_by_hand_gives_the_bits_of_step():
    task = numpy_rastrigin()
    stepped = qdmeta.Algorithm(ME, task=task)
    by_hand = qdmeta.Algorithm(ME, task=task)
    for _ in range(15):
        stepped.step(threads=2)
        x = by_hand.ask()
        assert x.shape == ((200 if by_hand.generation == 0 else 50), 20) and x.dtype == np.float32
        by_hand.tell(*rastrigin(x))
    a, b = stepped.data(), by_hand.data()
    assert np.array_equal(a["index"], b["index"])
    assert np.array_equal(a["objective"], b["objective"])
    assert np.array_equal(a["solution"], b["solution"])
    assert stepped.evaluations == by_hand.evaluations == {"bottom": 200 + 14 * 50, "meta": 0, "total": 900}
    assert stepped.stats.num_elites == len(a["index"]) > 100


def test_a_numpy_task_matches_the_builtin_one():
    builtin = qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 20})
    x = np.random.default_rng(0).random((64, 20), dtype=np.float32)
    f_c, b_c, v_c = builtin.evaluate(x)
    f_py, b_py, v_py = numpy_rastrigin().evaluate(x)
    np.testing.assert_allclose(f_py, f_c, rtol=2e-5)
    assert np.array_equal(b_py, b_c) and v_c.all() and v_py.all()
    # The same run through both tasks: the same cells and genotypes (the fitness differs in the
    # last float bits: the built-in task sums in float with its own cosine).
    cfg = dict(ME)
    ours = qdmeta.Algorithm(cfg, task=numpy_rastrigin())
    theirs = qdmeta.Algorithm(dict(cfg, task={"name": "rastrigin", "dimensions": 20}))
    for _ in range(10):
        ours.step(threads=1)
        theirs.step(threads=1)
    a, b = ours.data(), theirs.data()
    assert np.array_equal(a["index"], b["index"])
    assert np.array_equal(a["solution"], b["solution"])
    np.testing.assert_allclose(a["objective"], b["objective"], rtol=2e-5)


def test_protocol_errors_say_what_was_expected():
    algo = qdmeta.Algorithm(ME, task=numpy_rastrigin())
    with pytest.raises(qdmeta.Error, match="no pending ask"):
        algo.tell(np.zeros(200), np.zeros((200, 20)))
    x = algo.ask()
    with pytest.raises(qdmeta.Error, match=r"ask\(\) called again before tell\(\)"):
        algo.ask()
    with pytest.raises(ValueError, match=r"fitness must have shape \(200,\), got \(199,\)"):
        algo.tell(np.zeros(199), np.zeros((200, 20)))
    f, b, v = rastrigin(x)
    b = b.copy()
    b[3, 7] = 1.5
    with pytest.raises(ValueError, match=r"row 3: base feature 7 is 1.5, outside \[0, 1\]"):
        algo.tell(f, b, v)
    f[2] = np.nan
    with pytest.raises(ValueError, match=r"row 2: fitness nan is not finite"):
        algo.tell(f, x, v)
    assert algo.step_in_progress, "a refused tell() leaves the request pending"
    algo.tell(*rastrigin(x))
    assert not algo.step_in_progress and algo.generation == 1


def test_config_errors_name_the_key():
    with pytest.raises(qdmeta.InputError, match="archive.bins"):
        qdmeta.Algorithm(dict(ME, archive={"bins": [0, 3]}), task=numpy_rastrigin())
    with pytest.raises(qdmeta.InputError, match="map_elites.batch_sise"):
        qdmeta.Algorithm(dict(ME, map_elites={"batch_sise": 3}), task=numpy_rastrigin())
    with pytest.raises(TypeError, match="'seed' is None"):
        qdmeta.Algorithm(dict(ME, seed=None), task=numpy_rastrigin())
    with pytest.raises(ValueError, match='task.name is "rastrigin", but the task given is "numpy-rastrigin"'):
        qdmeta.Algorithm(dict(ME, task={"name": "rastrigin"}), task=numpy_rastrigin())


class TaskFailure(Exception):
    pass


def failing(x):
    raise TaskFailure(f"no simulator for {len(x)} genotypes")


def test_a_task_exception_reaches_the_caller_with_its_traceback():
    algo = qdmeta.Algorithm(ME, task=qdmeta.Task(failing, 20, 2, name="failing"))
    with pytest.raises(TaskFailure, match="no simulator for 200 genotypes") as info:
        algo.step(threads=2)
    frames = [f.name for f in traceback.extract_tb(info.value.__traceback__)]
    assert "failing" in frames


def test_a_task_returning_the_wrong_shapes_is_named():
    bad = qdmeta.Task(lambda x: (np.zeros(len(x)), np.zeros((len(x), 3))), 20, 2, name="bad")
    with pytest.raises(ValueError, match=r"task 'bad': base_features must have shape \(200, 2\), got \(200, 3\)"):
        qdmeta.Algorithm(ME, task=bad).step()
    nan = qdmeta.Task(lambda x: (np.full(len(x), np.nan), x[:, :2]), 20, 2, name="nan")
    with pytest.raises(qdmeta.InputError, match="task 'nan' row 0: fitness nan is not finite"):
        qdmeta.Algorithm(ME, task=nan).step()


QD = {"algorithm": "qd-meta", "seed": 2, "archive": {"bins": [10, 10]},
      "qd_meta": {"meta_population": 3, "batch_size": 40, "initial_population": 200, "database_capacity": 5000,
                  "hidden": 4},
      "control": {"kind": "static", "generations": 2}}


def test_a_python_meta_objective_drives_qd_meta():
    calls = []

    def mean_of_first_gene(elites, seed):
        assert elites.ndim == 2 and elites.shape[1] == 20 and elites.dtype == np.float32
        calls.append((len(elites), seed))
        return float(np.mean(elites[:, 0]))

    objective = qdmeta.MetaObjective(mean_of_first_gene, name="first-gene")
    algo = qdmeta.Algorithm(QD, task=numpy_rastrigin(), meta_objective=objective)
    assert algo.config["meta_fitness"]["kind"] == "first-gene"
    for _ in range(3):
        algo.step(threads=2)
    assert len(calls) == 3 * 3, "each map of each meta-generation scored once"
    assert len({s for _, s in calls}) == len(calls), "each evaluation has its own seed"
    again = qdmeta.Algorithm(QD, task=numpy_rastrigin(), meta_objective=qdmeta.MetaObjective(
        lambda e, s: calls.append((len(e), s)) or float(np.mean(e[:, 0])), name="first-gene"))
    first = list(calls)
    for _ in range(3):
        again.step(threads=1)
    # Maps are scored in parallel (in any order) when the task is shareable.
    assert sorted(calls[len(first):]) == sorted(first), "the same run gives the function the same elites and seeds"


def test_a_meta_objective_with_archive_true_reads_what_the_archive_stored():
    archives = []

    def record(archive, seed):
        archives.append(archive)
        return float(np.mean(archive["objective"]))

    objective = qdmeta.MetaObjective(record, name="stored-mean", archive=True)
    assert objective.archive
    algo = qdmeta.Algorithm(QD, task=numpy_rastrigin(), meta_objective=objective)
    for _ in range(2):
        algo.step(threads=2)
    assert len(archives) == 2 * 3
    for archive in archives:
        assert sorted(archive) == ["base_features", "measures", "objective", "solution"]
        solution = archive["solution"]
        k = len(solution)
        assert k > 0 and solution.shape == (k, 20) and solution.dtype == np.float32
        assert archive["objective"].shape == (k,) and archive["measures"].shape == (k, 2)
        # The stored values are the task's for those very genotypes (base features = genes here),
        # and the measures are a grid's: in [0, 1], one elite per cell of the 10 x 10 bins.
        fitness, base, _ = rastrigin(solution)
        np.testing.assert_array_equal(archive["objective"], fitness)
        np.testing.assert_array_equal(archive["base_features"], base)
        measures = archive["measures"]
        assert np.all((measures >= 0) & (measures <= 1))
        grid = qdmeta.GridArchive(solution_dim=20, dims=[10, 10])
        assert len(set(grid.index_of(measures).tolist())) == k


def test_qd_meta_requests_can_be_served_job_by_job():
    algo = qdmeta.Algorithm(dict(QD, task={"name": "rastrigin", "dimensions": 20},
                                 meta_fitness={"kind": "translation"}))
    reference = qdmeta.Algorithm(dict(QD, task={"name": "rastrigin", "dimensions": 20},
                                      meta_fitness={"kind": "translation"}))
    reference.step(threads=1)
    while True:
        jobs = algo.ask_jobs()
        assert all(isinstance(t, qdmeta.Task) for t, _ in jobs)
        algo.tell_jobs([t.evaluate(x) for t, x in jobs])
        if not algo.step_in_progress:
            break
    assert np.array_equal(algo.data()["solution"], reference.data()["solution"])


def test_the_gil_is_released_while_qdmeta_works():
    import threading
    algo = qdmeta.Algorithm(dict(QD, task={"name": "rastrigin", "dimensions": 20},
                                 qd_meta=dict(QD["qd_meta"], database_capacity=200_000, batch_size=400),
                                 control={"kind": "static", "generations": 10}))
    inside = threading.Event()
    done = threading.Event()

    def work():
        inside.set()
        for _ in range(4):
            algo.step(threads=1)
        done.set()

    ticks = 0
    worker = threading.Thread(target=work)
    worker.start()
    inside.wait()
    while not done.is_set():
        ticks += 1
    worker.join()
    assert ticks > 1000, "this thread ran while the other was inside qdmeta"


@pytest.mark.skipif(not qdmeta.build_info["rhex"], reason="qdmeta was built without the RHex task (DART)")
def test_the_rhex_robot_is_there_from_python():
    rhex = qdmeta.Task.builtin({"name": "rhex"})
    x = np.random.default_rng(2).random((3, rhex.genotype_size), dtype=np.float32)
    fitness, features, valid = rhex.evaluate(x)
    assert fitness.shape == (3,) and features.shape == (3, rhex.base_feature_size)
    again = rhex.evaluate(x)
    assert np.array_equal(fitness, again[0]) and np.array_equal(features, again[1])


def raising_once(at, exception=TaskFailure):
    """numpy Rastrigin whose `at`-th call raises `exception` instead."""
    calls = [0]

    def f(x):
        calls[0] += 1
        if calls[0] == at:
            raise exception(f"call {at} failed")
        return rastrigin(x)
    return qdmeta.Task(f, genotype_size=20, base_feature_size=20, name="numpy-rastrigin")


def assert_same_run(a, b):
    assert a.generation == b.generation and a.evaluations == b.evaluations
    x, y = a.data(), b.data()
    assert np.array_equal(x["index"], y["index"]) and np.array_equal(x["solution"], y["solution"])
    assert np.array_equal(x["objective"], y["objective"])


@pytest.mark.parametrize("config,steps,at", [(ME, 6, 1), (ME, 6, 4), (QD, 4, 2), (QD, 4, 9), (QD, 4, 20)],
                         ids=["me-first", "me-later", "qd-after-seeds", "qd-second", "qd-later"])
def test_a_step_that_raises_is_undone_and_stepping_on_gives_the_same_bits(config, steps, at):
    # QD-Meta's steps: the seeds (first step only), then 2 generations of 3 maps, one call each.
    def objective():
        return qdmeta.MetaObjective(lambda e, s: float(np.mean(e[:, 0])), "first-gene") if config is QD else None
    reference = qdmeta.Algorithm(config, task=numpy_rastrigin(), meta_objective=objective())
    algo = qdmeta.Algorithm(config, task=raising_once(at), meta_objective=objective())
    failures = 0
    while algo.generation < steps:
        before = algo.generation
        try:
            algo.step(threads=2)
        except TaskFailure:
            failures += 1
            assert not algo.step_in_progress and algo.generation == before
    assert failures == 1
    for _ in range(steps):
        reference.step(threads=2)
    assert_same_run(algo, reference)
    jobs = algo.ask_jobs()  # and ask/tell work on
    algo.tell_jobs([task.evaluate(x) for task, x in jobs])


def test_a_step_whose_meta_objective_raises_is_undone():
    calls = [0]

    def spread(elites, seed):
        calls[0] += 1
        if calls[0] == 5:
            raise TaskFailure("the meta-objective failed")
        return float(np.std(elites[:, 0])) + seed % 7

    def make():
        return qdmeta.Algorithm(QD, task=numpy_rastrigin(), meta_objective=qdmeta.MetaObjective(spread, "spread"))
    algo = make()
    algo.step()
    with pytest.raises(TaskFailure, match="the meta-objective failed"):
        algo.step()
    assert algo.generation == 1 and not algo.step_in_progress
    algo.step()
    algo.step()
    reference = make()
    for _ in range(3):
        reference.step()
    assert_same_run(algo, reference)


def test_config_dicts_that_contain_themselves_or_nest_too_deep_are_refused():
    looped = dict(ME)
    looped["archive"] = {"bins": [20, 20]}
    looped["archive"]["again"] = looped
    with pytest.raises(qdmeta.InputError, match=r"^config: 'archive\.again' contains itself$"):
        qdmeta.Algorithm(looped, task=numpy_rastrigin())
    listed = [1, 2]
    listed.append(listed)
    with pytest.raises(qdmeta.InputError, match=r"^config: 'archive\.bins' contains itself$"):
        qdmeta.Algorithm(dict(ME, archive={"bins": listed}), task=numpy_rastrigin())
    deep = {}
    for _ in range(100_000):
        deep = {"a": deep}
    with pytest.raises(qdmeta.InputError, match=r"^config: 'a\.a\.a.*\.\.\.' is nested more than 64 levels deep$"):
        qdmeta.Algorithm(deep)
    row = [20]  # the same list twice side by side is no loop: the reader judges it
    with pytest.raises(qdmeta.InputError, match="archive.bins") as info:
        qdmeta.Algorithm(dict(ME, archive={"bins": [row, row]}), task=numpy_rastrigin())
    assert "contains itself" not in str(info.value)


def test_an_integer_too_large_for_the_config_is_named_with_its_range():
    with pytest.raises(qdmeta.InputError) as info:
        qdmeta.Algorithm(dict(ME, seed=2**70), task=numpy_rastrigin())
    assert str(info.value) == (f"config: seed = {2**70} is out of range: a config integer must be in "
                               "[-9223372036854775808, 9223372036854775807]")
    with pytest.raises(qdmeta.InputError, match=r"seed = -1 is out of range"):
        qdmeta.Algorithm(dict(ME, seed=-1), task=numpy_rastrigin())


def warm_sphere(x):
    return -np.sum(x * x, axis=1), x[:, :2].copy()


def test_map_elites_starts_from_a_given_archive_of_its_shape():
    import pickle
    task = qdmeta.Task(warm_sphere, genotype_size=3, base_feature_size=2, name="warm")
    config = {"algorithm": "map-elites", "seed": 3, "archive": {"bins": [4, 4]},
              "map_elites": {"batch_size": 8, "initial_population": 8}}
    given = qdmeta.GridArchive(solution_dim=3, dims=[4, 4])
    given.add(np.full((1, 3), 0.1), np.array([-0.03]), np.array([[0.1, 0.1]]))
    algo = qdmeta.Algorithm(config, task=task, archive=given)
    assert len(algo.archive) == 1 and algo.archive.best_elite["objective"] == np.float32(-0.03)
    offspring = algo.ask()  # the first generation mutates the given elite instead of drawing at random
    assert len(offspring) == 8 and np.mean(offspring == np.float32(0.1)) > 0.5  # rate 0.1: most genes kept
    algo.tell(*task.evaluate(offspring)[:2])
    assert len(given) == 1 and len(algo.archive) >= 1  # the algorithm took a copy
    back = pickle.loads(pickle.dumps(algo))
    assert np.array_equal(back.archive.data("solution"), algo.archive.data("solution"))
    with pytest.raises(qdmeta.InputError, match=r"^Algorithm\(archive=\.\.\.\): the archive has solution_dim 2, "
                                                r"dims \[4, 4\].*, but the config and task make solution_dim 3, dims "
                                                r"\[4, 4\]"):
        qdmeta.Algorithm(config, task=task, archive=qdmeta.GridArchive(solution_dim=2, dims=[4, 4]))
    with pytest.raises(qdmeta.InputError, match=r"dims \[5, 4\]"):
        qdmeta.Algorithm(config, task=task, archive=qdmeta.GridArchive(solution_dim=3, dims=[5, 4]))
    with pytest.raises(ValueError, match=r'serves algorithm "map-elites" only, not "cvt-map-elites"'):
        qdmeta.Algorithm({"algorithm": "cvt-map-elites", "cvt": {"centroids": 20, "samples": 500, "cache": False}},
                         task=task, archive=given)
    with pytest.raises(TypeError, match=r"archive must be a qdmeta\.GridArchive, got list"):
        qdmeta.Algorithm(config, task=task, archive=[1])


CMA_MAE = {"algorithm": "cma-mae", "seed": 3, "archive": {"bins": [20, 20], "learning_rate": 0.05},
           "emitters": {"count": 3, "batch_size": 10}}


def test_cma_mae_by_hand_with_a_numpy_task_gives_the_bits_of_step_and_shows_its_archive():
    task = numpy_rastrigin()
    stepped = qdmeta.Algorithm(CMA_MAE, task=task)
    by_hand = qdmeta.Algorithm(CMA_MAE, task=task)
    for _ in range(30):
        stepped.step(threads=2)
        x = by_hand.ask()
        assert x.shape == (30, 20) and x.min() >= 0.0 and x.max() <= 1.0  # 3 emitters of 10, genes in [0, 1]
        by_hand.tell(*rastrigin(x))
    assert_same_run(stepped, by_hand)
    assert by_hand.evaluations["bottom"] == 30 * 30
    # Its result archive, as the other algorithms': every elite where retrieve finds it.
    archive = stepped.archive
    assert isinstance(archive, qdmeta.GridArchive) and len(archive) == stepped.stats.num_elites > 30
    data = stepped.data()
    occupied, found = stepped.retrieve(data["solution"][:, :2])
    assert occupied.all() and np.array_equal(found["objective"], data["objective"])

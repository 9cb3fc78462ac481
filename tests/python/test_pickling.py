"""Pickling, copy and deepcopy: archives come back as themselves (elites, fill order, future
samples), tasks evaluate the same (also in a process pool), and an algorithm pickled mid-run
continues to the bits the original reaches."""
import copy
import multiprocessing
import pickle

import numpy as np
import pytest

import qdmeta


def sphere(genotypes):
    """A task function importable by name, so it pickles by reference."""
    x = genotypes.astype(np.float64) - 0.5
    fitness = -np.sum(x * x, axis=1)
    return fitness.astype(np.float32), genotypes[:, :2].copy(), genotypes[:, 2] < 0.9


def first_gene_mean(elites, seed):
    return float(np.mean(elites[:, 0])) + (seed % 5) * 1e-3


def sphere_task():
    return qdmeta.Task(sphere, genotype_size=6, base_feature_size=2, name="sphere", qd_offset=-2.0)


def round_trip(obj, how):
    return pickle.loads(pickle.dumps(obj)) if how == "pickle" else copy.deepcopy(obj)


def assert_same_elites(a, b):
    x, y = a.data(), b.data()
    assert x.keys() == y.keys()
    for key in x:
        assert x[key].dtype == y[key].dtype and np.array_equal(x[key], y[key]), key
    assert a.stats.as_dict() == b.stats.as_dict()


def filled_archives():
    rng = np.random.default_rng(3)
    solutions = rng.random((400, 6), dtype=np.float32)
    objectives = rng.normal(size=400).astype(np.float32)
    measures = rng.random((400, 2), dtype=np.float32)
    grid = qdmeta.GridArchive(solution_dim=6, dims=[7, 9], lower=-0.5, upper=1.5, qd_offset=-3.0,
                              base_feature_dim=2, seed=11)
    grid.add(solutions, objectives, measures, base_features=measures * 0.5)
    cvt = qdmeta.CvtArchive(solution_dim=6, centroids=rng.random((30, 2)), qd_offset=-1.0, seed=12)
    cvt.add(solutions, objectives, measures)
    unstructured = qdmeta.UnstructuredArchive(solution_dim=6, measure_dim=2, target_size=50, seed=13)
    unstructured.add(solutions, objectives, measures, threshold=0.1)
    return [grid, cvt, unstructured]


def later_batch():
    rng = np.random.default_rng(4)
    return rng.random((300, 6), dtype=np.float32), rng.normal(size=300).astype(np.float32), rng.random(
        (300, 2), dtype=np.float32)


def add(archive, batch):
    if isinstance(archive, qdmeta.UnstructuredArchive):
        return archive.add(*batch, threshold=0.1)
    if isinstance(archive, qdmeta.GridArchive):
        return archive.add(*batch, base_features=batch[2] * 0.5)
    return archive.add(*batch)


@pytest.mark.parametrize("how", ["pickle", "deepcopy", "copy"])
@pytest.mark.parametrize("index", [0, 1, 2], ids=["grid", "cvt", "unstructured"])
def test_an_archive_comes_back_as_itself(how, index):
    original = filled_archives()[index]
    original.sample_elites(5)  # the copy continues the sampling streams from here
    twin = copy.copy(original) if how == "copy" else round_trip(original, how)
    assert type(twin) is type(original) and twin is not original
    assert len(twin) == len(original) > 10 and twin.seed == original.seed
    assert_same_elites(twin, original)
    a, b = original.sample_elites(50), twin.sample_elites(50)
    for field in a:
        assert np.array_equal(a[field], b[field]), field
    # The same future: the same statuses for the same batch, then the same elites and samples.
    assert np.array_equal(add(twin, later_batch()), add(original, later_batch()))
    assert_same_elites(twin, original)
    a, b = original.sample_elites(200), twin.sample_elites(200)
    for field in a:
        assert np.array_equal(a[field], b[field]), field
    if index == 1:
        assert np.array_equal(twin.centroids, original.centroids)
    # And they are separate objects.
    twin.clear()
    assert len(twin) == 0 and len(original) > 0


def test_a_pickled_grid_keeps_its_parameters():
    grid = filled_archives()[0]
    twin = pickle.loads(pickle.dumps(grid))
    assert (twin.dims, twin.lower, twin.upper, twin.solution_dim, twin.measure_dim) == ([7, 9], -0.5, 1.5, 6, 2)
    m = np.array([[-0.5, -0.5], [1.49, 1.49], [0.3, 0.8]], dtype=np.float32)
    assert np.array_equal(twin.index_of(m), grid.index_of(m))
    # The QD-score offset came along: sum(objective - (-3)).
    assert twin.stats.qd_score == pytest.approx(float(np.sum(twin.data()["objective"].astype(np.float64) + 3.0)))


def test_a_state_that_qdmeta_did_not_make_is_refused():
    grid = qdmeta.GridArchive(solution_dim=2, dims=[3])
    state = grid.__getstate__()
    damaged = (state[0], state[1], state[2], state[3], state[4][:-3], state[5])
    fresh = qdmeta.GridArchive.__new__(qdmeta.GridArchive)  # as pickle makes it
    with pytest.raises(qdmeta.InputError, match="the pickled GridArchive: truncated"):
        fresh.__setstate__(damaged)
    with pytest.raises(qdmeta.InputError, match="state format 99"):
        fresh.__setstate__((99,) + tuple(state[1:]))
    fresh.__setstate__(state)
    assert len(fresh) == 0 and fresh.dims == [3]


def test_tasks_pickle_by_reference_and_by_config():
    x = np.random.default_rng(0).random((32, 6), dtype=np.float32)
    python_task = sphere_task()
    builtin = qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 6})
    for task in (python_task, builtin):
        for how in ("pickle", "deepcopy"):
            twin = round_trip(task, how)
            assert (twin.name, twin.genotype_size, twin.base_feature_size, twin.qd_offset, twin.is_python) == (
                task.name, task.genotype_size, task.base_feature_size, task.qd_offset, task.is_python)
            for a, b in zip(task.evaluate(x), twin.evaluate(x)):
                assert a.dtype == b.dtype and np.array_equal(a, b)
    assert b"sphere" in pickle.dumps(python_task)  # the function by its name, not its code
    assert builtin.__getstate__() == ("builtin", qdmeta.Task.builtin({"name": "rastrigin",
                                                                      "dimensions": 6}).__getstate__()[1])
    assert builtin.__getstate__()[1]["dimensions"] == 6


def test_a_meta_objective_pickles_with_what_it_reads():
    for archive in (False, True):
        objective = qdmeta.MetaObjective(first_gene_mean, name="first-gene-mean", archive=archive)
        for how in ("pickle", "deepcopy"):
            twin = round_trip(objective, how)
            assert (twin.name, twin.archive) == ("first-gene-mean", archive)
    # A state pickled before `archive` existed: (function, name) reads the genotypes.
    fresh = qdmeta.MetaObjective.__new__(qdmeta.MetaObjective)
    fresh.__setstate__((first_gene_mean, "old"))
    assert (fresh.name, fresh.archive) == ("old", False)
    with pytest.raises(qdmeta.InputError, match="not one qdmeta made"):
        qdmeta.MetaObjective.__new__(qdmeta.MetaObjective).__setstate__((first_gene_mean, "x", "yes"))


def test_a_task_that_cannot_pickle_says_why():
    local = qdmeta.Task(lambda g: sphere(g), genotype_size=6, base_feature_size=2, name="local")
    with pytest.raises((pickle.PicklingError, AttributeError)):
        pickle.dumps(local)
    # A task the config made (here the algorithm's own) has no table of its own to pickle as.
    algo = qdmeta.Algorithm({"algorithm": "map-elites", "task": {"name": "rastrigin", "dimensions": 6}})
    [(made_by_config, _)] = algo.ask_jobs()
    assert made_by_config.name == "rastrigin"
    with pytest.raises(TypeError, match=r"cannot pickle task 'rastrigin': only a Task\(function, \.\.\.\) or a "
                                        r"Task\.builtin\(table\) pickles"):
        pickle.dumps(made_by_config)


def evaluate_in_worker(task, genotypes):
    return task.evaluate(genotypes)


def test_a_task_evaluates_the_same_in_a_process_pool():
    x = np.random.default_rng(1).random((64, 6), dtype=np.float32)
    tasks = [sphere_task(), qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 6})]
    with multiprocessing.get_context("spawn").Pool(2) as pool:
        remote = pool.starmap(evaluate_in_worker, [(t, x) for t in tasks])
    for task, results in zip(tasks, remote):
        for here, there in zip(task.evaluate(x), results):
            assert here.dtype == there.dtype and np.array_equal(here, there)


ME = {"algorithm": "map-elites", "seed": 7, "archive": {"bins": [10, 10]},
      "map_elites": {"batch_size": 40, "initial_population": 100}}
CVT = {"algorithm": "cvt-map-elites", "seed": 7, "cvt": {"centroids": 50, "samples": 2000, "cache": False},
       "map_elites": {"batch_size": 40, "initial_population": 100}}
AURORA = {"algorithm": "aurora", "seed": 7,
          "aurora": {"batch_size": 40, "initial_population": 200, "target_size": 100, "max_epochs": 5,
                     "rebuild_every": 2, "retrain_period_step": 1, "retrain_period_max": 3}}
QD = {"algorithm": "qd-meta", "seed": 7, "archive": {"bins": [5, 5]},
      "control": {"kind": "sarsa", "min_generations": 1, "max_generations": 3},
      "qd_meta": {"meta_population": 3, "batch_size": 30, "initial_population": 100, "database_capacity": 2000}}

CMA_ME = {"algorithm": "cma-me", "seed": 7, "archive": {"bins": [10, 10]}, "emitters": {"count": 2, "batch_size": 8}}
CMA_MAE = {"algorithm": "cma-mae", "seed": 7, "emitters": {"count": 2, "batch_size": 8, "restart_rule": "every-n",
                                                          "restart_every": 2},
           "archive": {"kind": "cvt", "learning_rate": 0.1}, "cvt": {"centroids": 50, "samples": 2000, "cache": False}}


def assert_same_algorithm(a, b):
    assert a.generation == b.generation and a.evaluations == b.evaluations
    assert a.config == b.config
    assert_same_elites(a, b)


@pytest.mark.parametrize("how", ["pickle", "deepcopy"])
@pytest.mark.parametrize("config,objective,steps,more", [
    (ME, None, 4, 5), (CVT, None, 3, 4), (AURORA, None, 3, 4), (QD, first_gene_mean, 2, 3), (QD, None, 2, 2),
    (CMA_ME, None, 5, 6), (CMA_MAE, None, 5, 6)],
    ids=["map-elites", "cvt-map-elites", "aurora", "qd-meta-python-objective", "qd-meta-builtin", "cma-me", "cma-mae-cvt"])
def test_a_pickled_algorithm_continues_to_the_same_bits(config, objective, steps, more, how):
    if objective is None and config is QD:
        config = dict(QD, task={"name": "rastrigin", "dimensions": 6})
        kwargs = {}
    else:
        kwargs = {"task": sphere_task()}
    if objective is not None:
        kwargs["meta_objective"] = qdmeta.MetaObjective(objective, name="first-gene-mean")
    original = qdmeta.Algorithm(config, **kwargs)
    for _ in range(steps):
        original.step(threads=2)
    assert original.stats.num_elites > 0
    twin = round_trip(original, how)
    assert_same_algorithm(twin, original)
    for _ in range(more):
        original.step(threads=2)
        twin.step(threads=1)
    assert_same_algorithm(twin, original)
    assert twin.generation == steps + more
    # Driven by hand from here, both ask for the same genotypes.
    jobs_a, jobs_b = original.ask_jobs(), twin.ask_jobs()
    assert len(jobs_a) == len(jobs_b)
    for (ta, xa), (tb, xb) in zip(jobs_a, jobs_b):
        assert ta.name == tb.name and np.array_equal(xa, xb)


def test_a_fresh_algorithm_pickles_and_a_step_in_progress_is_refused():
    algo = qdmeta.Algorithm(ME, task=sphere_task())
    twin = pickle.loads(pickle.dumps(algo))
    assert twin.generation == 0 and len(twin.data()["index"]) == 0
    x = algo.ask()
    with pytest.raises(qdmeta.Error, match="cannot pickle in the middle of a step"):
        pickle.dumps(algo)
    algo.tell(*sphere(x))
    twin = pickle.loads(pickle.dumps(algo))
    twin.step(threads=1)
    algo.step(threads=1)
    assert_same_algorithm(twin, algo)


def test_an_unpickled_algorithm_runs_to_a_budget_as_the_original():
    original = qdmeta.Algorithm(ME, task=sphere_task())
    original.run(budget=500, threads=1)
    twin = pickle.loads(pickle.dumps(original))
    assert twin.config["budget"]["evaluations"] == 500
    original.run(budget=1500, threads=1)
    twin.run(budget=1500, threads=1)
    assert_same_algorithm(twin, original)


# A pickle has no checksum of its own: each qdmeta state carries one (the checkpoint's) and is
# value-checked on load, so a flipped bit is refused, never loaded as other data.
def flipped(data, bit):
    damaged = bytearray(data)
    damaged[bit // 8] ^= 1 << (bit % 8)
    return bytes(damaged)


def loaded_or_refused(data, kind):
    """The object pickle.loads makes of `data`, or None when it refuses it (any exception: a
    pickle opcode broken, a qdmeta state refused) or makes no `kind` (a flipped opcode may make
    pickle load a str: no qdmeta state was read)."""
    try:
        loaded = pickle.loads(data)
    except Exception:  # noqa: BLE001 (every refusal is fine here; loading other data is not)
        return None
    return loaded if type(loaded) is kind else None


@pytest.mark.parametrize("make", [lambda: filled_archives()[0], lambda: filled_archives()[1],
                                  lambda: filled_archives()[2]], ids=["grid", "cvt", "unstructured"])
def test_an_archive_pickle_with_a_bit_flipped_is_refused_or_the_same(make):
    original = make()
    data = pickle.dumps(original)
    same = 0
    for bit in range(5, 8 * len(data), 8 * len(data) // 160):  # 160 flips spread over every byte range
        twin = loaded_or_refused(flipped(data, bit), type(original))
        if twin is not None:
            assert_same_elites(twin, original)
            assert (twin.seed, twin.solution_dim, twin.measure_dim) == (original.seed, original.solution_dim,
                                                                        original.measure_dim)
            same += 1
    assert same < 10  # a flip in pickle's own framing may leave the data as it was; no more


def test_an_algorithm_pickle_with_a_bit_flipped_is_refused_or_the_same():
    original = qdmeta.Algorithm(ME, task=sphere_task())
    for _ in range(3):
        original.step(threads=1)
    data = pickle.dumps(original)
    for bit in range(3, 8 * len(data), 8 * len(data) // 160):
        twin = loaded_or_refused(flipped(data, bit), qdmeta.Algorithm)
        if twin is not None:
            assert_same_algorithm(twin, original)


def with_bytes(state, old, new):
    """The algorithm state with one value of its checkpoint bytes replaced (found by its bytes)."""
    raw = state[4]
    assert old in raw
    return state[:4] + (raw.replace(old, new, 1),) + state[5:]


@pytest.mark.parametrize("what, rule", [("objective", "non-finite objective or measure"),
                                        ("gene", "the state is damaged: elite 0 \\(cell \\d+\\) has a gene nan, where every gene must lie in \\[0, 1\\]")])
def test_an_algorithm_state_with_a_nan_value_is_refused_on_load(what, rule):
    algo = qdmeta.Algorithm(ME, task=sphere_task())
    algo.step(threads=1)
    data = algo.data()
    value = data["objective"][0] if what == "objective" else data["solution"][0, 0]
    state = algo.__getstate__()
    damaged = with_bytes(state, np.float32(value).tobytes(), np.float32(np.nan).tobytes())
    fresh = qdmeta.Algorithm.__new__(qdmeta.Algorithm)
    with pytest.raises(qdmeta.InputError, match=rule):
        fresh.__setstate__(damaged)


def test_an_algorithm_state_whose_bytes_changed_is_refused_by_its_checksum():
    algo = qdmeta.Algorithm(ME, task=sphere_task())
    algo.step(threads=1)
    state = algo.__getstate__()
    value = algo.data()["objective"][0]
    damaged = with_bytes(state, np.float32(value).tobytes(), np.float32(value + 1).tobytes())
    fresh = qdmeta.Algorithm.__new__(qdmeta.Algorithm)
    with pytest.raises(qdmeta.InputError, match="unpickling a qdmeta.Algorithm: the state is damaged \\(checksum "
                                                "mismatch\\)"):
        fresh.__setstate__(damaged)
    config = dict(state[1], seed=state[1]["seed"] + 1)  # the config too
    with pytest.raises(qdmeta.InputError, match="checksum mismatch"):
        qdmeta.Algorithm.__new__(qdmeta.Algorithm).__setstate__(state[:1] + (config,) + state[2:])


def test_a_pickled_cvt_map_elites_carries_its_centroids():
    algo = qdmeta.Algorithm(CVT, task=sphere_task())
    assert algo.__getstate__()[7] is None  # no centroids before the first step
    algo.step()
    state = algo.__getstate__()
    centroids = algo.archive.centroids
    assert state[0] == 3 and np.array_equal(state[7], centroids) and state[7].shape == (50, 2)
    back = pickle.loads(pickle.dumps(algo))
    assert np.array_equal(back.archive.centroids, centroids)
    assert_same_algorithm(algo, back)
    # The pickle's centroids are the ones used (the elites no longer fall in their cells), and refused.
    tampered = state[:7] + (centroids[::-1].copy(),)
    with pytest.raises(qdmeta.InputError, match=r"does not fall in its saved cell|checksum"):
        qdmeta.Algorithm.__new__(qdmeta.Algorithm).__setstate__(tampered)
    assert qdmeta.Algorithm(ME, task=sphere_task()).__getstate__()[7] is None

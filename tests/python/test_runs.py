"""Runs from Python: the CLI's run directory, Ctrl-C with a checkpoint, resume to the same bits,
and the CLI reading a Python run."""
import json
import os
import signal
import subprocess
import traceback

import numpy as np
import pytest

import qdmeta
from test_algorithms import QD, numpy_rastrigin


@pytest.fixture(autouse=True)
def ctrl_c_raises_keyboard_interrupt():
    """SIGINT as an interactive Python has it: a process started in the background (a CI job, nohup,
    `cmd &` in a script) inherits SIGINT ignored, and the Ctrl-C tests below would then fail, their
    os.kill(SIGINT) ignored, for a reason that is the shell's and not qdmeta's."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)


CONFIG = {"algorithm": "map-elites", "seed": 3, "budget": {"evaluations": 6000},
          "archive": {"bins": [20, 20]}, "map_elites": {"batch_size": 100, "initial_population": 500},
          "checkpoint": {"every_seconds": 0.0}}


def test_a_run_writes_the_clis_run_directory(tmp_path):
    seen = []
    summary = qdmeta.run(CONFIG, tmp_path / "run", task=numpy_rastrigin(), threads=2, progress=seen.append)
    run = tmp_path / "run"
    for f in ("config.toml", "metrics.csv", "archive.csv", "summary.json"):
        assert (run / f).stat().st_size > 0, f
    assert not (run / "checkpoint.bin").exists(), "a finished run drops its checkpoint"
    assert summary == json.loads((run / "summary.json").read_text())
    assert summary["stop_reason"] == "budget" and summary["task"] == "numpy-rastrigin"
    assert summary["evals"] == 6000 and summary["num_elites"] > 100
    assert [p["evals"] for p in seen] == list(range(500, 6001, 100))
    assert seen[-1]["num_elites"] == summary["num_elites"]
    config = (run / "config.toml").read_text()
    assert "name = 'numpy-rastrigin'" in config and "config_file = '<python>'" in config
    with pytest.raises(qdmeta.InputError, match="holds a run"):
        qdmeta.run(CONFIG, run, task=numpy_rastrigin())


def interrupt_at(evals):
    def progress(p):
        if p["evals"] == evals:
            os.kill(os.getpid(), signal.SIGINT)  # as Ctrl-C would
    return progress


def test_ctrl_c_leaves_a_checkpoint_and_resume_gives_the_same_bits(tmp_path):
    qdmeta.run(CONFIG, tmp_path / "straight", task=numpy_rastrigin(), threads=1)
    with pytest.raises(KeyboardInterrupt):
        qdmeta.run(CONFIG, tmp_path / "stopped", task=numpy_rastrigin(), threads=2, progress=interrupt_at(2000))
    stopped = tmp_path / "stopped"
    assert (stopped / "checkpoint.bin").exists()
    assert json.loads((stopped / "summary.json").read_text())["stop_reason"] == "interrupted"
    with pytest.raises(qdmeta.InputError, match="pass it again"):
        qdmeta.resume(stopped)
    summary = qdmeta.resume(stopped, task=numpy_rastrigin(), threads=2)
    assert summary["stop_reason"] == "budget"
    for f in ("archive.csv", "metrics.csv"):
        assert (stopped / f).read_bytes() == (tmp_path / "straight" / f).read_bytes(), f


def test_a_python_meta_objective_run_resumes_and_logs_its_values(tmp_path):
    def spread(elites, seed):
        return float(np.std(elites[:, 0]))

    config = dict(QD, budget={"evaluations": 3000}, checkpoint={"every_seconds": 0.0})
    objective = qdmeta.MetaObjective(spread, name="spread")
    qdmeta.run(config, tmp_path / "straight", task=numpy_rastrigin(), meta_objective=objective)
    with pytest.raises(KeyboardInterrupt):
        qdmeta.run(config, tmp_path / "stopped", task=numpy_rastrigin(), meta_objective=objective,
                   progress=lambda p: p["generation"] == 3 and os.kill(os.getpid(), signal.SIGINT))
    with pytest.raises(ValueError, match="meta_fitness.kind is 'spread', but the meta-objective given is 'other'"):
        qdmeta.resume(tmp_path / "stopped", task=numpy_rastrigin(), meta_objective=qdmeta.MetaObjective(spread, "other"))
    qdmeta.resume(tmp_path / "stopped", task=numpy_rastrigin(), meta_objective=objective)
    for f in ("archive.csv", "meta.csv"):
        assert (tmp_path / "stopped" / f).read_bytes() == (tmp_path / "straight" / f).read_bytes(), f
    meta = np.genfromtxt(tmp_path / "straight" / "meta.csv", delimiter=",", names=True)
    assert (meta["meta_fitness_best"] >= meta["meta_fitness_mean"]).all()
    assert 0 < meta["meta_fitness_best"].max() < 0.5, "the std of genes in [0, 1]"


def test_the_cli_reads_a_python_run(tmp_path):
    qdmeta.run(dict(CONFIG, task={"name": "rastrigin", "dimensions": 20}), tmp_path / "run")
    binary = os.environ.get("QDMETA_BINARY")
    if not binary:
        pytest.skip("QDMETA_BINARY is not set (ctest sets it)")
    out = subprocess.run([binary, "adapt", "--run", str(tmp_path / "run"), "--test", "translation", "--budget", "5"],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert (tmp_path / "run" / "adapt-translation.csv").exists()


class SimulatorCrash(Exception):
    pass


def test_a_task_that_fails_midway_leaves_a_resumable_run(tmp_path):
    calls = [0]

    def flaky(x):
        calls[0] += 1
        if calls[0] == 12:
            raise SimulatorCrash("the simulator crashed")
        return rastrigin_parts(x)

    run = tmp_path / "run"
    with pytest.raises(SimulatorCrash, match="the simulator crashed"):
        qdmeta.run(CONFIG, run, task=qdmeta.Task(flaky, 20, 20, name="numpy-rastrigin"))
    assert not (run / "summary.json").exists(), "the run must not look finished"
    assert (run / "checkpoint.bin").exists()
    lines = (run / "metrics.csv").read_text().splitlines(keepends=True)
    assert all(line.endswith("\n") and line.count(",") == lines[0].count(",") for line in lines)
    qdmeta.resume(run, task=numpy_rastrigin())
    qdmeta.run(CONFIG, tmp_path / "straight", task=numpy_rastrigin())
    for f in ("archive.csv", "metrics.csv"):
        assert (run / f).read_bytes() == (tmp_path / "straight" / f).read_bytes(), f


def rastrigin_parts(x):
    from test_algorithms import rastrigin
    return rastrigin(x)


def test_algorithm_run_in_memory_and_into_a_run_directory(tmp_path):
    algo = qdmeta.Algorithm(CONFIG, task=numpy_rastrigin())
    result = algo.run(budget=3000, threads=2)
    assert result["stop_reason"] == "budget" and result["evals"] == 3000 == algo.evaluations["bottom"]
    assert result["num_elites"] == algo.stats.num_elites
    more = algo.run(budget=4000)
    assert more["evals"] == 4000, "a second run() continues to the new budget"
    with pytest.raises(ValueError, match="a run directory needs a fresh one"):
        algo.run(out_dir=tmp_path / "late")
    fresh = qdmeta.Algorithm(CONFIG, task=numpy_rastrigin())
    summary = fresh.run(budget=3000, out_dir=tmp_path / "run")
    assert summary["evals"] == 3000 and (tmp_path / "run" / "archive.csv").exists()
    assert "evaluations = 3000" in (tmp_path / "run" / "config.toml").read_text()
    reference = qdmeta.Algorithm(CONFIG, task=numpy_rastrigin())
    reference.run(budget=3000)
    assert np.array_equal(reference.data()["solution"], fresh.data()["solution"])


def ctrl_c_at_call(at):
    """numpy Rastrigin that is sent SIGINT (as Ctrl-C would) during its `at`-th call."""
    calls = [0]

    def f(x):
        calls[0] += 1
        if calls[0] == at:
            os.kill(os.getpid(), signal.SIGINT)  # KeyboardInterrupt is raised here, inside the task
        return rastrigin_parts(x)
    return qdmeta.Task(f, 20, 20, name="numpy-rastrigin")


def spread(elites, seed):
    return float(np.std(elites[:, 0]))


# (algorithm, the task's call that gets Ctrl-C, the generations finished before it): QD-Meta's
# first step makes 7 calls (the seeds, then 2 generations of 3 maps), the next ones 6.
@pytest.mark.parametrize("algorithm,at,finished", [("map-elites", 1, 0), ("map-elites", 7, 6), ("qd-meta", 3, 0),
                                                   ("qd-meta", 12, 1)])
def test_ctrl_c_inside_a_python_task_ends_the_run_with_its_files_and_resumes_to_the_same_bits(tmp_path, algorithm,
                                                                                               at, finished):
    config, objective = CONFIG, None
    if algorithm == "qd-meta":
        config = dict(QD, budget={"evaluations": 3000}, checkpoint={"every_seconds": 0.0})
        objective = qdmeta.MetaObjective(spread, name="spread")
    qdmeta.run(config, tmp_path / "straight", task=numpy_rastrigin(), meta_objective=objective, threads=1)
    stopped = tmp_path / "stopped"
    with pytest.raises(KeyboardInterrupt) as info:
        qdmeta.run(config, stopped, task=ctrl_c_at_call(at), meta_objective=objective, threads=1)
    assert "f" in [frame.name for frame in traceback.extract_tb(info.value.__traceback__)], "raised in the task"
    summary = json.loads((stopped / "summary.json").read_text())
    assert summary["stop_reason"] == "interrupted" and summary["generations"] == finished
    assert (stopped / "archive.csv").exists() and (stopped / "checkpoint.bin").exists()
    qdmeta.resume(stopped, task=numpy_rastrigin(), meta_objective=objective, threads=1)
    for f in ("archive.csv", "metrics.csv") + (("meta.csv",) if algorithm == "qd-meta" else ()):
        assert (stopped / f).read_bytes() == (tmp_path / "straight" / f).read_bytes(), f


def test_ctrl_c_inside_a_python_meta_objective_ends_the_run_with_its_files(tmp_path):
    calls = [0]

    def interrupted_spread(elites, seed):
        calls[0] += 1
        if calls[0] == 4:  # map 1 of meta-generation 2
            os.kill(os.getpid(), signal.SIGINT)
        return spread(elites, seed)

    config = dict(QD, budget={"evaluations": 3000}, checkpoint={"every_seconds": 0.0})
    objective = qdmeta.MetaObjective(interrupted_spread, name="spread")
    qdmeta.run(config, tmp_path / "straight", task=numpy_rastrigin(), meta_objective=qdmeta.MetaObjective(spread, "spread"),
               threads=1)
    with pytest.raises(KeyboardInterrupt):
        qdmeta.run(config, tmp_path / "stopped", task=numpy_rastrigin(), meta_objective=objective, threads=1)
    summary = json.loads((tmp_path / "stopped" / "summary.json").read_text())
    assert summary["stop_reason"] == "interrupted" and summary["generations"] == 1
    calls[0] = -10**9  # no more Ctrl-C
    qdmeta.resume(tmp_path / "stopped", task=numpy_rastrigin(), meta_objective=objective, threads=1)
    for f in ("archive.csv", "meta.csv"):
        assert (tmp_path / "stopped" / f).read_bytes() == (tmp_path / "straight" / f).read_bytes(), f


def test_ctrl_c_inside_a_python_task_leaves_an_in_memory_algorithm_usable():
    algo = qdmeta.Algorithm(CONFIG, task=ctrl_c_at_call(5))
    with pytest.raises(KeyboardInterrupt):
        algo.run(budget=3000, threads=1)
    assert algo.generation == 4 and not algo.step_in_progress
    assert algo.run(budget=3000, threads=1)["evals"] == 3000
    reference = qdmeta.Algorithm(CONFIG, task=numpy_rastrigin())
    reference.run(budget=3000, threads=1)
    assert np.array_equal(reference.data()["solution"], algo.data()["solution"])

"""One exception per kind of mistake, wherever it is found, and messages in Python's words: a
bad value from the caller's task is the same qdmeta.InputError whether tell() or a run finds it;
a used run directory names overwrite=True and qdmeta.resume(); a run without a task says so
instead of running Rastrigin; Task.evaluate refuses genes outside [0, 1]."""
import numpy as np
import pytest

import qdmeta

ME = {"algorithm": "map-elites", "seed": 1, "archive": {"bins": [4, 4]}, "budget": {"evaluations": 60},
      "map_elites": {"batch_size": 10, "initial_population": 20}}


def features_of(x):
    return x[:, :2].copy()


def with_a_bad_feature(x):
    """Row 3's base feature 1 is 1.5."""
    features = features_of(x)
    features[3, 1] = 1.5
    return -np.sum(x * x, axis=1), features


def bad_task():
    return qdmeta.Task(with_a_bad_feature, genotype_size=4, base_feature_size=2, name="bad")


def test_a_bad_value_is_the_same_input_error_from_tell_a_step_a_run_and_evaluate(tmp_path):
    message = r"row 3: base feature 1 is 1\.5, outside \[0, 1\]"
    by_hand = qdmeta.Algorithm(ME, task=bad_task())
    x = by_hand.ask()
    with pytest.raises(qdmeta.InputError, match=r"tell\(\): job 0 " + message):
        by_hand.tell(*with_a_bad_feature(x))
    with pytest.raises(qdmeta.InputError, match=r"^task 'bad' " + message):
        bad_task().evaluate(x)
    with pytest.raises(qdmeta.InputError, match=r"^task 'bad' " + message):
        qdmeta.Algorithm(ME, task=bad_task()).step()
    with pytest.raises(qdmeta.InputError, match=r"^task 'bad' " + message):
        qdmeta.Algorithm(ME, task=bad_task()).run()
    with pytest.raises(qdmeta.InputError, match=r"^task 'bad' " + message):
        qdmeta.run(ME, tmp_path / "run", task=bad_task())
    # An InputError is a ValueError, as a wrong shape is.
    assert issubclass(qdmeta.InputError, ValueError) and issubclass(qdmeta.InputError, qdmeta.Error)


def test_a_used_run_directory_is_refused_in_pythons_words(tmp_path):
    task = qdmeta.Task(lambda x: (np.zeros(len(x)), features_of(x)), genotype_size=4, base_feature_size=2, name="ok")
    qdmeta.run(ME, tmp_path, task=task)
    with pytest.raises(qdmeta.InputError) as info:
        qdmeta.run(ME, tmp_path, task=task)
    assert str(info.value) == (f"{tmp_path} already holds a run: pass overwrite=True to replace it, or continue it "
                               f"with qdmeta.resume('{tmp_path}')")
    with pytest.raises(qdmeta.InputError, match="pass overwrite=True"):
        qdmeta.Algorithm(ME, task=task).run(out_dir=tmp_path)
    assert qdmeta.run(ME, tmp_path, task=task, overwrite=True)["stop_reason"] == "budget"


def test_a_run_without_a_task_says_so():
    expected = r"^config: no task: pass task=qdmeta\.Task\(\.\.\.\) or give config\['task'\]"
    with pytest.raises(qdmeta.InputError, match=expected):
        qdmeta.Algorithm(ME)
    with pytest.raises(qdmeta.InputError, match=expected):
        qdmeta.run(ME, "never-made")
    # Named either way, it runs.
    named = qdmeta.Algorithm(dict(ME, task={"name": "rastrigin", "dimensions": 4}))
    assert named.ask().shape == (20, 4)


def test_a_builtin_task_given_as_task_brings_its_settings():
    five = qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 5})
    algo = qdmeta.Algorithm(ME, task=five)
    assert algo.ask().shape == (20, 5) and algo.config["task"]["dimensions"] == 5
    agreeing = qdmeta.Algorithm(dict(ME, task={"name": "rastrigin", "dimensions": 5}), task=five)
    assert agreeing.config["task"] == algo.config["task"]
    with pytest.raises(qdmeta.InputError, match=r"^config: task\.dimensions is 6, but the task given has 5$"):
        qdmeta.Algorithm(dict(ME, task={"dimensions": 6}), task=five)


def test_more_bins_than_base_features_names_the_bins():
    with pytest.raises(qdmeta.InputError) as info:
        qdmeta.Algorithm(dict(ME, archive={"bins": [3, 3, 3]}), task=bad_task())
    assert str(info.value) == ("<python>: archive.bins has 3 entries (one per target feature), but the task has 2 "
                               "base features: give at most 2, or archive.measures to pick a base feature for each")


def test_task_evaluate_refuses_genes_outside_the_unit_interval():
    task = qdmeta.Task.builtin({"name": "rastrigin", "dimensions": 3})
    assert task.evaluate(np.array([[0.0, 0.5, 1.0]]))[2].all()
    for gene in (1.5, -0.25, np.nan):
        genotypes = np.full((2, 3), 0.5)
        genotypes[1, 2] = gene
        with pytest.raises(qdmeta.InputError, match=rf"^genotypes row 1 gene 2 is {gene}, outside \[0, 1\]$"):
            task.evaluate(genotypes)


def test_arguments_a_method_does_not_take_are_one_line_without_the_arrays():
    archive = qdmeta.GridArchive(solution_dim=3, dims=[4, 4])
    batch = np.zeros((500, 3)), np.zeros(500), np.zeros((500, 2))
    with pytest.raises(TypeError) as info:
        archive.add(solution=batch[0], objective=batch[1], measures=batch[2])  # pyribs's names
    assert str(info.value) == ("GridArchive.add() takes (solutions, objectives, measures, base_features=None, "
                               "valid=None); it was given solution=, objective=, measures=")
    algo = qdmeta.Algorithm(ME, task=bad_task())
    x = algo.ask()
    with pytest.raises(TypeError, match=r"^Algorithm\.tell\(\) takes \(fitness, base_features, valid=None\); it "
                                        r"was given objective=, measures=$"):
        algo.tell(objective=np.zeros(len(x)), measures=x)
    with pytest.raises(TypeError, match=r"^CvtArchive\(\) takes \(solution_dim, centroids, qd_offset=0\.0, "
                                        r"seed=1, learning_rate=None, threshold_min=-inf\); it was given 2 positional, ranges=$"):
        qdmeta.CvtArchive(3, np.zeros((1000, 2)), ranges=[(0, 1), (0, 1)])
    # A TypeError from the caller's own task reaches them as it was raised.
    def typo(x):
        raise TypeError("my task's own mistake")
    with pytest.raises(TypeError, match="^my task's own mistake$"):
        qdmeta.Algorithm(ME, task=qdmeta.Task(typo, genotype_size=4, base_feature_size=2)).step()
    # The wrapped methods keep their names and documentation.
    assert qdmeta.GridArchive.add.__name__ == "add" and "statuses" in qdmeta.GridArchive.add.__doc__


# Text and paths the C++ side cannot take: one line naming the key or argument and the reason,
# never pybind11's "Unable to cast" or its list of overloads, never a message cut at a NUL.
@pytest.mark.parametrize("text, reason", [("ra\ud800strigin", r"holds a lone surrogate \(a code point in "
                                                             r"U\+D800\.\.U\+DFFF\), which is not text: give valid "
                                                             r"Unicode$"),
                                          ("ras\0trigin", r"holds a NUL character \(at byte 3\), which qdmeta's text "
                                                          r"cannot hold$")])
def test_a_config_string_the_cpp_side_cannot_take_names_its_key(text, reason):
    with pytest.raises(qdmeta.InputError, match=r"^config: 'task\.name' " + reason):
        qdmeta.Algorithm(dict(ME, task={"name": text}))
    with pytest.raises(qdmeta.InputError, match=r"^config: key '" + ("ra\\\\ud800strigin" if "\ud800" in text else
                                                                     "ras\\\\x00trigin") + "' under 'task' " + reason):
        qdmeta.Algorithm(dict(ME, task={"name": "rastrigin", text: 1}))
    with pytest.raises(qdmeta.InputError, match=r"^Task\(\): name " + reason):
        qdmeta.Task(features_of, genotype_size=4, base_feature_size=2, name=text)
    with pytest.raises(qdmeta.InputError, match=r"^MetaObjective\(\): name " + reason):
        qdmeta.MetaObjective(features_of, name=text)


@pytest.mark.parametrize("call", ["run", "resume", "Algorithm.run"])
def test_a_path_with_a_nul_names_the_argument_in_one_line(tmp_path, call):
    out = str(tmp_path / "ru\0n")
    with pytest.raises(ValueError) as refused:
        if call == "run":
            qdmeta.run(dict(ME, task={"name": "rastrigin"}), out)
        elif call == "resume":
            qdmeta.resume(out_dir=out)
        else:
            qdmeta.Algorithm(dict(ME, task={"name": "rastrigin"})).run(out_dir=out)
    assert str(refused.value) == f"{call}(): out_dir holds a NUL character, which no path can hold"


def test_a_config_takes_numpy_arrays_and_scalars_where_it_takes_lists_and_numbers():
    task = qdmeta.Task(lambda x: (np.zeros(len(x)), features_of(x)), genotype_size=4, base_feature_size=2, name="ok")
    config = dict(ME, archive={"bins": np.array([5, 3])}, map_elites={"batch_size": np.int64(10),
                                                                      "initial_population": 20})
    algo = qdmeta.Algorithm(config, task=task)
    assert algo.archive.dims == [5, 3] and len(algo.ask()) == 20
    assert qdmeta.Algorithm(dict(ME, archive={"bins": [np.int32(2), 2]}), task=task).archive.dims == [2, 2]


def test_a_mutation_key_the_kind_does_not_read_is_refused_naming_it():
    task = qdmeta.Task(lambda x: (np.zeros(len(x)), features_of(x)), genotype_size=4, base_feature_size=2, name="ok")
    with pytest.raises(qdmeta.InputError, match=r'^<python>: mutation\.sigma is not read by mutation kind "iso-line" '
                                                r'\(it reads iso_sigma, line_sigma\): remove it$'):
        qdmeta.Algorithm(dict(ME, mutation={"kind": "iso-line", "sigma": 0.3}), task=task)
    with pytest.raises(qdmeta.InputError, match=r"mutation\.rate is not read"):
        qdmeta.Algorithm(dict(ME, mutation={"kind": "iso-line", "rate": 0.5}), task=task)
    # The kind's own keys, and a recorded config's defaults, still build.
    qdmeta.Algorithm(dict(ME, mutation={"kind": "iso-line", "iso_sigma": 0.02, "line_sigma": 0.1}), task=task)
    qdmeta.Algorithm(dict(ME, mutation={"kind": "gaussian", "sigma": 0.1, "step": 0.025, "iso_sigma": 0.01}),
                     task=task)


def test_a_wrong_argument_type_is_named_with_the_types():
    with pytest.raises(TypeError, match=r"^GridArchive\(\): solution_dim must be int, got str; it takes "
                                        r"\(solution_dim, dims, "):
        qdmeta.GridArchive(solution_dim="x", dims=[4, 4])
    with pytest.raises(TypeError, match=r"^GridArchive\(\): dims must be a list of int, got float"):
        qdmeta.GridArchive(2, 4.0)
    with pytest.raises(TypeError, match=r"^Algorithm\(\): task must be qdmeta\.Task or None, got int"):
        qdmeta.Algorithm(ME, task=3)


def test_tell_gives_runs_hint_for_a_feature_outside_the_unit_range():
    by_hand = qdmeta.Algorithm(ME, task=bad_task())
    x = by_hand.ask()
    with pytest.raises(qdmeta.InputError) as from_tell:
        by_hand.tell(*with_a_bad_feature(x))
    with pytest.raises(qdmeta.InputError) as from_run:
        qdmeta.Algorithm(ME, task=bad_task()).run()
    hint = str(from_run.value).split("outside [0, 1]")[1]
    assert hint.startswith(" (base features are in [0, 1]") and str(from_tell.value).endswith(hint)


def test_qd_meta_without_a_meta_objective_names_the_argument():
    task = qdmeta.Task(lambda x: (np.zeros(len(x)), features_of(x)), genotype_size=4, base_feature_size=2, name="t")
    with pytest.raises(qdmeta.InputError, match=r"task 't' has no meta-fitness yet: pass "
                                                r"meta_objective=qdmeta\.MetaObjective\(f, name=\.\.\.\)$"):
        qdmeta.Algorithm({"algorithm": "qd-meta"}, task=task)


def test_an_archive_refuses_a_non_finite_solution_naming_the_row():
    archive = qdmeta.GridArchive(solution_dim=2, dims=[4, 4])
    for bad in (np.nan, np.inf):
        with pytest.raises(qdmeta.InputError, match=r"^grid archive: row 1 of the batch has solution value 1 = "):
            archive.add(np.array([[0.0, 0.0], [0.0, bad]]), np.ones(2), np.full((2, 2), 0.5))
    assert len(archive) == 0


def test_pybind11_2_and_3_annotations_are_read_alike():
    # pybind11 3 (the pip build) spells the signatures that _arguments reads otherwise than
    # pybind11 2 (Debian's); the messages above must not depend on which built the module.
    from qdmeta._arguments import _plain
    spelled = {
        "typing.SupportsInt | typing.SupportsIndex": "int",
        "typing.SupportsFloat | typing.SupportsIndex": "float",
        "collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex]": "List[int]",
        "qdmeta._qdmeta.Task | None": "Optional[qdmeta._qdmeta.Task]",
        "collections.abc.Sequence[tuple[typing.SupportsFloat | typing.SupportsIndex, typing.SupportsFloat]] | None":
            "Optional[List[tuple[float, float]]]",
    }
    for pybind11_3, pybind11_2 in spelled.items():
        assert _plain(pybind11_3) == pybind11_2
        assert _plain(pybind11_2) == pybind11_2
    assert _plain("object") == "object" and _plain("Dict[str, int]") == "Dict[str, int]"

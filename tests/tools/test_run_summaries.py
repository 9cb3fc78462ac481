"""tools/runs.py and tools/run_summary.py: a run's summary holds what the report reads of it, so
the report from summaries is the report from the run directories, byte for byte (report.md,
data/*.csv, figures/*.png); a summary is kilobytes; a damaged one is one line naming it and the
rule it breaks. The run files mirror qdmeta's writers (run_tables.cpp, summary.cpp,
adaptation.cpp, csv.cpp, run_directory.cpp's config.toml), with values of full precision."""
import csv
import json
import math
import os
import pathlib
import shutil
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import report  # noqa: E402
import run_summary  # noqa: E402
import runs  # noqa: E402

pytestmark = [pytest.mark.filterwarnings("ignore:Mean of empty slice"),
              pytest.mark.filterwarnings("ignore:Degrees of freedom <= 0")]

METRICS = ["evals", "evals_bottom", "evals_meta", "generation", "num_elites", "coverage", "qd_score", "norm_qd_score",
           "obj_max", "obj_mean"]
META = ["meta_generation", "evals", "evals_bottom", "evals_meta", "meta_fitness_best", "meta_fitness_mean",
        "meta_fitness_sd", "generations", "states", "population_num_elites_mean", "population_num_elites_se",
        "population_obj_mean_mean", "population_obj_mean_se", "population_obj_max_mean", "population_obj_max_se",
        "population_qd_score_mean", "population_qd_score_se"]
BUDGET = 30_000
# name, slug, algorithm, meta-fitness kind, control, meta-generations per seed (0: no meta-population)
CONDITIONS = [
    ("QD-Meta Dimension", "qd-meta-dimension", "qd-meta", "dimension", "sarsa", {1: 450, 2: 900, 3: 180}),
    ("QD-Meta (static G)", "qd-meta-static-g", "qd-meta", "translation", "static", {1: 60, 2: 75, 3: 70}),
    ("CVT-MAP-Elites", "cvt-map-elites", "cvt-map-elites", None, None, {}),
]
SEEDS = [1, 2, 3]
CLAIMS = '''
[[claim]]
text = "QD-Meta's maps hold about 500 solutions"
kind = "near"
measure = "population:num_elites"
conditions = ["QD-Meta Dimension", "QD-Meta (static G)"]
value = 500
tolerance = 0.5
budget = 100_000

[[claim]]
text = "QD-Meta's mean meta-fitness reaches ten million"
kind = "near"
measure = "meta:meta_fitness_mean"
conditions = ["QD-Meta Dimension"]
value = 1e7
tolerance = 0.1
budget = 100_000

[[claim]]
text = "CVT-MAP-Elites covers half its cells"
kind = "near"
measure = "final:coverage"
conditions = ["CVT-MAP-Elites"]
value = 0.5
tolerance = 0.1
budget = 100_000

[[claim]]
text = "SARSA's G beats a static G on meta-fitness and the dimension test"
kind = "order"
measure = ["meta:meta_fitness_best", "test:dimension@10"]
groups = [["QD-Meta Dimension"], ["QD-Meta (static G)"]]

[[claim]]
text = "QD-Meta generalises better than CVT-MAP-Elites"
kind = "top"
measure = "generalisation:damage"
conditions = ["QD-Meta Dimension", "CVT-MAP-Elites"]
top = "QD-Meta Dimension"
'''


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


def logged_evals(rng, budget, rows):
    """Evaluation counts as a run logs them: uneven steps, the last at or just past the budget."""
    steps = rng.integers(budget // rows // 2, 3 * budget // rows // 2, size=4 * rows)
    evals = np.cumsum(steps)
    end = int(np.searchsorted(evals, budget))
    return [int(e) for e in evals[: end + 1]]


def write_run(path, seed, algorithm, kind, control, meta_generations, elites, rng):
    path.mkdir(parents=True)
    text = (f'# Resolved configuration of this run: every key in force, defaults included.\nalgorithm = "{algorithm}"\n'
            f'seed = {seed}\n\n[budget]\ncounts = "bottom"\nevaluations = {BUDGET}\n\n[task]\nname = "rastrigin"\n')
    if kind:
        text += (f'\n[control]\nkind = "{control}"\nmax_generations = 10\n\n'
                 f'[meta_fitness]\nkind = "{kind}"\n')
    (path / "config.toml").write_text(text + '\n[provenance]\nconfig_file = "x.toml"\nthreads = 1\n')
    evals = logged_evals(rng, BUDGET, 200)
    growth = np.linspace(0.1, 1.0, len(evals))
    metrics = [[e, e, 7 * e, k, int(elites * g), elites * g / 1e4, 1e5 * g + rng.normal(), g / 3, -4 - rng.random(),
                -90 - 10 * rng.random()] for k, (e, g) in enumerate(zip(evals, growth))]
    write_csv(path / "metrics.csv", METRICS, metrics)
    if meta_generations:
        meta_evals = logged_evals(rng, BUDGET, meta_generations)
        n = len(meta_evals)
        g = rng.integers(1, 11, n) if control == "sarsa" else np.full(n, 5)
        rows = [[k + 1, e, e, 9 * e, 2e6 + 1e3 * k + rng.normal(), 2e6 + 900 * k + rng.normal(), rng.random(), g[k],
                 3 + k // 100, elites * 0.9 + rng.normal(), rng.random(), -95 + rng.normal(), rng.random(),
                 -4.5 + rng.random(), rng.random(), 1e5 + rng.normal(), rng.random()] for k, e in enumerate(meta_evals)]
        write_csv(path / "meta.csv", META, rows)
    x, y = rng.random(elites), rng.random(elites)
    fitness = -100 * ((x - 0.5) ** 2 + (y - 0.5) ** 2) - rng.random(elites)
    write_csv(path / "archive.csv", ["index", "objective", "measures_0", "measures_1", "solution_0", "solution_1"],
              [[i, f, a, b, 0.5, 0.25] for i, (f, a, b) in enumerate(zip(fitness, x, y))])
    for test, length in (("dimension", 100), ("translation", 100 if elites >= 100 else elites)):
        curve = np.maximum.accumulate(-200 + 10 * rng.random(length).cumsum())
        write_csv(path / f"adapt-{test}.csv", ["evaluations", "best_mean", "best_se"],
                  [[k + 1, v, 0.5] for k, v in enumerate(curve)])
    write_csv(path / "generalisation.csv", ["group", "environments", "solutions", "mean", "se"],
              [[group, 6, elites, rng.random() + (1 if kind else 0), 0.1] for group in ("damage", "obstacle")])
    last = metrics[-1]
    summary = {"algorithm": algorithm, "task": "rastrigin", "stop_reason": "budget", "message": "", "seed": seed,
               "budget": BUDGET, "budget_counts": "bottom"}
    summary.update({k: v for k, v in zip(METRICS, last) if k != "generation"})
    summary.update({"generations": last[3], "threads": 1, "wall_seconds": 1.0 + rng.random(),
                    "evals_per_second": 1e4 * rng.random()})
    (path / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")


def make_experiment(root):
    """3 conditions x 3 replicates of every file a finished run has, values drawn from one seed."""
    rng = np.random.default_rng(7)
    spec = ['name = "Synthetic"', "replicates = 3", f"evaluations = {BUDGET}",
            'tests = ["dimension", "translation", "generalisation"]', ""]
    for name, slug, algorithm, kind, control, generations in CONDITIONS:
        spec += ["[[condition]]", f'name = "{name}"', f'slug = "{slug}"', f'config = "{slug}.toml"', ""]
        for seed in SEEDS:
            elites = 60 if (slug, seed) == ("qd-meta-static-g", 2) else 500 + 40 * seed
            write_run(root / slug / f"seed-{seed}", seed, algorithm, kind, control, generations.get(seed, 0), elites,
                      rng)
    (root / "experiment.toml").write_text("\n".join(spec) + CLAIMS)
    return root


def summarise(experiment, kept, which=lambda slug, seed: True):
    """The summaries of the chosen runs, in `kept` beside a copy of experiment.toml."""
    kept.mkdir(parents=True, exist_ok=True)
    shutil.copy(experiment / "experiment.toml", kept / "experiment.toml")
    for _, slug, *_ in CONDITIONS:
        for seed in SEEDS:
            if which(slug, seed):
                run_summary.write_summary(str(experiment / slug / f"seed-{seed}"), str(kept / slug / f"seed-{seed}.json"))


def report_files(directory):
    """{relative path: bytes} of what the report writes."""
    names = ["report.md"] + [f"{d}/{n}" for d in ("data", "figures") for n in sorted(os.listdir(directory / d))]
    return {n: (directory / n).read_bytes() for n in names}


def build_report(directory, out=None):
    args = ["report.py", str(directory), "--quiet", "--supplementary"] + (["--out", str(out)] if out else [])
    assert report.main(args) == 0
    return report_files(out or directory)


@pytest.fixture(scope="module")
def experiment(tmp_path_factory):
    root = make_experiment(tmp_path_factory.mktemp("runs"))
    return root, build_report(root)


def test_a_report_from_summaries_equals_the_report_from_the_run_directories(experiment, tmp_path):
    root, from_runs = experiment
    summarise(root, tmp_path / "kept")
    from_summaries = build_report(tmp_path / "kept", tmp_path / "report")
    assert sorted(from_summaries) == sorted(from_runs)
    assert len([n for n in from_runs if n.startswith("figures/")]) == 7  # S4 and S5 included
    for name, data in from_runs.items():
        assert from_summaries[name] == data, name
    md = from_runs["report.md"].decode()
    # The claims read every family a summary keeps: the meta-population, meta.csv's last row,
    # the test curves, the generalisation means, and (for claims about a larger budget than
    # the runs') meta.csv's and metrics.csv's rows at half the budget.
    assert "| QD-Meta generalises better than CVT-MAP-Elites | QD-Meta Dimension 1." in md
    assert "not testable in this experiment" not in md
    assert md.count("at 15,000") >= 2, md


def test_runs_and_summaries_mix_in_one_report(experiment, tmp_path):
    root, from_runs = experiment
    mixed = tmp_path / "mixed"
    summarise(root, mixed, lambda slug, seed: seed != 2)
    for _, slug, *_ in CONDITIONS:
        shutil.copytree(root / slug / "seed-2", mixed / slug / "seed-2")
    assert build_report(mixed, tmp_path / "report") == from_runs


def test_a_missing_replicate_is_left_out_and_counted(experiment, tmp_path):
    root, _ = experiment
    summarise(root, tmp_path / "kept", lambda slug, seed: seed != 3)
    md = build_report(tmp_path / "kept", tmp_path / "report")["report.md"].decode()
    assert "3 of 9 runs are not finished and are left out: qd-meta-dimension/seed-3, " in md
    assert "| CVT-MAP-Elites | 2 |" in md


def test_the_rows_a_summary_keeps_give_the_curves_on_the_grid_and_at_half_the_budget():
    rng = np.random.default_rng(3)
    for budget in (1000, 12345, 100_000_000):
        evals = np.array(logged_evals(rng, budget, 500), dtype=float)
        values = rng.random(len(evals))
        kept, whole = runs.kept_rows(evals, budget)
        grid = runs.evaluation_grid(budget)
        assert len(kept) <= runs.GRID_POINTS + 1 and kept[-1] == len(evals) - 1
        np.testing.assert_array_equal(runs.on_grid(evals[kept], values[kept], grid), runs.on_grid(evals, values, grid))
        # Kept whole: the last row and the row a claim reads at half the budget.
        half = runs.earlier_evals(budget)
        assert [kept[w] for w in whole] == [runs.row_at(evals, half), len(evals) - 1]
        assert kept[runs.row_at(evals[kept], half)] == runs.row_at(evals, half)
    # The last grid point is the run's end, the others the last row at or before them.
    assert runs.on_grid(np.array([10.0, 60.0, 101.0]), np.array([1.0, 2.0, 3.0]), np.array([0, 50, 100])).tolist()[1:] \
        == [1.0, 3.0]


def test_meta_curves_are_drawn_at_a_power_of_two_stride():
    assert [runs.meta_stride(n) for n in (1, 200, 201, 400, 401, 6000)] == [1, 1, 2, 2, 4, 32]
    assert runs.rounded([2365937.828033713, -4.534912109375]).tolist() == [2365940.0, -4.53491]


def test_the_archive_picture_holds_each_bins_best_fitness():
    archive = {"objective": np.array([0.0, 1.0, 2.0, 3.0, 0.5]), "measures_0": np.array([0.0, 1.0, 0.0, 1.0, 0.99]),
               "measures_1": np.array([0.0, 0.0, 1.0, 1.0, 0.01])}
    picture = runs.archive_picture(archive)
    top, bottom = runs.PICTURE_BINS - 1, 0
    level = {f: runs.PICTURE_ALPHABET[min(int(runs.PICTURE_LEVELS * f / 3.0), runs.PICTURE_LEVELS - 1)]
             for f in (0.0, 1.0, 2.0, 3.0)}
    assert picture["rows"][bottom][0] == level[0.0]
    assert picture["rows"][bottom][top] == level[1.0]  # the better of 1.0 and 0.5 in that bin
    assert picture["rows"][top][0] == level[2.0] and picture["rows"][top][top] == "*"  # the highest level
    assert sum(row.count(".") for row in picture["rows"]) == runs.PICTURE_BINS ** 2 - 4
    assert picture["measures_0"] == [0.0, 1.0] and picture["fitness"] == [0.0, 3.0] and picture["elites"] == 5
    values = runs.picture_values(picture)
    assert values[0, 0] == pytest.approx(0.5 / runs.PICTURE_LEVELS * 3.0)
    assert runs.archive_picture({"objective": np.array([1.0])}) is None  # fewer than 2 measures


def test_a_summary_of_a_long_run_is_kilobytes(tmp_path):
    """A QD-Meta run of 100,000,000 evaluations: 200 rows of metrics, 6,000 meta-generations,
    a 10,000-elite archive (tens of megabytes of run files)."""
    rng = np.random.default_rng(11)
    global BUDGET
    saved, BUDGET = BUDGET, 100_000_000
    try:
        write_run(tmp_path / "run", 1, "qd-meta", "dimension", "sarsa", 6000, 10_000, rng)
    finally:
        BUDGET = saved
    target = tmp_path / "seed-1.json"
    run_summary.write_summary(str(tmp_path / "run"), str(target))
    size = target.stat().st_size
    assert 10_000 < size < 40_000, size
    loaded = runs.RunSummary(str(target))
    assert len(loaded.metrics["evals"]) <= runs.GRID_POINTS
    assert runs.meta_stride(loaded.meta_generations) == 32  # about 6,000 meta-generations
    assert len(loaded.meta_series("meta_fitness_best", 32)) == math.ceil(loaded.meta_generations / 32)


@pytest.mark.parametrize("damage, rule", [
    (lambda s: s.update(version=2), "not a qdmeta run summary of version 1 (format 'qdmeta run summary', version 2)"),
    (lambda s: s.update(extra=1), "unknown key 'extra' (a summary has format, version, summary, config, metrics, "
                                  "meta, adapt, generalisation, picture)"),
    (lambda s: s["metrics"]["rows"]["obj_mean"].pop(), "metrics.rows.obj_mean has 99 values, 100 expected"),
    (lambda s: s["metrics"]["rows"]["evals"].reverse(), "metrics.rows.evals must not decrease"),
    (lambda s: s["metrics"]["whole_at"].pop(),
     "metrics.whole_at must be increasing row positions in [0, 100) ending with the last"),
    (lambda s: s["metrics"]["whole"]["coverage"].append(0.5), "metrics.whole.coverage has 3 values, 2 expected"),
    (lambda s: s["summary"].update(stop_reason="interrupted"),
     "summary.stop_reason must be 'budget': a summary is of a finished run"),
    (lambda s: s["summary"].update(num_elites="many"), "num_elites must be a finite number"),
    (lambda s: s["meta"].update(stride=2), "meta.stride must be 4 for 447 meta-generations"),
    (lambda s: s["meta"]["series"]["generations"].pop(), "meta.series.generations has 111 values, 112 expected"),
    (lambda s: s["meta"]["table"]["whole"].pop("states"), "meta.table.whole has no 'states'"),
    (lambda s: s["adapt"].update(dimension=[1.0, "x"]), "adapt.dimension must be a list of finite numbers"),
    (lambda s: s["picture"]["rows"].__setitem__(3, "?" * 64),
     "picture.rows must be 64 strings of 64 characters of "
     "'0123456789ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz+*.'"),
    (lambda s: s["config"].update(control="sarsa"), "config.control must be an object whose kind is a string"),
])
def test_a_damaged_summary_is_one_line_naming_it_and_the_rule(experiment, tmp_path, capsys, damage, rule):
    root, _ = experiment
    kept = tmp_path / "kept"
    summarise(root, kept)
    target = kept / "qd-meta-dimension" / "seed-1.json"
    data = json.loads(target.read_text())
    # as the rules assume
    assert data["meta"]["meta_generations"] == 447 and len(data["metrics"]["rows"]["evals"]) == 100
    assert len(data["metrics"]["whole_at"]) == 2
    damage(data)
    target.write_text(json.dumps(data))
    assert report.main(["report.py", str(kept), "--quiet"]) == 2
    assert capsys.readouterr().err == f"report.py: error: {target}: {rule}\n"
    assert not (kept / "report.md").exists()


def test_summary_files_that_are_not_json_are_refused(experiment, tmp_path, capsys):
    root, _ = experiment
    kept = tmp_path / "kept"
    summarise(root, kept)
    target = kept / "cvt-map-elites" / "seed-2.json"
    target.write_text(target.read_text().replace('"seed": 2', '"seed": NaN'))
    assert report.main(["report.py", str(kept), "--quiet"]) == 2
    assert capsys.readouterr().err == f"report.py: error: {target}: not valid JSON: NaN is not a JSON number\n"


def test_an_unfinished_run_has_no_summary(experiment, tmp_path, capsys):
    root, _ = experiment
    run = tmp_path / "run"
    shutil.copytree(root / "cvt-map-elites" / "seed-1", run)
    (run / "summary.json").write_text(json.dumps({"stop_reason": "interrupted"}))
    assert run_summary.main(["run_summary.py", str(run), str(tmp_path / "seed-1.json")]) == 2
    assert capsys.readouterr().err == (f"run_summary.py: error: {run}: the run has not finished (its summary.json does "
                                       "not say stop_reason \"budget\"): nothing to summarise yet\n")
    assert not (tmp_path / "seed-1.json").exists()


def test_summary_numbers_read_back_as_the_same_doubles(experiment, tmp_path):
    root, _ = experiment
    summarise(root, tmp_path / "kept")
    loaded = runs.RunSummary(str(tmp_path / "kept" / "qd-meta-dimension" / "seed-2.json"))
    direct = runs.RunDirectory(str(root / "qd-meta-dimension" / "seed-2"), loaded.summary)
    assert loaded.mean_generations == direct.mean_generations
    assert loaded.meta["meta_fitness_sd"][-1] == direct.meta["meta_fitness_sd"][-1]
    assert not math.isnan(loaded.metrics["obj_mean"][-1])
    assert loaded.metrics["obj_mean"][-1] == direct.metrics["obj_mean"][-1]

"""tools/report.py on a RHex-like experiment: Table 2 (generalisation, mean ± SD, bold best,
underlined trained groups), recovery curves continued with their last value (Fig 7), and the
supplementary figures S4 and S5 (the paper's numbering: S4 meta-fitness, S5 the G schedule). The run files mirror qdmeta's writers (run_tables.cpp,
summary.cpp, adaptation.cpp, csv.cpp, run_directory.cpp's config.toml)."""
import csv
import json
import pathlib
import statistics
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import report  # noqa: E402

# NaN means before the first logged row (the evaluation grid starts at 0) are expected.
pytestmark = [pytest.mark.filterwarnings("ignore:Mean of empty slice"),
              pytest.mark.filterwarnings("ignore:Degrees of freedom <= 0")]

METRICS = ["evals", "evals_bottom", "evals_meta", "generation", "num_elites", "coverage", "qd_score", "norm_qd_score",
           "obj_max", "obj_mean"]
META = ["meta_generation", "evals", "evals_bottom", "evals_meta", "meta_fitness_best", "meta_fitness_mean",
        "meta_fitness_sd", "generations", "states", "population_num_elites_mean", "population_num_elites_se",
        "population_obj_mean_mean", "population_obj_mean_se", "population_obj_max_mean", "population_obj_max_se",
        "population_qd_score_mean", "population_qd_score_se"]
GROUPS = ["damage-training", "obstacle-training", "damage", "obstacle"]
LABELS = ["Training-Damages", "Training-Obstacles", "Test-Damages", "Test-Obstacles"]
BUDGET = 1000

# Each condition's generalisation means per group, replicate 1 and 2: mean = (a + b) / 2 and the
# sample SD = |a - b| / sqrt(2), computed independently below with the statistics module.
GENERALISATION = {
    "QD-Meta Damage": {"damage-training": (7.0, 6.0), "obstacle-training": (3.0, 3.5), "damage": (4.0, 4.4),
                       "obstacle": (3.0, 3.2)},
    "QD-Meta Obstacle": {"damage-training": (7.5, 7.0), "obstacle-training": (4.0, 4.2), "damage": (4.8, 4.6),
                         "obstacle": (4.1, 4.3)},
    "CVT-MAP-Elites": {"damage-training": (4.4, 4.5), "obstacle-training": (2.6, 2.7), "damage": (3.4, 3.5),
                       "obstacle": (2.6, 2.7)},
}


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows(rows)


def config_toml(algorithm, seed, meta_kind=None, control="sarsa"):
    """The parts of a run's resolved config.toml the report reads (the real one holds every key)."""
    text = (f'# Resolved configuration of this run: every key in force, defaults included.\nalgorithm = "{algorithm}"\n'
            f"seed = {seed}\n\n[budget]\ncounts = \"all\"\nevaluations = {BUDGET}\n\n"
            '[task]\nname = "rhex"\nfeatures = "trajectory"\n')
    if meta_kind:
        text += (f'\n[control]\nkind = "{control}"\nmax_generations = 10\n\n'
                 f'[meta_fitness]\ndamage_type_count = 2\nkind = "{meta_kind}"\nsample_fraction = 1.0\n')
    text += '\n[provenance]\nconfig_file = "x.toml"\nqdmeta_version = "0.1.0"\nthreads = 1\n'
    return text


def write_run(path, name, seed, algorithm, meta_kind, adapt_lengths, elites, meta_generations=0, control="sarsa"):
    path.mkdir(parents=True)
    (path / "config.toml").write_text(config_toml(algorithm, seed, meta_kind, control))
    rows = [[e, e, 0, e // 100, elites, elites / 4096, 10.0 * e / BUDGET, 0.5, 8.0, 5.0 + seed]
            for e in range(100, BUDGET + 1, 100)]
    write_csv(path / "metrics.csv", METRICS, rows)
    if meta_generations:
        meta = []
        for k in range(1, meta_generations + 1):
            g = 10 - (k % 7) if control == "sarsa" else 5
            meta.append([k, k * BUDGET // meta_generations, k * 50, k * 50, 1.0 + k + seed, 0.5 + k, 0.1, g, 3,
                         elites, 1.0, 5.0, 0.1, 8.0, 0.2, 100.0, 1.0])
        write_csv(path / "meta.csv", META, meta)
    write_csv(path / "archive.csv", ["index", "objective", "measures_0", "measures_1", "solution_0", "solution_1"],
              [[i, 1.0 + i, 0.1 * i, 0.2, 0.5, 0.5] for i in range(elites)])
    summary = {"algorithm": algorithm, "task": "rhex", "stop_reason": "budget", "message": "", "seed": seed,
               "budget": BUDGET, "budget_counts": "all"}
    summary.update(dict(zip(METRICS, rows[-1])))
    summary["generations"] = summary.pop("generation")
    summary.update({"threads": 1, "wall_seconds": 1.5, "evals_per_second": 600.0})
    (path / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    for test, length in adapt_lengths.items():
        curve = adapt_curve(name, seed, test, length)
        write_csv(path / f"adapt-{test}.csv", ["evaluations", "best_mean", "best_se"],
                  [[e + 1, v, 0.1] for e, v in enumerate(curve)])
    write_csv(path / "generalisation.csv", ["group", "environments", "solutions", "mean", "se"],
              [[g, 6, elites, GENERALISATION[name][g][seed - 1], 0.1] for g in GROUPS])


def adapt_curve(name, seed, test, length):
    """A rising best-so-far curve, distinct per run."""
    return [1.0 + seed + 0.1 * len(name) + (0.5 if test == "obstacle" else 0.0) + 0.01 * e for e in range(length)]


CONDITIONS = [  # name, slug, algorithm, meta-fitness kind, control
    ("QD-Meta Damage", "qd-meta-damage", "qd-meta", "damage", "sarsa"),
    ("QD-Meta Obstacle", "qd-meta-obstacle", "qd-meta", "obstacle", "static"),
    ("CVT-MAP-Elites", "cvt-map-elites", "cvt-map-elites", None, None),
]


@pytest.fixture
def experiment(tmp_path):
    """3 conditions x 2 replicates; QD-Meta Damage's seed 2 has a 3-solution archive, so its
    recovery curves stop after 3 evaluations (the others run the test's 50)."""
    spec = ['# The experiment in force for the runs below (written by qdmeta experiment; read by qdmeta report).',
            'name = "RHex (synthetic)"', "replicates = 2", f"evaluations = {BUDGET}",
            'tests = [ "damage", "obstacle", "generalisation" ]', ""]
    for name, slug, algorithm, kind, control in CONDITIONS:
        spec += ["[[condition]]", f'name = "{name}"', f'slug = "{slug}"', f'config = "/configs/{slug}.toml"', ""]
        for seed in (1, 2):
            short = name == "QD-Meta Damage" and seed == 2
            length = 3 if short else 50
            write_run(tmp_path / slug / f"seed-{seed}", name, seed, algorithm, kind,
                      {"damage": length, "obstacle": length}, elites=3 if short else 100,
                      meta_generations=(12 if seed == 1 else 9) if kind else 0, control=control or "sarsa")
    (tmp_path / "experiment.toml").write_text("\n".join(spec) + "\n")
    assert report.main(["report.py", str(tmp_path), "--quiet"]) == 0
    return tmp_path


def table2(md):
    """Table 2's rows as {environment label: [cells]} and its header cells."""
    section = md.split("## Generalisation test (Table 2)")[1].split("\n## ")[0]
    lines = [line for line in section.splitlines() if line.startswith("| ")]
    header = [c.strip() for c in lines[0].strip("| ").split(" | ")]
    rows = {}
    for line in lines[1:]:
        cells = [c.strip() for c in line.strip("| ").split(" | ")]
        rows[cells[0]] = cells[1:]
    return header, rows


def test_table2_cells_are_mean_and_sample_sd_with_bold_best_and_underlined_training(experiment):
    md = (experiment / "report.md").read_text()
    header, rows = table2(md)
    names = [c[0] for c in CONDITIONS]
    assert header == ["environment"] + [f"{n} (n=2)" for n in names]
    assert list(rows) == LABELS
    for group, label in zip(GROUPS, LABELS):
        means = [statistics.mean(GENERALISATION[n][group]) for n in names]
        best = int(np.argmax(means))
        for i, (n, cell) in enumerate(zip(names, rows[label])):
            values = GENERALISATION[n][group]
            expected = f"{statistics.mean(values):.4g} ± {statistics.stdev(values):.2g}"
            trained = (n, group) in {("QD-Meta Damage", "damage-training"), ("QD-Meta Obstacle", "obstacle-training")}
            bold = i == best
            assert cell.startswith("<u>") == trained, (label, n, cell)
            inner = cell[3:-4] if trained else cell
            assert inner.startswith("**") == bold, (label, n, cell)
            assert inner.strip("*") == expected, (label, n, cell)
    # The values are chosen so that the bold cells fall on different conditions, and one row's
    # best is a trained cell (both marks) while another row's trained cell is not the best.
    assert rows["Training-Damages"][0] == "<u>6.5 ± 0.71</u>"
    assert rows["Training-Damages"][1] == "**7.25 ± 0.35**"
    assert rows["Training-Obstacles"][1] == "<u>**4.1 ± 0.14**</u>"
    assert rows["Test-Damages"][1] == "**4.7 ± 0.14**"


def test_table2_csv(experiment):
    with open(experiment / "data" / "generalisation.csv", newline="") as f:
        got = list(csv.DictReader(f))
    assert [(r["condition"], r["group"]) for r in got] == [(c[0], g) for c in CONDITIONS for g in GROUPS]
    for r in got:
        values = GENERALISATION[r["condition"]][r["group"]]
        assert int(r["n"]) == 2
        assert float(r["mean"]) == pytest.approx(statistics.mean(values))
        assert float(r["sd"]) == pytest.approx(statistics.stdev(values))
        trained = (r["condition"], r["group"]) in {("QD-Meta Damage", "damage-training"),
                                                   ("QD-Meta Obstacle", "obstacle-training")}
        assert r["trained"] == ("1" if trained else "0")


def test_short_recovery_curve_is_continued_with_its_last_value(experiment):
    with open(experiment / "data" / "curves.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["view"] == "test" and r["condition"] == "QD-Meta Damage"
                and r["statistic"] == "damage"]
    assert [int(r["evals"]) for r in rows] == list(range(1, 51))  # the longest run's length, not the shortest's
    full = adapt_curve("QD-Meta Damage", 1, "damage", 50)
    short = adapt_curve("QD-Meta Damage", 2, "damage", 3)
    for r in rows:
        k = int(r["evals"]) - 1
        expected = (full[k] + (short[k] if k < 3 else short[-1])) / 2
        assert float(r["mean"]) == pytest.approx(expected), r
        assert int(r["n"]) == 2
    md = (experiment / "report.md").read_text()
    damage_table = md.split("**damage** (")[1].split("**obstacle** (")[0]
    assert "continued with its last value" in damage_table
    row = next(line for line in damage_table.splitlines() if line.startswith("| QD-Meta Damage |"))
    end = np.mean([full[-1], short[-1]])
    assert row.endswith(f"| {report.fmt(*report.stat([full[-1], short[-1]]))} (50 evaluations) |")
    assert f"{end:.4g}" in row
    # The figure is there and its caption says the lines are continued.
    figure = md.split("### Test phase: damage")[1].split("###")[0]
    assert "continued with its last value" in figure and "figures/adaptation-damage.png" in figure


def test_generalisation_entry_is_no_curve(experiment):
    md = (experiment / "report.md").read_text()
    assert "**generalisation**" not in md and "Test phase: generalisation" not in md
    assert not (experiment / "figures" / "adaptation-generalisation.png").exists()
    with open(experiment / "data" / "runs.csv", newline="") as f:
        header = next(csv.reader(f))
    assert "test_damage_at_10" in header and not any("generalisation" in h for h in header)


def test_supplementary_figures_s4_and_s5(experiment):
    md = (experiment / "report.md").read_text()
    for name, title in [("meta-fitness-running-average.png", "(Fig S4)"), ("generations-and-meta-fitness.png", "(Fig S5)")]:
        assert (experiment / "figures" / name).stat().st_size > 0
        assert f"figures/{name}" in md and title in md


def test_s5_only_for_sarsa_conditions(experiment):
    _, conditions = report.load(str(experiment))
    by_name = {c["name"]: c["runs"] for c in conditions}
    assert report.controls_generations(by_name["QD-Meta Damage"])
    assert not report.controls_generations(by_name["QD-Meta Obstacle"])  # static: G fixed
    assert report.trained_groups(by_name["CVT-MAP-Elites"]) == set()


def test_continued_curves_pad_with_the_last_value_and_keep_equal_lengths():
    got = report.continued_curves([np.array([1.0, 2.0, 3.0]), np.array([5.0])])
    assert got.tolist() == [[1.0, 2.0, 3.0], [5.0, 5.0, 5.0]]
    same = [np.array([1.0, 2.0]), np.array([3.0, 4.0])]
    assert report.continued_curves(same).tolist() == [[1.0, 2.0], [3.0, 4.0]]


def test_trailing_mean_window():
    assert report.trailing_mean([2.0, 4.0, 6.0, 8.0], 2).tolist() == [2.0, 3.0, 5.0, 7.0]


def test_rastrigin_like_experiment_has_no_rhex_outputs(tmp_path):
    """Without generalisation.csv or a RHex task the report is the generic one: no Table 2, no
    S4/S5, and equal-length recovery curves averaged as before."""
    spec = ['name = "Rastrigin (synthetic)"', "replicates = 2", 'tests = [ "dimension" ]', "",
            "[[condition]]", 'name = "QD-Meta Dimension"', 'slug = "qd-meta-dimension"', 'config = "/c.toml"', ""]
    (tmp_path / "experiment.toml").write_text("\n".join(spec) + "\n")
    for seed in (1, 2):
        path = tmp_path / "qd-meta-dimension" / f"seed-{seed}"
        write_run(path, "QD-Meta Damage", seed, "qd-meta", "dimension", {"dimension": 100}, elites=200,
                  meta_generations=5)
        (path / "generalisation.csv").unlink()
        (path / "config.toml").write_text((path / "config.toml").read_text().replace('"rhex"', '"rastrigin"'))
    assert report.main(["report.py", str(tmp_path), "--quiet"]) == 0
    md = (tmp_path / "report.md").read_text()
    assert "Table 2" not in md and "Fig S4" not in md and "Fig S5" not in md and "continued" not in md
    assert not (tmp_path / "data" / "generalisation.csv").exists()
    assert not (tmp_path / "figures" / "meta-fitness-running-average.png").exists()
    with open(tmp_path / "data" / "curves.csv", newline="") as f:
        rows = [r for r in csv.DictReader(f) if r["view"] == "test"]
    assert len(rows) == 100
    a, b = (adapt_curve("QD-Meta Damage", s, "dimension", 100) for s in (1, 2))
    assert [float(r["mean"]) for r in rows] == pytest.approx([(x + y) / 2 for x, y in zip(a, b)])

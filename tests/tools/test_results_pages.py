"""The results pages (docs/results/*.md) are what their templates make from the committed data
(tools/results_page.py), so a page cannot drift from its data; the committed data (runs.csv) is
what the committed reports printed; and the template language does what its usage says."""
import glob
import os
import pathlib
import re
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import report  # noqa: E402
import results_page  # noqa: E402
from study_data import Study, StudyError  # noqa: E402

RESULTS = ROOT / "docs" / "results"
TEMPLATES = sorted(glob.glob(str(RESULTS / "*.md.in")))
STUDIES = sorted(os.path.dirname(p) for p in glob.glob(str(RESULTS / "**" / "report.md"), recursive=True))


def test_every_results_page_has_a_template():
    pages = sorted(glob.glob(str(RESULTS / "*.md")))
    assert pages and [p + ".in" for p in pages] == TEMPLATES


@pytest.mark.parametrize("template", TEMPLATES, ids=os.path.basename)
def test_each_page_is_what_its_template_makes_from_the_committed_data(template):
    page = pathlib.Path(results_page.page_of(template)).read_text()
    rendered = results_page.render(template)
    if page != rendered:
        diff = [f"line {i}: page {a!r}\n        made {b!r}" for i, (a, b) in
                enumerate(zip(page.splitlines(), rendered.splitlines()), 1) if a != b]
        pytest.fail(f"{os.path.relpath(template, ROOT)} renders differently (run tools/results_page.py "
                    f"{os.path.relpath(template, ROOT)} --write):\n" + "\n".join(diff[:5]))


@pytest.mark.parametrize("directory", STUDIES, ids=lambda d: os.path.relpath(d, RESULTS))
def test_each_committed_runs_csv_holds_what_its_report_printed(directory):
    """The final-archive table of report.md, recomputed from data/runs.csv, and the p of every
    test-phase pairwise row: the page's numbers come from the same data as the report's."""
    study = Study(directory)
    text = pathlib.Path(directory, "report.md").read_text()
    columns = [("num_elites", 5), ("coverage", 3), ("obj_mean", 4), ("obj_max", 4), ("qd_score", 4), ("evals", 9),
               ("wall_seconds", 3)]
    table = text.split("## Final archives", 1)[1].split("\n\n")[2].splitlines()[2:]
    # A report of a study under way lists the conditions without a finished run as n = 0, n/a.
    not_run = [row for row in table if row.split(" | ")[1] == "0"]
    assert all(set(c.strip() for c in row.strip("|").split("|")[2:]) == {"n/a"} for row in not_run)
    table = [row for row in table if row not in not_run]
    assert [row.split(" | ")[0].lstrip("| ") for row in table] == study.conditions
    for row in table:
        cells = [c.strip() for c in row.strip("|").split("|")]
        condition = cells[0]
        assert int(cells[1]) == study.n(condition)
        for (column, digits), cell in zip(columns, cells[2:]):
            assert report.fmt(study.mean(condition, column), study.se(condition, column), digits) == cell, \
                (condition, column)
    checked = 0
    for block in re.findall(r"\*\*Test phase (\w+), after (\d+) evaluations\*\*\n\n(.*?)\n\n", text + "\n\n", re.S):
        test, at, rows = block
        for row in rows.splitlines()[2:]:
            cells = [c.strip() for c in row.strip("|").split("|")]
            measure = f"test:{test}@{at}"
            assert f"{study.u(cells[0], cells[1], measure):g}" == cells[4]
            assert f"{study.holm(cells[0], cells[1], measure):.3g}" == cells[5]
            checked += 1
    assert checked > 0


def write_template(tmp_path, text):
    path = tmp_path / "page.md.in"
    path.write_text(text)
    return str(path)


def test_statements_run_and_expressions_are_formatted(tmp_path, monkeypatch):
    template = write_template(tmp_path, "{% x = 1234.5678 %}\n{% y = [1, 2] %}\n"
                                        "a {{ x }} b {{ x | ,.0f }} c {{ len(y) }} d {{ 'text' }}\n"
                                        "| a | {{ x * 2 | .1f }} |\n")
    lines = results_page.render(template).splitlines()
    assert lines[0].startswith("<!-- Made by tools/results_page.py from ")
    assert lines[1:] == ["a 1235 b 1,235 c 2 d text", "| a | 2469.1 |"]


def test_a_failing_expression_or_assertion_names_the_template_line(tmp_path):
    with pytest.raises(SystemExit, match=r"page.md.in:2: \{\{ 1 / 0 \}\}: ZeroDivisionError"):
        results_page.render(write_template(tmp_path, "fine\n{{ 1 / 0 }}\n"))
    with pytest.raises(SystemExit, match=r"page.md.in:1: assert 1 > 2: AssertionError"):
        results_page.render(write_template(tmp_path, "{% assert 1 > 2 %}\n"))


def test_a_study_refuses_a_measure_or_condition_it_does_not_have():
    study = Study(str(RESULTS / "rastrigin" / "sigma"))
    assert study.budget == 10_000_000 and study.n("AURORA") == 10
    assert study.samples("not a condition", "population:obj_mean") == []
    with pytest.raises(StudyError, match="no values of 'population:obj_mean' for condition 'nope'"):
        study.mean("nope", "population:obj_mean")
    with pytest.raises(StudyError, match="runs.csv has no column 'test_dimension_at_50'"):
        study.mean("AURORA", "test:dimension@50")
    with pytest.raises(StudyError, match="has no column"):
        study.samples("AURORA", "generalisation:damage")


def test_pairs_match_the_same_seed_at_two_budgets():
    small, large = Study(str(RESULTS / "rastrigin" / "5m" / "sigma")), Study(str(RESULTS / "rastrigin" / "sigma"))
    pairs = large.pairs_with(small)("CVT-MAP-Elites", "population:num_elites")
    assert len(pairs) == 10
    by_seed = {r["seed"]: float(r["population_num_elites"]) for r in small.runs if r["condition"] == "CVT-MAP-Elites"}
    first = next(r for r in large.runs if r["condition"] == "CVT-MAP-Elites")
    assert pairs[0] == (float(first["population_num_elites"]), by_seed[first["seed"]])

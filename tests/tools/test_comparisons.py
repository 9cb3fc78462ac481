"""tools/comparisons.py: conditions of two committed studies compared run against run, with Holm's
adjustment over the pairs of a measure deciding the verdict (values checked by hand)."""
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import comparisons  # noqa: E402
from study_data import Study  # noqa: E402


def study(tmp_path, name, runs):
    """A committed report of 1,000 evaluations per run: runs {condition: {column: [value per seed]}}."""
    directory = tmp_path / name
    (directory / "data").mkdir(parents=True)
    (directory / "report.md").write_text("# toy\n\n1 condition x 4 replicates (seeds 1..4), 1,000 evaluations each.\n")
    columns = ["num_elites", "obj_mean", "qd_score"]
    rows = ["condition,seed," + ",".join(columns)]
    for condition, values in runs.items():
        for seed in range(4):
            rows.append(f"{condition},{seed + 1}," + ",".join(str(values[c][seed]) for c in columns))
    (directory / "data" / "runs.csv").write_text("\n".join(rows) + "\n")
    return Study(str(directory))


@pytest.fixture
def sides(tmp_path):
    x = study(tmp_path, "x", {"A": {"num_elites": [5, 6, 7, 8], "obj_mean": [1, 2, 3, 4], "qd_score": [1, 3, 5, 7]}})
    y = study(tmp_path, "y", {"B": {"num_elites": [1, 2, 3, 4], "obj_mean": [5, 6, 7, 8], "qd_score": [2, 4, 6, 8]},
                              "C": {"num_elites": [4.5, 5.5, 6.5, 7.5], "obj_mean": [1, 2, 3, 4],
                                    "qd_score": [1, 3, 5, 7]}})
    return ("A here", x, "A"), ("B there", y, "B"), ("C there", y, "C")


def test_a_pair_counts_across_the_two_studies(sides):
    a, b, c = sides
    r = comparisons.pair(a, b, "final:num_elites")
    # Every A above every B: U = 16 of 16; exactly 1 of the C(8, 4) = 70 arrangements reaches it,
    # so the two-sided p is 2/70.
    assert (r["n1"], r["n2"], r["median1"], r["median2"]) == (4, 4, 6.5, 2.5)
    assert r["u"] == 16 and r["p"] == pytest.approx(2 / 70) and r["a12"] == 1.0
    assert comparisons.pair(a, c, "final:num_elites")["u"] == 1 + 2 + 3 + 4


def test_holm_over_the_pairs_of_a_measure_decides_the_verdict(sides):
    a, b, c = sides
    # Alone, A above B is significant (p = 2/70); beside a second pair, Holm doubles the smallest p
    # to 4/70 > 0.05, and the same data no longer shows a difference.
    alone = comparisons.compared([(a, b)], "final:num_elites")[0]
    assert alone["holm"] == pytest.approx(2 / 70) and alone["verdict"] == "higher"
    both = comparisons.compared([(a, b), (a, c)], "final:num_elites")
    assert both[0]["holm"] == pytest.approx(4 / 70) and both[0]["verdict"] == "no difference shown"
    assert comparisons.compared([(b, a)], "final:num_elites")[0]["verdict"] == "lower"
    assert comparisons.verdict([(a, b), (a, c)], "final:num_elites", a, b) == "no difference shown"
    assert comparisons.verdict([(b, a)], "final:num_elites", b, a) == "lower"


MEASURES = [("size", "final:num_elites"), ("average", "final:obj_mean"), ("QD", "final:qd_score")]


def test_verdicts_group_the_measures_by_direction(sides):
    a, b, c = sides
    assert comparisons.verdicts([(a, b)], MEASURES, a, b) == "higher on size; lower on average; no difference shown on QD"
    assert comparisons.verdicts([(a, b)], MEASURES[:2] + [("worth", "final:num_elites")], a, b) == \
        "higher on size and worth; lower on average"
    assert comparisons.verdicts([(a, b)], [MEASURES[0], ("worth", "final:num_elites")], a, b) == "higher on every measure"
    assert comparisons.verdicts([(a, b)], MEASURES[:1], a, b) == "higher on size"
    with pytest.raises(ValueError, match="C there against B there is not one of the pairs"):
        comparisons.verdicts([(a, b)], MEASURES, c, b)


def test_the_table_has_a_row_per_measure_and_pair_and_stars_what_holm_keeps(sides):
    a, b, c = sides
    lines = comparisons.table([(a, b), (a, c)], MEASURES).splitlines()
    assert len(lines) == 2 + len(MEASURES) * 2
    assert lines[2] == "| size | A here | B there | 4 / 4 | 6.5 | 2.5 | 16 | 0.0571 | 1.00 | no difference shown |"
    alone = comparisons.table([(a, b)], MEASURES).splitlines()
    assert alone[2].endswith("| 16 | 0.0286* | 1.00 | higher |")
    assert alone[3].endswith("| 0 | 0.0286* | 0.00 | lower |")

"""tools/report.py's pairwise tables: Holm over a table's pairs, A12, and the significance mark."""
import pathlib
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import report  # noqa: E402
import significance  # noqa: E402


def rows(table):
    return [line.split(" | ") for line in table.splitlines() if line.startswith("| ") and "---" not in line][1:]


def test_pairs_are_tested_and_adjusted_within_the_table():
    samples = {"A": [10, 11, 12, 13, 14, 15, 16, 17, 18, 19], "B": [0, 1, 2, 3, 4, 5, 6, 7, 8, 9],
               "C": [0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5, 7.5, 8.5, 9.5], "empty": []}
    table = report.comparison_table("Final QD-score", samples)
    assert table.startswith("**Final QD-score**")
    got = rows(table)
    assert [(r[0].strip("| "), r[1]) for r in got] == [("A", "B"), ("A", "C"), ("B", "C")]
    raw = [significance.mann_whitney_u(samples[a], samples[b])[1] for a, b in [("A", "B"), ("A", "C"), ("B", "C")]]
    adjusted = significance.holm(raw)
    for r, p in zip(got, adjusted):
        assert float(r[5]) == pytest.approx(p, rel=1e-2)
    # A beats B and C in every pair (A12 = 1, p tiny: marked); B against C is a coin toss.
    assert got[0][6] == "1.00" and got[0][7].startswith("*")
    assert got[2][7].strip(" |") == ""
    assert 0.4 < float(got[2][6]) < 0.6


def test_no_table_without_two_conditions_with_data():
    assert report.comparison_table("x", {"A": [1, 2], "B": []}) == ""

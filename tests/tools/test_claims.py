"""tools/claims.py: measures read from runs, and each kind's verdicts on hand-made samples."""
import pathlib
import sys

import numpy as np

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import claims  # noqa: E402


class FakeRun:
    def __init__(self, summary, meta=None, adapt=None):
        self.summary = summary
        self.meta = meta or {}
        self.adapt = adapt or {}


def samples_from(table):
    return lambda condition, measure: list(table.get(condition, {}).get(measure, []))


def test_measures_read_the_files_a_run_writes():
    qd_meta = FakeRun({"num_elites": 120, "budget": 1000},
                      meta={"meta_fitness_best": np.array([1.0, 4.0]), "population_num_elites_mean": np.array([50.0, 80.5])},
                      adapt={"dimension": {"best_mean": np.array([-9.0, -5.0, -2.0])}})
    cvt = FakeRun({"num_elites": 300})
    assert claims.measure_values([qd_meta, cvt], "final:num_elites") == [120.0, 300.0]
    # The meta-population view: QD-Meta's mean over its maps; one archive's own size otherwise.
    assert claims.measure_values([qd_meta, cvt], "population:num_elites") == [80.5, 300.0]
    assert claims.measure_values([qd_meta, cvt], "meta:meta_fitness_best") == [4.0]
    assert claims.measure_values([qd_meta], "test:dimension@1") == [-9.0]
    assert claims.measure_values([qd_meta], "test:dimension@100") == [-2.0]  # shorter curve: its last value


def test_generalisation_measures_read_generalisation_csv(tmp_path):
    run = FakeRun({})
    run.path = str(tmp_path)
    (tmp_path / "generalisation.csv").write_text("group,environments,solutions,mean,se\n"
                                                 "damage-training,12,40,4.25,0.5\nobstacle,4,40,2.5,0.25\n")
    other = FakeRun({})
    other.path = str(tmp_path / "missing")  # a run without the test
    assert claims.measure_values([run, other], "generalisation:damage-training") == [4.25]
    assert claims.measure_values([run], "generalisation:obstacle") == [2.5]
    assert claims.measure_values([run], "generalisation:damage") == []


def test_near_and_below_judge_the_mean_and_know_the_budget():
    table = {"A": {"m": [9500, 10400]}, "B": {"m": [6000, 7000]}}
    near = {"text": "about 10,000", "kind": "near", "measure": "m", "conditions": ["A"], "value": 10000,
            "tolerance": 0.1, "budget": 100}
    assert claims.check(near, samples_from(table), 100)[1] == claims.REPRODUCED  # mean 9950
    near["conditions"] = ["A", "B"]
    assert claims.check(near, samples_from(table), 100)[1] == claims.NOT_REPRODUCED  # B: 6500
    assert claims.check(near, samples_from(table), 50)[1] == claims.NOT_AT_BUDGET
    per_condition = dict(near, value={"A": 10000, "B": 6500})
    assert claims.check(per_condition, samples_from(table), 100)[1] == claims.REPRODUCED
    below = {"text": "under 3,000", "kind": "below", "measure": "m", "conditions": ["B"], "value": 7000}
    assert claims.check(below, samples_from(table), None)[1] == claims.REPRODUCED
    below["value"] = 6500  # the mean is not below itself
    measured, verdict = claims.check(below, samples_from(table), None)
    assert verdict == claims.NOT_REPRODUCED
    assert measured == "B 6500 ± 5e+02"


def test_a_growing_measure_past_the_claim_is_not_reproduced_at_any_budget():
    # Archive sizes only grow with evaluations: 9,600 elites at a small budget cannot become
    # "below 3,000" at the paper's; 2,000 against "about 10,000" still could become it.
    table = {"CVT": {"m": [9600, 9700]}, "QD": {"m": [2000, 2100]}}
    below = {"text": "under 3,000", "kind": "below", "measure": "m", "conditions": ["CVT"], "value": 3000,
             "budget": 100, "grows": True}
    assert claims.check(below, samples_from(table), 5)[1] == claims.NOT_REPRODUCED
    assert claims.check(dict(below, grows=False), samples_from(table), 5)[1] == claims.NOT_AT_BUDGET
    near = {"text": "about 10,000", "kind": "near", "measure": "m", "conditions": ["QD"], "value": 10000,
            "tolerance": 0.1, "budget": 100, "grows": True}
    assert claims.check(near, samples_from(table), 5)[1] == claims.NOT_AT_BUDGET
    # Best fitness grows too: -11 is past "about -70" (at most -59.5), -88 is still short of it.
    fitness = {"A": {"m": [-11.0, -12.0]}, "B": {"m": [-88.0, -87.0]}}
    near = {"text": "about -70", "kind": "near", "measure": "m", "conditions": ["B"], "value": -70, "tolerance": 0.15,
            "budget": 100, "grows": True}
    assert claims.check(near, samples_from(fitness), 5)[1] == claims.NOT_AT_BUDGET
    near["conditions"] = ["A", "B"]
    assert claims.check(near, samples_from(fitness), 5)[1] == claims.NOT_REPRODUCED


def test_order_needs_every_pair_ordered_and_significant_after_holm():
    high = list(np.arange(10, 20.0))
    low = list(np.arange(0, 10.0))
    mixed = list(np.arange(0.5, 10.5))
    claim = {"text": "A > B", "kind": "order", "measure": "m", "groups": [["A"], ["B"]]}
    assert claims.check(claim, samples_from({"A": {"m": high}, "B": {"m": low}}), None)[1] == claims.REPRODUCED
    # Ordered by mean but not significant: 0.5 .. 9.5 against 0 .. 9.
    assert claims.check(claim, samples_from({"A": {"m": mixed}, "B": {"m": low}}), None)[1] == claims.NOT_REPRODUCED
    # Reversed.
    assert claims.check(claim, samples_from({"A": {"m": low}, "B": {"m": high}}), None)[1] == claims.NOT_REPRODUCED
    # Two against two: the smallest exact two-sided p is 2 / C(4, 2) = 1/3, never below 0.05.
    two = samples_from({"A": {"m": [5, 6]}, "B": {"m": [1, 2]}})
    assert claims.check(claim, two, None)[1] == claims.TOO_FEW
    # Three groups: A > B > C needs A > B and B > C, each significant, on every measure.
    chain = {"text": "A > B > C", "kind": "order", "measure": ["m", "n"], "groups": [["A"], ["B"], ["C"]]}
    data = {"A": {"m": high, "n": high}, "B": {"m": low, "n": low}, "C": {"m": [x - 20 for x in low], "n": low}}
    assert claims.check(chain, samples_from(data), None)[1] == claims.NOT_REPRODUCED  # B and C tie on n
    data["C"]["n"] = [x - 20 for x in low]
    measured, verdict = claims.check(chain, samples_from(data), None)
    assert verdict == claims.REPRODUCED
    assert "over 4 pairs" in measured


def test_ratio_and_top():
    table = {"one": {"m": [0.9, 1.1]}, "two": {"m": [2.0, 2.0]}, "ten": {"m": [2.5, 1.5]}}
    ratio = {"text": "half", "kind": "ratio", "measure": "m", "numerator": "one", "denominator": ["two", "ten"],
             "value": 0.5, "tolerance": 0.3}
    measured, verdict = claims.check(ratio, samples_from(table), None)
    assert verdict == claims.REPRODUCED and "ratio 0.5" in measured  # 1 / mean(2, 2)
    ratio["value"] = 0.9
    assert claims.check(ratio, samples_from(table), None)[1] == claims.NOT_REPRODUCED
    top = {"text": "two on top", "kind": "top", "measure": "m", "conditions": ["two", "ten"], "top": "two"}
    assert claims.check(top, samples_from(table), None)[1] == claims.NOT_REPRODUCED  # 2.0 against 2.0: a tie
    table["ten"]["m"] = [1.0, 1.0]
    assert claims.check(top, samples_from(table), None)[1] == claims.REPRODUCED


def test_a_condition_without_runs_is_not_testable_here():
    claim = {"text": "x", "kind": "below", "measure": "m", "conditions": ["absent"], "value": 1}
    assert claims.check(claim, samples_from({}), None)[1] == claims.NOT_IN_EXPERIMENT


def test_claims_summary_merges_the_claims_tables_of_several_reports(tmp_path, capsys):
    import claims_summary
    for name, verdict, value in [("small", "not testable at this budget", "9"), ("large", "reproduced", "10")]:
        (tmp_path / name).mkdir()
        (tmp_path / name / "report.md").write_text(
            "# x\n\n| condition | n |\n|---|---|\n| A | 2 |\n\n## The paper's claims\n\ntext\n\n"
            "| claim | measured (mean ± SE over replicates) | verdict |\n|---|---|---|\n"
            f"| about 10 | A {value} ± 0 | **{verdict}** |\n")
    assert claims_summary.main(["x", f"study:5M={tmp_path / 'small'},10M={tmp_path / 'large'}"]) == 0
    lines = capsys.readouterr().out.splitlines()
    assert lines[0] == "| experiment | claim | 5M | 10M | measured (10M) |"
    assert lines[2] == "| study | about 10 | not testable at this budget | **reproduced** | A 10 ± 0 |"

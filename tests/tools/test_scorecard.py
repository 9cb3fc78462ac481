"""tools/scorecard.py: each cell is the claim's verdict on what the study holds, partial studies say
so, and the cause column follows the variants' verdicts."""
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import scorecard  # noqa: E402
from study_data import Study  # noqa: E402

EXPERIMENT = """name = "toy"
replicates = 3

[[condition]]
name = "A"
config = "a.toml"

[[condition]]
name = "B"
config = "b.toml"

[[claim]]
text = "A holds about 100 elites"
kind = "near"
measure = "population:num_elites"
conditions = ["A"]
value = 100
tolerance = 0.1
budget = 1000

[[claim]]
text = "A above B"
kind = "order"
measure = "population:num_elites"
groups = [["A"], ["B"]]
"""


def study(tmp_path, name, elites):
    """A committed report of 1,000 evaluations per run: elites {condition: [value per seed]}."""
    directory = tmp_path / name
    (directory / "data").mkdir(parents=True)
    (directory / "report.md").write_text("# toy\n\n2 conditions x 3 replicates (seeds 1..3), 1,000 evaluations each.\n")
    rows = ["condition,seed,population_num_elites"]
    rows += [f"{c},{seed},{v}" for c, values in elites.items() for seed, v in enumerate(values, 1)]
    (directory / "data" / "runs.csv").write_text("\n".join(rows) + "\n")
    return Study(str(directory))


@pytest.fixture
def experiment(tmp_path):
    path = tmp_path / "experiment.toml"
    path.write_text(EXPERIMENT)
    return str(path)


def test_a_cell_is_the_claims_verdict_on_full_replicates(tmp_path, experiment):
    near = study(tmp_path, "near", {"A": [99, 101, 100], "B": [10, 11, 12]})
    far = study(tmp_path, "far", {"A": [50, 51, 52], "B": [10, 11, 12]})
    assert scorecard.cell(experiment, "A holds about 100 elites", near) == ("reproduced", "reproduced")
    assert scorecard.cell(experiment, "A holds about 100 elites", far) == ("not reproduced", "not reproduced")


def test_a_partial_study_says_how_far_it_got_and_is_not_judged(tmp_path, experiment):
    partial = study(tmp_path, "partial", {"A": [99, 101], "B": [10]})
    assert scorecard.cell(experiment, "A above B", partial)[1] is None
    assert scorecard.cell(experiment, "A holds about 100 elites", partial) == ("reproduced (2 of 3 replicates)", None)
    missing = study(tmp_path, "missing", {"A": [99, 101, 100]})
    assert scorecard.cell(experiment, "A above B", missing) == ("pending (3 of 6 runs)", None)
    assert scorecard.cell(experiment, "A above B", None) == ("not run yet", None)


def test_an_unknown_claim_text_is_refused(experiment):
    with pytest.raises(ValueError, match="0 claims with text 'no such claim'"):
        scorecard.cell(experiment, "no such claim", None)


COLUMNS = [("ours", "setting"), ("stated", "setting"), ("variant 1", "variant"), ("variant 2", "variant")]


def test_the_cause_names_each_other_setting_and_variant_of_a_missed_claim():
    missed = {"ours": "not reproduced", "stated": "reproduced", "variant 1": "reproduced", "variant 2": None}
    assert scorecard.cause(missed, COLUMNS) == "stated: explains it; variant 1: explains it; variant 2: pending"
    assert scorecard.cause(dict(missed, stated="not reproduced", **{"variant 1": "not reproduced"}), COLUMNS) == \
        "stated: does not explain it; variant 1: does not explain it; variant 2: pending"
    # A column the row does not name is left out of the cause.
    assert scorecard.cause({"ours": "not reproduced", "variant 2": "reproduced"}, COLUMNS) == "variant 2: explains it"
    # A claim held at the first setting has no cause to give, whatever the variants say.
    assert scorecard.cause(dict(missed, ours="reproduced"), COLUMNS) == ""


def test_the_table_has_a_dash_where_a_row_names_no_claim(tmp_path, experiment):
    far = study(tmp_path, "far", {"A": [50, 51, 52], "B": [10, 11, 12]})
    near = study(tmp_path, "near", {"A": [99, 101, 100], "B": [10, 11, 12]})
    rows = [("about 100", {"ours": (experiment, "A holds about 100 elites", far),
                           "variant 1": (experiment, "A holds about 100 elites", near)})]
    lines = scorecard.table(rows, COLUMNS).splitlines()
    assert lines[0] == "| claim | ours | stated | variant 1 | variant 2 | cause of a miss |"
    assert lines[2] == "| about 100 | not reproduced | — | reproduced | — | variant 1: explains it |"
    with pytest.raises(ValueError, match="unknown columns: nope"):
        scorecard.table([("x", {"nope": (experiment, "A above B", far)})], COLUMNS)

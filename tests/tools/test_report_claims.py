"""The report's claims: the paper's under their own heading, checks of our own under another, and
a magnitude claim about a larger budget judged on the runs' own curves at half the budget."""
import pathlib
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
from test_report_inputs import make_experiment, report_of  # noqa: E402

pytestmark = [pytest.mark.filterwarnings("ignore:Mean of empty slice"),
              pytest.mark.filterwarnings("ignore:Degrees of freedom <= 0")]

# The run make_experiment writes: 300 evaluations, metrics.csv rows at 100, 200 and 300 with
# 10, 20 and 30 elites.
CLAIMS = '''
[[claim]]
text = "ME holds about 100 elites"
kind = "near"
measure = "population:num_elites"
conditions = ["ME"]
value = 100
tolerance = 0.1
budget = 3000

[[claim]]
text = "ME holds about 1 elite"
kind = "near"
measure = "population:num_elites"
conditions = ["ME"]
value = 1
tolerance = 0.1
budget = 3000

[[claim]]
text = "ME is on top of itself"
kind = "top"
measure = "final:qd_score"
conditions = ["ME"]
top = "ME"
source = "ours"
'''


def test_claims_of_the_paper_and_our_own_under_their_headings_with_the_trend(tmp_path, capsys):
    make_experiment(tmp_path)
    with open(tmp_path / "experiment.toml", "a") as f:
        f.write(CLAIMS)
    assert report_of(tmp_path, capsys) == (0, [])
    md = (tmp_path / "report.md").read_text()
    paper, ours = md.split("## The paper's claims")[1].split("## Our own checks (not in the paper)")
    assert "(300 evaluations each)" in paper
    # 30 elites at 300, 10 at 150 (the row at 100): toward 90 to 110, so not testable yet; away from
    # 0.9 to 1.1, so not reproduced.
    assert "| ME holds about 100 elites | ME 30 ± 0 (allowed: 90 to 110) (at 150: ME 10 ± 0, toward) | " \
           "**not testable at this budget** |" in paper
    assert "| ME holds about 1 elite | ME 30 ± 0 (allowed: 0.9 to 1.1) (at 150: ME 10 ± 0, away) | " \
           "**not reproduced** |" in paper
    assert "ME under a billion" in paper and "ME is on top of itself" not in paper
    assert "| ME is on top of itself | ME 5.5 ± 0 (highest: ME) | **reproduced** |" in ours


def test_a_report_without_checks_of_our_own_has_no_such_heading(tmp_path, capsys):
    make_experiment(tmp_path)
    assert report_of(tmp_path, capsys) == (0, [])
    md = (tmp_path / "report.md").read_text()
    assert "## The paper's claims" in md and "Our own checks" not in md

"""tools/claim_rules.py: the shared cases (tests/data/claims/cases.toml, judged alike by qdmeta
experiment) and every claim of the committed experiment files."""
import pathlib
import re
import sys
import tomllib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
import claim_rules  # noqa: E402

CASES = tomllib.loads((ROOT / "tests/data/claims/cases.toml").read_text())


@pytest.mark.parametrize("case", CASES["case"], ids=lambda c: c["error"] or c["claim"]["text"])
def test_each_shared_case_is_judged_as_its_file_says(case):
    if not case["error"]:
        claim_rules.validate(case["claim"], CASES["conditions"], CASES["tests"])
        return
    with pytest.raises(claim_rules.ClaimError) as refused:
        claim_rules.validate(case["claim"], CASES["conditions"], CASES["tests"])
    assert case["error"] in str(refused.value)


def test_the_cases_cover_every_kind_accepted_and_refused():
    accepted = {c["claim"]["kind"] for c in CASES["case"] if not c["error"]}
    assert accepted == set(claim_rules.KINDS)
    assert sum(1 for c in CASES["case"] if c["error"]) >= 30


def test_every_committed_experiment_files_claims_are_accepted():
    checked = 0
    for path in sorted((ROOT / "configs").rglob("*.toml")):
        spec = tomllib.loads(path.read_text())
        for claim in spec.get("claim", []):
            claim_rules.validate(claim, [c["name"] for c in spec["condition"]], spec.get("tests", []))
            checked += 1
    assert checked >= 30  # 37 now: the check must not pass by finding none


def test_the_meta_measures_are_meta_csvs_columns():
    """meta:<column> names a column of meta.csv as qdmeta writes it (src/qdmeta/run/run_tables.cpp,
    whose list the C++ reader uses directly)."""
    source = (ROOT / "src/qdmeta/run/run_tables.cpp").read_text().split("meta_table()")[1]
    assert re.findall(r'\{"(\w+)", \[\]\(const MetaPoint&', source) == claim_rules.META_COLUMNS


SIZE_TOLERANCE, FITNESS_TOLERANCE = 0.10, 0.15


def test_the_committed_claims_state_one_tolerance_per_kind_of_claim():
    """docs/config.md ("Tolerances in the shipped experiment files"): a number of solutions 10%,
    a fitness, meta-fitness or ratio 15%; a "below" claim of the paper is "just below", with a
    tolerance; a range the paper states is a "between" claim."""
    checked = 0
    for path in sorted((ROOT / "configs").rglob("*.toml")):
        for claim in tomllib.loads(path.read_text()).get("claim", []):
            if claim["kind"] not in ("near", "below", "ratio"):
                continue
            measures = claim["measure"] if isinstance(claim["measure"], list) else [claim["measure"]]
            sizes = [m.endswith(":num_elites") for m in measures]
            assert len(set(sizes)) == 1, (path.name, claim["text"])
            expected = SIZE_TOLERANCE if sizes[0] else FITNESS_TOLERANCE
            assert claim.get("tolerance") == expected, (path.name, claim["text"], claim.get("tolerance"))
            checked += 1
    assert checked >= 15  # 18 now

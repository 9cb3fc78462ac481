"""The report's replicates: a finished run that lacks a part of what a table reads is left out
of that table and named, in report.md and on stderr; runs of one condition made from different
configs (their config fingerprints differ) are refused, never pooled."""
import json
import shutil

import pytest

import test_run_summaries as synthetic  # noqa: E402  (the 3 x 3 synthetic experiment, its runs and summaries)
from test_run_summaries import report  # noqa: E402

pytestmark = [pytest.mark.filterwarnings("ignore:Mean of empty slice"),
              pytest.mark.filterwarnings("ignore:Degrees of freedom <= 0")]


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    return synthetic.make_experiment(tmp_path_factory.mktemp("runs"))


def copy(runs, tmp_path):
    shutil.copytree(runs, tmp_path / "e")
    return tmp_path / "e"


def report_of(directory, capsys):
    status = report.main(["report.py", str(directory), "--quiet"])
    return status, capsys.readouterr().err.splitlines()


def test_a_test_curve_cut_to_its_header_is_a_replicate_left_out_and_named(runs, tmp_path, capsys):
    e = copy(runs, tmp_path)
    adapt = e / "cvt-map-elites" / "seed-2" / "adapt-dimension.csv"
    adapt.write_text(adapt.read_text().split("\n", 1)[0] + "\n")
    status, err = report_of(e, capsys)
    assert (status, err) == (0, [f"report.py: warning: CVT-MAP-Elites seed 2 is left out where it lacks data: {adapt}: "
                                 "only its header, no row"])
    md = (e / "report.md").read_text()
    assert ("1 times a finished run lacks what a table or figure reads, and that table or figure leaves its replicate "
            "out (n counts the others):\n\n- CVT-MAP-Elites, seed 2: cvt-map-elites/seed-2/adapt-dimension.csv: only "
            "its header, no row\n") in md
    dimension = md[md.index("**dimension**"):md.index("**translation**")]
    assert "| CVT-MAP-Elites | 2 |" in dimension


@pytest.mark.parametrize("key, value, why", [
    ("adapt", {}, "its adapt holds no curve of test 'dimension'"),
    ("meta", None, "its meta is null"),
])
def test_a_summary_without_a_part_is_a_replicate_left_out_and_named(runs, tmp_path, capsys, key, value, why):
    kept = tmp_path / "kept"
    synthetic.summarise(runs, kept)
    summary = kept / "qd-meta-dimension" / "seed-1.json"
    data = json.loads(summary.read_text())
    data[key] = value
    summary.write_text(json.dumps(data))
    status, err = report_of(kept, capsys)
    assert status == 0
    assert f"report.py: warning: QD-Meta Dimension seed 1 is left out where it lacks data: {summary}: {why}" in err
    assert f"- QD-Meta Dimension, seed 1: qd-meta-dimension/seed-1.json: {why}\n" in (kept / "report.md").read_text()


def fingerprint(run, value):
    summary = json.loads((run / "summary.json").read_text())
    summary["config_fingerprint"] = value
    (run / "summary.json").write_text(json.dumps(summary))


def test_runs_of_one_condition_made_from_different_configs_are_refused(runs, tmp_path, capsys):
    e = copy(runs, tmp_path)
    fingerprint(e / "cvt-map-elites" / "seed-1", "00ff00ff00ff00ff")
    fingerprint(e / "cvt-map-elites" / "seed-3", "1234abcd1234abcd")
    assert report_of(e, capsys) == (2, [
        f"report.py: error: condition 'CVT-MAP-Elites': runs {e / 'cvt-map-elites' / 'seed-1'} and "
        f"{e / 'cvt-map-elites' / 'seed-3'} were made from different configs (config_fingerprint 00ff00ff00ff00ff and "
        "1234abcd1234abcd): a condition pools the runs of one config; run the other again, or remove it"])
    assert not (e / "report.md").exists()


def test_runs_of_one_config_and_runs_made_before_fingerprints_pool(runs, tmp_path, capsys):
    e = copy(runs, tmp_path)
    fingerprint(e / "cvt-map-elites" / "seed-1", "00ff00ff00ff00ff")
    fingerprint(e / "cvt-map-elites" / "seed-3", "00ff00ff00ff00ff")  # seed 2: legacy, none
    assert report_of(e, capsys) == (0, [])


def test_a_summary_keeps_its_runs_fingerprint_and_the_report_compares_it(runs, tmp_path, capsys):
    e = copy(runs, tmp_path)
    fingerprint(e / "cvt-map-elites" / "seed-1", "00ff00ff00ff00ff")
    (e / "cvt-map-elites" / "seed-2" / "config.toml").write_text(
        (e / "cvt-map-elites" / "seed-2" / "config.toml").read_text() + 'config_fingerprint = "abc"\n')
    kept = tmp_path / "kept"
    synthetic.summarise(e, kept)
    assert json.loads((kept / "cvt-map-elites" / "seed-1.json").read_text())["config_fingerprint"] == "00ff00ff00ff00ff"
    assert json.loads((kept / "cvt-map-elites" / "seed-2.json").read_text())["config_fingerprint"] == "abc"
    assert "config_fingerprint" not in json.loads((kept / "cvt-map-elites" / "seed-3.json").read_text())
    status, err = report_of(kept, capsys)
    assert status == 2 and err[0].startswith("report.py: error: condition 'CVT-MAP-Elites': runs ")


def test_a_fingerprint_that_is_not_lowercase_hex_is_refused(runs, tmp_path, capsys):
    e = copy(runs, tmp_path)
    fingerprint(e / "cvt-map-elites" / "seed-1", "00FF")
    assert report_of(e, capsys) == (2, [f"report.py: error: {e / 'cvt-map-elites' / 'seed-1'}: config_fingerprint "
                                        "must be a string of lowercase hexadecimal digits"])

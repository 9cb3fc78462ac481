"""tools/report.py on damaged inputs and hostile output folders: a damaged file is one line naming
the file, line and rule with exit status 2, never a traceback; a FIFO or /dev/zero in place of an
input neither hangs the report nor fills its memory; a symbolic link planted where the report
writes is replaced, never written through."""
import json
import os
import pathlib
import resource
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
REPORT = ROOT / "tools" / "report.py"
sys.path.insert(0, str(ROOT / "tools"))
import report  # noqa: E402

pytestmark = [pytest.mark.filterwarnings("ignore:Mean of empty slice"),
              pytest.mark.filterwarnings("ignore:Degrees of freedom <= 0")]

METRICS = "evals,evals_bottom,evals_meta,generation,num_elites,coverage,qd_score,norm_qd_score,obj_max,obj_mean\n"


def make_experiment(root):
    """One condition, one finished replicate: the files qdmeta writes, with their real headers."""
    (root / "experiment.toml").write_text(
        'name = "small"\nreplicates = 1\ntests = ["dimension"]\n[[condition]]\nname = "ME"\nslug = "me"\n'
        'config = "/c.toml"\n[[claim]]\ntext = "ME under a billion"\nkind = "below"\n'
        'measure = "population:num_elites"\nconditions = ["ME"]\nvalue = 1e9\n')
    run = root / "me" / "seed-1"
    run.mkdir(parents=True)
    (run / "config.toml").write_text('algorithm = "map-elites"\nseed = 1\n[budget]\nevaluations = 300\n'
                                     '[task]\nname = "rastrigin"\n')
    (run / "metrics.csv").write_text(METRICS + "".join(f"{e},{e},0,{e // 100},{e // 10},0.1,5.5,0.01,-3.5,-9.25\n"
                                                       for e in (100, 200, 300)))
    (run / "archive.csv").write_text("index,objective,measures_0,measures_1,solution_0,solution_1\n"
                                     + "".join(f"{i},{-i}.5,0.{i},0.5,0.25,0.75\n" for i in range(30)))
    (run / "adapt-dimension.csv").write_text("evaluations,best_mean,best_se\n"
                                             + "".join(f"{k},{-10 + k},0.5\n" for k in range(1, 11)))
    summary = {"algorithm": "map-elites", "task": "rastrigin", "stop_reason": "budget", "message": "", "seed": 1,
               "budget": 300, "budget_counts": "all", "evals": 300, "num_elites": 30, "coverage": 0.1,
               "qd_score": 5.5, "obj_max": -3.5, "obj_mean": -9.25, "wall_seconds": 0.5}
    (run / "summary.json").write_text(json.dumps(summary, indent=2) + "\n")
    return run


def report_of(root, capsys):
    """(exit status, stderr lines) of the report on `root`."""
    status = report.main(["report.py", str(root), "--quiet"])
    return status, capsys.readouterr().err.splitlines()


def test_the_undamaged_experiment_reports(tmp_path, capsys):
    make_experiment(tmp_path)
    assert report_of(tmp_path, capsys) == (0, [])
    assert ("| ME under a billion | ME 30 ± 0 (allowed: below 1,000,000,000) | **reproduced** |"
            in (tmp_path / "report.md").read_text())


def test_an_archive_cut_short_names_the_file_and_line(tmp_path, capsys):
    run = make_experiment(tmp_path)
    text = (run / "archive.csv").read_bytes()
    (run / "archive.csv").write_bytes(text[: len(text) // 2])  # as a full disk leaves it
    status, err = report_of(tmp_path, capsys)
    line = text[: len(text) // 2].count(b"\n") + 1
    assert status == 2
    assert err == [f"report.py: error: {run / 'archive.csv'}:{line}: the last line has no line end: the file was "
                   "cut short"]
    assert not (tmp_path / "report.md").exists()  # nothing written from damaged inputs


def test_a_bad_value_in_metrics_names_the_line_column_and_rule(tmp_path, capsys):
    run = make_experiment(tmp_path)
    lines = (run / "metrics.csv").read_text().splitlines(keepends=True)
    lines[2] = lines[2].replace(",2,20,", ",2,2x,")
    (run / "metrics.csv").write_text("".join(lines))
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'metrics.csv'}:3:5: num_elites '2x' is "
                                               "not a number"])
    lines[2] = METRICS.replace("evals,", "")  # a row of the wrong width
    (run / "metrics.csv").write_text("".join(lines))
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'metrics.csv'}:3: 9 fields, the header "
                                               "has 10"])
    lines[2] = "50,50,0,0,5,0.1,1,0.01,-3,-9\n"  # evals going back
    (run / "metrics.csv").write_text("".join(lines))
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'metrics.csv'}:3:1: evals 50 is below the "
                                               "row before's: evals must not decrease"])


def test_a_damaged_summary_names_the_file_line_and_column(tmp_path, capsys):
    run = make_experiment(tmp_path)
    text = (run / "summary.json").read_text()
    (run / "summary.json").write_text(text.replace('"seed": 1,', '"seed": 1'))
    status, err = report_of(tmp_path, capsys)
    assert status == 2 and len(err) == 1
    assert err[0].startswith(f"report.py: error: {run / 'summary.json'}:7:3: not valid JSON: ")
    (run / "summary.json").write_text(text.replace('"num_elites": 30', '"num_elites": "thirty"'))
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'summary.json'}: num_elites must be a "
                                               "finite number"])


def test_a_damaged_generalisation_table_names_the_line_column_and_rule(tmp_path, capsys):
    run = make_experiment(tmp_path)
    (run / "generalisation.csv").write_text("group,environments,solutions,mean,se\ndamage,6,30,4.5,0.1\n"
                                            "obstacle,6,30,,0.1\n")
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'generalisation.csv'}:3:4: mean '' is not "
                                               "a number"])


def test_a_malformed_claim_in_the_experiment_file_is_one_line(tmp_path, capsys):
    make_experiment(tmp_path)
    spec = (tmp_path / "experiment.toml").read_text()
    (tmp_path / "experiment.toml").write_text(spec.replace('conditions = ["ME"]', 'conditions = ["MAP"]'))
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {tmp_path / 'experiment.toml'}: [[claim]] 1: "
                                               "unknown condition 'MAP' (conditions: ME)"])


def limited_memory():
    resource.setrlimit(resource.RLIMIT_AS, (2 << 30, 2 << 30))


def report_process(root):
    """The report as qdmeta starts it, in its own process: a hang is a timeout, not a stuck suite."""
    return subprocess.run([sys.executable, str(REPORT), str(root), "--quiet"], capture_output=True, text=True,
                          timeout=60, preexec_fn=limited_memory)


@pytest.mark.parametrize("name", ["metrics.csv", "summary.json", "archive.csv", "config.toml"])
def test_a_fifo_in_place_of_an_input_does_not_hang_the_report(tmp_path, name):
    run = make_experiment(tmp_path)
    (run / name).unlink()
    os.mkfifo(run / name)
    done = report_process(tmp_path)
    assert done.returncode == 2
    assert done.stderr == f"report.py: error: {run / name}: a FIFO, not a regular file: a run file must be one\n"


def test_dev_zero_in_place_of_an_input_does_not_fill_the_memory(tmp_path):
    run = make_experiment(tmp_path)
    (run / "archive.csv").unlink()
    (run / "archive.csv").symlink_to("/dev/zero")
    done = report_process(tmp_path)
    assert done.returncode == 2
    assert done.stderr == (f"report.py: error: {run / 'archive.csv'}: a character device, not a regular file: a run "
                           "file must be one\n")


@pytest.mark.parametrize("planted", ["report.md", "report.md.tmp", "data/runs.csv", "data/runs.csv.tmp",
                                     "figures/archives.png", "figures/archives.png.tmp"])
def test_a_link_planted_where_the_report_writes_is_not_followed(tmp_path, capsys, planted):
    experiment = tmp_path / "experiment"
    experiment.mkdir()
    make_experiment(experiment)
    victim = tmp_path / "victim.txt"
    victim.write_text("not the report's to change\n")
    (experiment / planted).parent.mkdir(exist_ok=True)
    (experiment / planted).symlink_to(victim)
    assert report_of(experiment, capsys) == (0, [])
    assert victim.read_text() == "not the report's to change\n"
    target = experiment / planted.removesuffix(".tmp")
    assert target.is_file() and not target.is_symlink() and target.stat().st_size > 100


def test_a_linked_output_folder_is_refused_and_left_alone(tmp_path, capsys):
    experiment = tmp_path / "experiment"
    experiment.mkdir()
    make_experiment(experiment)
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (experiment / "figures").symlink_to(elsewhere)
    status, err = report_of(experiment, capsys)
    assert status == 2 and len(err) == 1
    assert err[0].startswith(f"report.py: error: {experiment / 'figures'}: not a folder the report may write into")
    assert list(elsewhere.iterdir()) == []


# The cells qdmeta's C++ reader refuses (std::from_chars's syntax, archive.csv's rules in
# src/qdmeta/io/csv.cpp), and the counts qdmeta writes as whole numbers: the report refuses them
# too, each with the line, the column and the rule.
META_HEADER = ("meta_generation,evals,evals_bottom,evals_meta,meta_fitness_best,meta_fitness_mean,meta_fitness_sd,"
               "generations,states\n")


@pytest.mark.parametrize("name, before, after, column, rule", [
    ("archive.csv", "\n3,-3.5,", "\n9223372036854775808,-3.5,", 1, "is out of range of a 64-bit integer"),
    ("archive.csv", "\n3,-3.5,", "\n-3,-3.5,", 1, "is negative: a cell index must be >= 0"),
    ("archive.csv", "\n3,-3.5,", "\n3,+3.5,", 2, "is not a number"),
    ("archive.csv", "\n3,-3.5,", "\n3, 3.5,", 2, "is not a number"),
    ("archive.csv", "\n3,-3.5,", "\n3,3_5,", 2, "is not a number"),
    ("archive.csv", "\n3,-3.5,", "\n3,infinity,", 2, "is not finite: every value must be"),
    ("archive.csv", "\n3,-3.5,", "\n3,-1e39,", 2, "is out of range of a 32-bit float"),
    ("archive.csv", "\n3,-3.5,", "\n3,-1e-50,", 2, "is out of range of a 32-bit float"),
    ("archive.csv", "\n3,-3.5,0.3,0.5,0.25,", "\n3,-3.5,0.3,0.5,1.25,", 5,
     "is outside [0, 1], where every gene must lie"),
    ("adapt-dimension.csv", "\n3,-7,", "\n3,-\u0667,", 2, "is not a number"),  # an Arabic-Indic 7
    ("adapt-dimension.csv", "\n3,-7,", "\n0,-7,", 1, "is below 1"),
    ("metrics.csv", "\n200,200,0,2,20,", "\n200,200,0,2,20.5,", 5, "is not a whole number: qdmeta writes this "
                                                                    "column as one"),
    ("meta.csv", "\n2,200,", "\n-1,200,", 1, "is below 1"),
])
def test_a_cell_qdmeta_refuses_the_report_refuses(tmp_path, capsys, name, before, after, column, rule):
    run = make_experiment(tmp_path)
    (run / "meta.csv").write_text(META_HEADER + "".join(f"{k},{100 * k},{100 * k},0,1.5,1.25,0.1,5,1\n"
                                                        for k in (1, 2, 3)))
    assert report_of(tmp_path, capsys) == (0, [])
    text = (run / name).read_text()
    assert before in text
    (run / name).write_text(text.replace(before, after, 1))
    line = text[: text.index(before)].count("\n") + 2
    cell = after.strip("\n").split(",")[column - 1]
    header = text.splitlines()[0].split(",")[column - 1]
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / name}:{line}:{column}: {header} '{cell}' "
                                               f"{rule}"])


@pytest.mark.parametrize("header, rule", [
    ("objective,index,measures_0,measures_1,solution_0,solution_1", "not an archive file (header must start with "
                                                                    "index,objective)"),
    ("index,objective,solution_0,solution_1,measures_0,measures_1", "column 5 ('measures_0') is not measures_*, "
                                                                    "solution_* or base_* in that order"),
])
def test_an_archive_header_qdmeta_refuses_the_report_refuses(tmp_path, capsys, header, rule):
    run = make_experiment(tmp_path)
    lines = (run / "archive.csv").read_text().split("\n", 1)
    (run / "archive.csv").write_text(header + "\n" + lines[1])
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'archive.csv'}:1: {rule}"])


def test_an_archive_of_no_elite_is_refused_as_adapt_refuses_it(tmp_path, capsys):
    run = make_experiment(tmp_path)
    (run / "archive.csv").write_text((run / "archive.csv").read_text().split("\n", 1)[0] + "\n")
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / 'archive.csv'}: the archive holds no elite "
                                               "(only its header): a finished run's archive has one"])


@pytest.mark.parametrize("name", ["archive.csv", "metrics.csv", "config.toml", "adapt-dimension.csv"])
def test_a_lost_file_of_a_finished_run_is_an_error(tmp_path, capsys, name):
    run = make_experiment(tmp_path)
    (run / name).unlink()
    assert report_of(tmp_path, capsys) == (2, [f"report.py: error: {run / name}: no such file, but the run has "
                                               "finished (its summary.json says stop_reason \"budget\"): a finished "
                                               "run's file was lost"])


def test_a_qd_meta_run_without_meta_csv_is_an_error(tmp_path, capsys):
    run = make_experiment(tmp_path)
    (run / "config.toml").write_text((run / "config.toml").read_text().replace("map-elites", "qd-meta"))
    status, err = report_of(tmp_path, capsys)
    assert (status, err) == (2, [f"report.py: error: {run / 'meta.csv'}: no such file, but the run has finished (its "
                                 "summary.json says stop_reason \"budget\"): a finished run's file was lost"])


def test_stored_base_features_are_read_in_minus_one_to_one_as_the_cxx_reader_reads_them():
    """QD-Meta with qd_meta.database_inputs = "authors-2g-1" stores 2g - 1 as base features: an
    archive's base_* columns lie in [-1, 1] (tests/io/csv_test.cpp holds the C++ side)."""
    import experiment_files
    import run_files
    rule = experiment_files.ARCHIVE_RULES["base_"]
    assert run_files._first_bad(["-0.5", "-1", "1"], rule)[1] is None
    assert run_files._first_bad(["0.5", "-1.5"], rule)[1] == (1, "is outside [-1, 1], where every stored base "
                                                                  "feature must lie")
    assert run_files._first_bad(["-0.5"], experiment_files.ARCHIVE_RULES["solution_"])[1] == (
        0, "is outside [0, 1], where every gene must lie")

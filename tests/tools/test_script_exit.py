"""Ctrl-C in the tools scripts qdmeta runs (tools/script_exit.py): one line and exit status 130,
as a shell reports SIGINT, never a traceback; no temporary file is left behind. The signal is
sent by the script to itself at a chosen point, so nothing here depends on timing."""
import pathlib
import subprocess
import sys

import test_report_inputs

TOOLS = pathlib.Path(__file__).resolve().parents[2] / "tools"


def interrupted_at(function, script, args):
    """The script run as qdmeta runs it, sending itself SIGINT when `function` of it is called."""
    code = (f"import os, signal, sys\nsys.path.insert(0, {str(TOOLS)!r})\nsys.argv = [{script!r}] + {args!r}\n"
            f"import script_exit\nscript_exit.before_main({script!r})\nimport {script[:-3]} as s\n"
            f"original = s.{function}\n"
            f"def {function.split('.')[-1]}(*a, **k):\n    os.kill(os.getpid(), signal.SIGINT)\n"
            "    return original(*a, **k)\n"
            f"s.{function} = {function.split('.')[-1]}\nsys.exit(s.main(sys.argv))\n")
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)


def test_ctrl_c_while_the_report_is_drawn_is_one_line_and_exit_130(tmp_path):
    test_report_inputs.make_experiment(tmp_path)
    done = interrupted_at("figure_adaptation", "report.py", [str(tmp_path), "--quiet"])
    assert (done.returncode, done.stderr, done.stdout) == (130, "report.py: interrupted\n", "")
    assert not (tmp_path / "report.md").exists()
    assert not [p for p in tmp_path.rglob("*.tmp")]


def test_ctrl_c_while_a_summary_is_made_is_one_line_and_exit_130(tmp_path):
    run = test_report_inputs.make_experiment(tmp_path)
    done = interrupted_at("runs.summary_of", "run_summary.py", [str(run), str(tmp_path / "kept.json")])
    assert (done.returncode, done.stderr) == (130, "run_summary.py: interrupted\n")
    assert not (tmp_path / "kept.json").exists()


def test_ctrl_c_before_main_is_one_line_and_exit_130():
    code = (f"import os, signal, sys\nsys.path.insert(0, {str(TOOLS)!r})\nimport script_exit\n"
            "script_exit.before_main('report.py')\nos.kill(os.getpid(), signal.SIGINT)\nimport time\ntime.sleep(60)\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert (done.returncode, done.stderr) == (130, "report.py: interrupted\n")

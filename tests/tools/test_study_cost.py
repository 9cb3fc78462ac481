"""bench/mpi/study_cost.py: docs/scaling.md's table of both engines is what the script prints for
the arguments the page names, and the arithmetic holds: a study's core-hours are its runs times one
run's hours on one core (the budget's episodes plus rank 0's serial work), and a study's wall time
is the shorter of its two schedules."""
import pathlib
import shlex
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "bench" / "mpi"))
import scaling_model  # noqa: E402
import study_cost  # noqa: E402

MARK = "<!-- bench/mpi/study_cost.py "


def test_scaling_md_holds_what_the_script_prints():
    lines = (ROOT / "docs" / "scaling.md").read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.startswith(MARK))
    args = shlex.split(lines[at][len(MARK):].removesuffix(" -->"))
    models = [(a.split("=")[0], float(a.split("=")[1])) for a in args]
    made = study_cost.table(models).splitlines()
    assert lines[at + 1:at + 1 + len(made)] == made


def test_one_core_runs_the_budget_and_the_serial_work():
    t_ep = 0.1
    per_run = scaling_model.run_hours(1, t_ep, 20e-6)
    serial = scaling_model.meta_gens * scaling_model.S / 3600
    # One core: every request is its episodes one after another, plus half an episode of tail
    # per request larger than the core count (all 60 requests of a meta-generation).
    tail = scaling_model.meta_gens * 60 * 0.5 * t_ep / 3600
    assert per_run == pytest.approx(scaling_model.budget * t_ep / 3600 + serial + tail)
    assert "| x | 0.1 | " + f"{24 * per_run:,.0f} | {32 * per_run:,.0f} |" in study_cost.table([("x", 0.1)])


def test_a_study_takes_the_shorter_schedule():
    h = lambda p: scaling_model.run_hours(p, 0.2, 20e-6)
    assert study_cost.study_hours(32, 24, 0.2, 20e-6) == pytest.approx(24 * h(32))  # 1 core each is slower
    assert study_cost.study_hours(4000, 24, 0.2, 20e-6) == pytest.approx(h(166))     # side by side
    assert study_cost.study_hours(10, 24, 0.2, 20e-6) == pytest.approx(24 * h(10))

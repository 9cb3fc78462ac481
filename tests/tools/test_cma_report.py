"""docs/results/cma-mae/peers.md against the committed rows it is made from: the page is what
bench/peers/cma_report.py makes of them, and every number on it is recomputed here on its own
(means and standard deviations, U counted pair by pair, A12, the p-values by SciPy where Debian's
python3-scipy is present, the medians and ratios of the timed runs, each run's row)."""
import csv
import itertools
import math
import pathlib
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
PEERS = ROOT / "bench" / "peers"
sys.path.insert(0, str(PEERS))
import cma_report  # noqa: E402

PAGE = (ROOT / "docs" / "results" / "cma-mae" / "peers.md").read_text()
# The page's three tables, apart (a run's row could otherwise look like a summary row).
MEANS = PAGE.split("## QD-score and coverage")[1].split("### Every run")[0]
RUNS = PAGE.split("### Every run")[1].split("## Time per iteration")[0]
TIMES = PAGE.split("## Time per iteration")[1]


def rows(name):
    path = PEERS / name
    if not path.exists():
        return []
    with path.open() as f:
        return list(csv.DictReader(f))


FULL = [r for r in rows("results-cma.csv") if r["iterations"] == "10000"]
TIMING = rows("results-cma-timing.csv")


def page_row(section, *cells):
    """The section's table line whose first cells are `cells`."""
    start = "| " + " | ".join(cells) + " |"
    found = [line for line in section.splitlines() if line.startswith(start)]
    assert len(found) == 1, start
    return found[0]


def sample(data, library, domain, algorithm, column):
    picked = sorted((r for r in data if (r["library"], r["domain"], r["algorithm"]) == (library, domain, algorithm)),
                    key=lambda r: int(r["seed"]))
    return [float(r[column]) for r in picked]


def spread(xs):
    if len(xs) == 1:
        return f"{xs[0]:.2f}"
    m = sum(xs) / len(xs)
    return f"{m:.2f} ± {math.sqrt(sum((x - m) ** 2 for x in xs) / (len(xs) - 1)):.2f}"


def test_the_page_is_what_the_script_makes_of_the_rows():
    assert cma_report.page() == PAGE


CONFIGS = list(itertools.product(["sphere", "arm"], ["cma-me", "cma-mae"]))


@pytest.mark.parametrize("domain,algorithm", CONFIGS)
def test_means_tests_and_the_papers_values(domain, algorithm):
    qd = {lib: sample(FULL, lib, domain, algorithm, "qd_score") for lib in ("qdmeta", "pyribs")}
    cov = {lib: sample(FULL, lib, domain, algorithm, "coverage") for lib in ("qdmeta", "pyribs")}
    for lib in ("qdmeta", "pyribs"):
        line = page_row(MEANS, domain, algorithm, lib, str(len(qd[lib])))
        if qd[lib]:
            assert f"| {spread(qd[lib])} | {spread(cov[lib])} |" in line
    line = page_row(MEANS, domain, algorithm, "qdmeta")
    for x, y in ((qd["qdmeta"], qd["pyribs"]), (cov["qdmeta"], cov["pyribs"])):
        if len(x) < 2 or len(y) < 2:
            assert "n < 2" in line
            continue
        u = sum(1.0 if a > b else 0.5 if a == b else 0.0 for a in x for b in y)
        assert f"U = {u:g}, " in line and f"A12 = {u / (len(x) * len(y)):.2f}" in line
        scipy_stats = pytest.importorskip("scipy.stats")
        p = scipy_stats.mannwhitneyu(x, y, alternative="two-sided").pvalue
        assert f"p = {p:.3g}," in line
    paper = {("sphere", "cma-me"): "36.50 | 42.82", ("sphere", "cma-mae"): "64.86 | 83.31",
             ("arm", "cma-me"): "75.82 | 75.89", ("arm", "cma-mae"): "79.03 | 79.24"}
    assert f"| 20 | {paper[(domain, algorithm)]} |" in page_row(MEANS, domain, algorithm, "the paper (20 trials)")


def test_every_run_has_its_row():
    for r in rows("results-cma.csv"):
        line = page_row(RUNS, r["domain"], r["algorithm"], r["library"], r["seed"], r["iterations"])
        assert (f"| {float(r['qd_score']):.2f} | {float(r['coverage']):.2f} | {float(r['wall_s']):.0f} | "
                f"{float(r['task_s']):.1f} | {float(r['load']):.1f} |") in line


def median(xs):
    xs = sorted(xs)
    mid = len(xs) // 2
    return xs[mid] if len(xs) % 2 else (xs[mid - 1] + xs[mid]) / 2


@pytest.mark.parametrize("domain,algorithm", CONFIGS)
def test_time_per_iteration(domain, algorithm):
    def ms(lib, own):
        picked = [r for r in TIMING if (r["library"], r["domain"], r["algorithm"]) == (lib, domain, algorithm)]
        return 1000 * median([(float(r["wall_s"]) - float(r["task_s"]) if own else float(r["task_s"]))
                              / int(r["iterations"]) for r in picked]) if picked else None
    own = {lib: ms(lib, True) for lib in ("qdmeta", "pyribs")}
    if None in own.values():
        assert f"| {domain} | {algorithm} | " not in TIMES
        return
    task = {lib: ms(lib, False) for lib in ("qdmeta", "pyribs")}
    line = page_row(TIMES, domain, algorithm)
    whole = (own["pyribs"] + task["pyribs"]) / (own["qdmeta"] + task["qdmeta"])
    assert (f"| {own['qdmeta']:.1f} | {own['pyribs']:.1f} | {own['pyribs'] / own['qdmeta']:.1f} | "
            f"{task['qdmeta']:.2f} | {task['pyribs']:.2f} | {whole:.1f} |") in line

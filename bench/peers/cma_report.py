"""Writes docs/results/cma-mae/peers.md from the committed per-seed rows of the CMA-MAE paper's
comparison (results-cma.csv: the full runs; results-cma-timing.csv: the timed short runs):
each domain and algorithm's QD-score and coverage per library beside the paper's reported
values, qdmeta against pyribs by the two-sided Mann-Whitney U test and Vargha-Delaney A12
(tools/significance.py), and each library's own time per iteration with the task's time apart.

    /usr/bin/python3 bench/peers/cma_report.py            # rewrite the page
    /usr/bin/python3 bench/peers/cma_report.py --check    # exit 1 if the page is not what the data make

tests/tools/test_cma_report.py runs --check and recomputes the page's numbers on its own.
"""
import argparse
import csv
import statistics
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import significance  # noqa: E402

RESULTS = HERE / "results-cma.csv"
TIMING = HERE / "results-cma-timing.csv"
PAGE = ROOT / "docs" / "results" / "cma-mae" / "peers.md"
DOMAINS = [("sphere", "linear-projection sphere (100-D)"), ("arm", "planar arm (100 joints)")]
ALGORITHMS = ["cma-me", "cma-mae"]
LIBRARIES = ["qdmeta", "pyribs"]
# The paper's reported means (QD-score, coverage %) at 10,000 iterations over its 20 trials, as
# the authors' repository lists them (github.com/icaros-usc/cma_mae, README.md, "Results": "the
# reported results from the paper"; Fontaine & Nikolaidis 2023, Table 1).
PAPER = {("sphere", "cma-me"): (36.50, 42.82), ("sphere", "cma-mae"): (64.86, 83.31),
         ("arm", "cma-me"): (75.82, 75.89), ("arm", "cma-mae"): (79.03, 79.24)}


def read(path):
    if not path.exists():
        return []
    with path.open() as f:
        return list(csv.DictReader(f))


def values(rows, library, domain, algorithm, column, iterations=None):
    """The column's values over seeds, in seed order."""
    picked = [r for r in rows if (r["library"], r["domain"], r["algorithm"]) == (library, domain, algorithm)
              and (iterations is None or int(r["iterations"]) == iterations)]
    return [float(r[column]) for r in sorted(picked, key=lambda r: int(r["seed"]))]


def mean_sd(xs):
    if not xs:
        return "–"
    if len(xs) == 1:
        return f"{xs[0]:.2f}"
    return f"{statistics.mean(xs):.2f} ± {statistics.stdev(xs):.2f}"


def test_cell(qd, py):
    """'U = .., p = .., A12 = ..' of qdmeta over pyribs, or why not."""
    if len(qd) < 2 or len(py) < 2:
        return "n < 2"
    u, p = significance.mann_whitney_u(qd, py)
    return f"U = {u:g}, p = {p:.3g}, A12 = {significance.a12(qd, py):.2f}"


def quality_section(rows):
    out = ["| domain | algorithm | library | seeds | QD-score | coverage (%) | QD-score: qdmeta vs pyribs | "
           "coverage: qdmeta vs pyribs |", "|---|---|---|---|---|---|---|---|"]
    for domain, _ in DOMAINS:
        for algorithm in ALGORITHMS:
            qd = {lib: values(rows, lib, domain, algorithm, "qd_score", 10_000) for lib in LIBRARIES}
            cov = {lib: values(rows, lib, domain, algorithm, "coverage", 10_000) for lib in LIBRARIES}
            for lib in LIBRARIES:
                tests = [test_cell(qd["qdmeta"], qd["pyribs"]), test_cell(cov["qdmeta"], cov["pyribs"])]
                out.append(f"| {domain} | {algorithm} | {lib} | {len(qd[lib])} | {mean_sd(qd[lib])} | "
                           f"{mean_sd(cov[lib])} | {tests[0] if lib == 'qdmeta' else ''} | "
                           f"{tests[1] if lib == 'qdmeta' else ''} |")
            paper_qd, paper_cov = PAPER[(domain, algorithm)]
            out.append(f"| {domain} | {algorithm} | the paper (20 trials) | 20 | {paper_qd:.2f} | {paper_cov:.2f} | | |")
    return out


def seeds_section(rows):
    out = ["| domain | algorithm | library | seed | iterations | QD-score | coverage (%) | wall (s) | task (s) | "
           "load |", "|---|---|---|---|---|---|---|---|---|---|"]
    key = lambda r: ([d for d, _ in DOMAINS].index(r["domain"]), ALGORITHMS.index(r["algorithm"]),  # noqa: E731
                     int(r["seed"]), LIBRARIES.index(r["library"]))
    for r in sorted(rows, key=key):
        out.append(f"| {r['domain']} | {r['algorithm']} | {r['library']} | {r['seed']} | {r['iterations']} | "
                   f"{float(r['qd_score']):.2f} | {float(r['coverage']):.2f} | {float(r['wall_s']):.0f} | "
                   f"{float(r['task_s']):.1f} | {float(r['load']):.1f} |")
    return out


def per_iteration_ms(rows, library, domain, algorithm, column):
    """Median over the timed runs of (wall - task) or task, in milliseconds per iteration."""
    picked = [r for r in rows if (r["library"], r["domain"], r["algorithm"]) == (library, domain, algorithm)]
    if not picked:
        return None
    if column == "overhead":
        per = [(float(r["wall_s"]) - float(r["task_s"])) / int(r["iterations"]) for r in picked]
    else:
        per = [float(r[column]) / int(r["iterations"]) for r in picked]
    return 1000 * statistics.median(per)


def timing_section(rows):
    out = ["| domain | algorithm | runs per library | qdmeta own (ms/it) | pyribs own (ms/it) | pyribs / qdmeta own | "
           "qdmeta task (ms/it) | pyribs task (ms/it) | whole loop pyribs / qdmeta |", "|---|---|---|---|---|---|---|---|---|"]
    for domain, _ in DOMAINS:
        for algorithm in ALGORITHMS:
            own = {lib: per_iteration_ms(rows, lib, domain, algorithm, "overhead") for lib in LIBRARIES}
            task = {lib: per_iteration_ms(rows, lib, domain, algorithm, "task_s") for lib in LIBRARIES}
            if None in own.values():
                continue
            n = len([r for r in rows if (r["library"], r["domain"], r["algorithm"]) == ("qdmeta", domain, algorithm)])
            whole = (own["pyribs"] + task["pyribs"]) / (own["qdmeta"] + task["qdmeta"])
            out.append(f"| {domain} | {algorithm} | {n} | {own['qdmeta']:.1f} | {own['pyribs']:.1f} | "
                       f"{own['pyribs'] / own['qdmeta']:.1f} | {task['qdmeta']:.2f} | {task['pyribs']:.2f} | "
                       f"{whole:.1f} |")
    return out


def load_range(rows):
    loads = [float(r["load"]) for r in rows]
    return f"{min(loads):.1f} to {max(loads):.1f}" if loads else "–"


def page():
    rows, timing = read(RESULTS), read(TIMING)
    full = [r for r in rows if int(r["iterations"]) == 10_000]
    lines = [
        "# CMA-ME and CMA-MAE: qdmeta against pyribs and the CMA-MAE paper",
        "",
        "Written by `bench/peers/cma_report.py` from `bench/peers/results-cma.csv` and",
        "`bench/peers/results-cma-timing.csv`; `tests/tools/test_cma_report.py` recomputes it. The",
        "setup, the domains and the commands are in [bench/peers/README.md](../../../bench/peers/README.md#cma-me-and-cma-mae).",
        "",
        "Settings (the paper's, as pyribs's `examples/sphere.py` configures them): 15 CMA-ES emitters of",
        "batch 36 from x0 = 0 (sigma0 0.5 on the sphere, 0.1 on the arm), mu selection, basic restarts;",
        "a 100 x 100 grid; 10,000 iterations (5.4 million evaluations). CMA-ME: two-stage improvement",
        "ranking, alpha = 1. CMA-MAE: improvement ranking, alpha = 0.01, threshold_min = 0, a separate",
        "result archive. QD-score as the paper: the result archive's objectives (in [0, 100] on the",
        "sphere; at most 100 on the arm) summed and divided by the 10,000 cells; coverage in percent.",
        "",
        "## QD-score and coverage at 10,000 iterations",
        "",
        f"Runs so far: {len(full)} (per configuration below; the sweep continues from the committed",
        "rows, `cma_peers.py` skips finished ones). Mean ± standard deviation over seeds; the tests are",
        "qdmeta over pyribs, two-sided Mann-Whitney U (exact for small samples without ties) and",
        "Vargha-Delaney A12 (0.5: no difference; above: qdmeta larger). The paper's rows are its",
        "reported means over 20 trials, as the authors' repository lists them (github.com/icaros-usc/",
        "cma_mae, README.md, \"Results\"; Fontaine & Nikolaidis 2023, Table 1): they are the paper's",
        "numbers, not runs of ours.",
        "",
    ] + quality_section(full) + [
        "",
        "### Every run",
        "",
        f"Wall and task seconds are each run's own, one or two runs at a time on a 2-core machine shared with",
        f"other work (1-minute load average at each run's start: {load_range(rows)}); compare speed in",
        "the timed runs below, not here.",
        "",
    ] + seeds_section(rows) + [
        "",
        "## Time per iteration, each library's own and the task's",
        "",
        "Short runs of 300 iterations, one at a time, interleaved (qdmeta, pyribs, ...) in one sitting",
        f"(`results-cma-timing.csv`; load {load_range(timing)} on 2 cores shared with other work, every",
        "run under `nice -n 10`). A library's own time is its loop's wall time less the time in the",
        "task (qdmeta's C++ domain, pyribs's numpy domain), per iteration of 540 evaluations; medians",
        "over the runs.",
        "",
    ] + timing_section(timing) + [""]
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--check", action="store_true")
    args = p.parse_args()
    text = page()
    if args.check:
        if not PAGE.exists() or PAGE.read_text() != text:
            print(f"{PAGE.relative_to(ROOT)} is not what bench/peers/cma_report.py makes from the data: rerun it")
            return 1
        return 0
    PAGE.parent.mkdir(parents=True, exist_ok=True)
    PAGE.write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

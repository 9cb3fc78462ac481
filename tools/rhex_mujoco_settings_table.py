#!/usr/bin/python3
"""The table of MuJoCo's settings against the engine cross-check (docs/fidelity.md, "MuJoCo's
settings against the cross-check"), made from the committed sweep
(docs/results/rhex-engines/mujoco-settings.csv, written by build/bench/rhex_mujoco_settings) and
the cross-check's DART episodes (docs/results/rhex-engines/episodes.csv), so that no number of it
is typed by hand (tests/tools/test_rhex_mujoco_settings_table.py remakes it and compares).

Usage: tools/rhex_mujoco_settings_table.py [SWEEP_CSV]            print the table
       tools/rhex_mujoco_settings_table.py [SWEEP_CSV] --write    replace it in docs/fidelity.md

Per variant and leg model: the mean CPU seconds of an episode (this thread's CPU time, all its
episodes) and its ratio to the faithful variant's; per environment the random controllers' mean
distance (a dead robot's is 0) and deaths, Pearson's r against the faithful variant and against
DART with the same legs (over the controllers both ran), and the mean |distance difference|
against the faithful variant.
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import rhex_engines_table as engines  # noqa: E402  (the cross-check's reader, statistics and paths)

CSV = os.path.join(os.path.dirname(engines.CSV), "mujoco-settings.csv")
DOC = engines.DOC
BEGIN = "<!-- tools/rhex_mujoco_settings_table.py: begin -->"
END = "<!-- tools/rhex_mujoco_settings_table.py: end -->"
FAITHFUL = "faithful"


def read(path):
    """({(variant, legs): {environment: {controller: (distance, dead)}}}, {(variant, legs): [cpu_s]}),
    variants, leg models and environments in the file's order."""
    runs, cpu = {}, {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            key = (row["variant"], row["legs"])
            runs.setdefault(key, {}).setdefault(row["environment"], {})[int(row["controller"])] = (
                float(row["distance"]), int(row["dead"]))
            cpu.setdefault(key, []).append(float(row["cpu_s"]))
    return runs, cpu


def r_text(x, y):
    """Pearson's r to 3 places, or - where either side has no spread (every robot dead)."""
    r = engines.pearson(x, y)
    return "-" if r != r else f"{r:.3f}"


def compared(x, y):
    """Distances of the controllers both ran, in controller order."""
    shared = sorted(set(x) & set(y))
    return [x[i][0] for i in shared], [y[i][0] for i in shared]


def table(path=CSV, crosscheck=engines.CSV):
    runs, cpu = read(path)
    dart = engines.read(crosscheck)
    environments = list(dict.fromkeys(env for by_env in runs.values() for env in by_env))
    out = ["CPU ms per episode (mean; x the faithful variant's), and per environment: mean distance (m; dead = 0) / "
           "deaths; Pearson's r against the faithful variant and against DART with the same legs; mean |distance "
           "difference| against the faithful variant (m):", "",
           "| variant | legs | CPU ms | " + " | ".join(environments) + " |",
           "|---|---|---|" + "---|" * len(environments)]
    for (variant, legs), by_env in runs.items():
        ms = 1000 * sum(cpu[(variant, legs)]) / len(cpu[(variant, legs)])
        base = cpu.get((FAITHFUL, legs))
        ratio = ms / (1000 * sum(base) / len(base)) if base else float("nan")
        cells = []
        for env in environments:
            episodes = by_env.get(env)
            if not episodes:
                cells.append("-")
                continue
            values = list(episodes.values())
            mean = sum(d for d, _ in values) / len(values)
            cell = f"{mean:.3f} / {sum(k for _, k in values)} ({len(values)})"
            faithful = runs.get((FAITHFUL, legs), {}).get(env)
            if faithful and variant != FAITHFUL:
                x, y = compared(episodes, faithful)
                diff = sum(abs(a - b) for a, b in zip(x, y)) / len(x)
                cell += f"; r {r_text(x, y)}"
            else:
                diff = None
            reference = dart.get(env, {}).get(f"dart-{legs}")
            if reference:
                x, y = compared(episodes, reference["random"])
                cell += f"; DART r {r_text(x, y)}"
            if diff is not None:
                cell += f"; \\|d\\| {diff:.3f}"
            cells.append(cell)
        out.append(f"| {variant} | {legs} | {ms:.1f} (x{ratio:.2f}) | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def main(argv):
    path = next((a for a in argv if a != "--write"), CSV)
    text = table(path)
    if "--write" in argv:
        with open(DOC) as f:
            doc = f.read()
        with open(DOC, "w") as f:
            f.write(engines.replaced(doc, text, BEGIN, END))
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

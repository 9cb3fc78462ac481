#!/usr/bin/python3
"""The engine cross-check's tables (docs/fidelity.md, "Cross-check, engine against engine"), made
from the committed episodes (docs/results/rhex-engines/episodes.csv, written by
scripts/rhex-engine-crosscheck.sh), so that no number of the tables is typed by hand
(tests/tools/test_rhex_engines_table.py remakes them and compares).

Usage: tools/rhex_engines_table.py [CSV]            print the tables
       tools/rhex_engines_table.py [CSV] --write    replace them in docs/fidelity.md

Per environment and model: the random controllers' mean distance (a dead robot's is 0), deaths
and the tripod's distance; per environment and pair of models, over the controllers both ran:
Pearson's r and Spearman's rank correlation (ties share their mean rank).
"""
import csv
import math
import os
import sys

TOOLS = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(TOOLS)
sys.path.insert(0, TOOLS)
from significance import _ranks  # noqa: E402  (mid-ranks, the same as the report's tests)

CSV = os.path.join(ROOT, "docs", "results", "rhex-engines", "episodes.csv")
DOC = os.path.join(ROOT, "docs", "fidelity.md")
BEGIN = "<!-- tools/rhex_engines_table.py: begin -->"
END = "<!-- tools/rhex_engines_table.py: end -->"
MODELS = ["dart-rigid", "dart-compliant", "mujoco-rigid", "mujoco-compliant"]
LABELS = {"dart-rigid": "DART rigid", "dart-compliant": "DART compliant", "mujoco-rigid": "MuJoCo rigid",
          "mujoco-compliant": "MuJoCo compliant"}
# The pairs compared: each MuJoCo model against both DART models, and each engine's two leg models.
PAIRS = [("mujoco-rigid", "dart-rigid"), ("mujoco-rigid", "dart-compliant"), ("mujoco-compliant", "dart-compliant"),
         ("mujoco-compliant", "dart-rigid"), ("dart-compliant", "dart-rigid"), ("mujoco-compliant", "mujoco-rigid")]


def pearson(a, b):
    n = len(a)
    ma, mb = sum(a) / n, sum(b) / n
    sab = sum((x - ma) * (y - mb) for x, y in zip(a, b))
    saa = sum((x - ma) ** 2 for x in a)
    sbb = sum((y - mb) ** 2 for y in b)
    return sab / math.sqrt(saa * sbb) if saa > 0 and sbb > 0 else float("nan")


def spearman(a, b):
    return pearson(_ranks(a)[0], _ranks(b)[0])


def read(path):
    """{environment: {model: {"random": {index: (distance, dead)}, "tripod": (distance, dead)}}}, the
    environments in the file's order."""
    episodes = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            model = episodes.setdefault(row["environment"], {}).setdefault(row["model"], {"random": {}})
            value = (float(row["distance"]), int(row["dead"]))
            if row["controller"] == "tripod":
                model["tripod"] = value
            else:
                model["random"][int(row["controller"])] = value
    return episodes


def paired(x, y):
    shared = sorted(set(x["random"]) & set(y["random"]))
    return [x["random"][i][0] for i in shared], [y["random"][i][0] for i in shared]


def tables(path=CSV):
    episodes = read(path)
    present = [m for m in MODELS if any(m in e for e in episodes.values())]
    out = ["Mean distance of the random controllers (m; dead = 0) / deaths / the tripod's distance, "
           "and (n) the controllers run:", "",
           "| environment | " + " | ".join(LABELS[m] for m in present) + " |",
           "|---|" + "---|" * len(present)]
    for env, models in episodes.items():
        cells = []
        for m in present:
            if m not in models:
                cells.append("-")
                continue
            values = list(models[m]["random"].values())
            mean = sum(d for d, _ in values) / len(values)
            tripod = models[m].get("tripod")
            cells.append(f"{mean:.3f} / {sum(k for _, k in values)} / "
                         f"{'-' if tripod is None else format(tripod[0], '.3f')} ({len(values)})")
        out.append(f"| {env} | " + " | ".join(cells) + " |")
    pairs = [p for p in PAIRS if p[0] in present and p[1] in present]
    out += ["", "Pearson's r, Spearman's rank r over the controllers both models ran (n):", "",
            "| environment | " + " | ".join(f"{LABELS[a]} vs {LABELS[b]}" for a, b in pairs) + " |",
            "|---|" + "---|" * len(pairs)]
    for env, models in episodes.items():
        cells = []
        for a, b in pairs:
            if a not in models or b not in models:
                cells.append("-")
                continue
            x, y = paired(models[a], models[b])
            cells.append(f"{pearson(x, y):.3f}, {spearman(x, y):.3f} ({len(x)})")
        out.append(f"| {env} | " + " | ".join(cells) + " |")
    return "\n".join(out) + "\n"


def replaced(doc_text, table_text, begin=BEGIN, end=END):
    head, rest = doc_text.split(begin + "\n", 1)
    _, tail = rest.split(end, 1)
    return head + begin + "\n" + table_text + end + tail


def main(argv):
    path = next((a for a in argv if a != "--write"), CSV)
    text = tables(path)
    if "--write" in argv:
        with open(DOC) as f:
            doc = f.read()
        with open(DOC, "w") as f:
            f.write(replaced(doc, text))
    else:
        sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

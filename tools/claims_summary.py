#!/usr/bin/python3
"""One table of the claims of several reports, for a results page.

Usage: tools/claims_summary.py "EXPERIMENT:LABEL=DIR,LABEL=DIR..." ...

Each argument names an experiment and its reports (DIR/report.md, as `qdmeta report` writes
them), one per label (e.g. a budget); the reports of one experiment must check the same claims.
Prints a Markdown table: experiment, claim, the verdict under each label, and what the last
label's report measured.
"""
import os
import sys


def claims_of(directory):
    """(claim, measured, verdict) rows of a report's claims table."""
    with open(os.path.join(directory, "report.md")) as f:
        text = f.read()
    if "## The paper's claims" not in text:
        raise SystemExit(f"{directory}/report.md has no claims table")
    rows = []
    for line in text.split("## The paper's claims", 1)[1].splitlines():
        if line.startswith("| ") and not line.startswith("| claim |"):
            claim, measured, verdict = [c.strip() for c in line.strip().strip("|").split(" | ")]
            rows.append((claim, measured, verdict.strip("*")))
    return rows


def main(argv):
    if len(argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    experiments = []
    for arg in argv[1:]:
        name, _, reports = arg.partition(":")
        labelled = [r.split("=", 1) for r in reports.split(",")]
        if not name or any(len(r) != 2 for r in labelled):
            raise SystemExit(f"bad argument '{arg}': expected EXPERIMENT:LABEL=DIR,LABEL=DIR...")
        experiments.append((name, labelled))
    labels = [label for label, _ in experiments[0][1]]
    print("| experiment | claim | " + " | ".join(labels) + f" | measured ({labels[-1]}) |")
    print("|---|---|" + "---|" * len(labels) + "---|")
    for name, labelled in experiments:
        tables = [claims_of(d) for _, d in labelled]
        for rows in zip(*tables):
            if len({claim for claim, _, _ in rows}) != 1:
                raise SystemExit(f"{name}: the reports check different claims: {[r[0] for r in rows]}")
            verdicts = [v for _, _, v in rows]
            print(f"| {name} | {rows[0][0]} | " + " | ".join(verdicts[:-1] + [f"**{verdicts[-1]}**"])
                  + f" | {rows[-1][1]} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

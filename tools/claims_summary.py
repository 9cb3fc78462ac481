#!/usr/bin/python3
"""One table of an experiment file's claims checked on committed reports at several budgets, for
a results page.

Usage: tools/claims_summary.py [--source paper|ours] "NAME:EXPERIMENT_FILE:LABEL=DIR,LABEL=DIR..." ...

Each argument names an experiment, the experiment file whose [[claim]] tables are checked (the
claims as they are now), and its committed reports (DIR/report.md and DIR/data/runs.csv, as
`qdmeta report` writes them), one per label, smallest budget first. Every claim is checked with
tools/claims.py on each report's runs.csv; a magnitude claim about a larger budget takes its
trend from the report one label before (the committed smaller budget: runs do not depend on
their budget, so that is the same runs' state there, paired by seed), and has none at the first
label. Prints a
Markdown table: experiment, claim, the verdict under each label, and what the last label's
report measured. --source picks the paper's claims (the default) or the checks of our own.
"""
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import claims  # noqa: E402
from study_data import Study  # noqa: E402


def claims_of(experiment_file, source):
    with open(experiment_file, "rb") as f:
        spec = tomllib.load(f)
    return [c for c in spec.get("claim", []) if c.get("source", "paper") == source]


def claim_of(experiment_file, text):
    """The one claim of the file (the paper's or our own) with this text."""
    matching = [c for source in ("paper", "ours") for c in claims_of(experiment_file, source) if c["text"] == text]
    if len(matching) != 1:
        raise ValueError(f"{experiment_file} has {len(matching)} claims with text '{text}'")
    return matching[0]


def verdicts(claim, studies):
    """[(measured, verdict)] of one claim on each study, each judged with the one before as its
    smaller budget."""
    out = []
    for i, study in enumerate(studies):
        earlier = ((studies[i - 1].budget, studies[i - 1].samples, study.pairs_with(studies[i - 1]))
                   if i > 0 else None)
        out.append(claims.check(claim, study.samples, study.budget, earlier))
    return out


def table(experiments, source="paper"):
    """The Markdown table of [(name, experiment file, [(label, Study)])], "" when no experiment
    has a claim of `source`."""
    labels = [label for label, _ in experiments[0][2]]
    if any([label for label, _ in labelled] != labels for _, _, labelled in experiments):
        raise ValueError("every experiment needs the same labels")
    rows = []
    for name, experiment_file, labelled in experiments:
        for claim in claims_of(experiment_file, source):
            checked = verdicts(claim, [s for _, s in labelled])
            cells = [v for _, v in checked[:-1]] + [f"**{checked[-1][1]}**"]
            rows.append(f"| {name} | {claim['text']} | " + " | ".join(cells) + f" | {checked[-1][0]} |")
    if not rows:
        return ""
    return "\n".join(["| experiment | claim | " + " | ".join(labels) + f" | measured ({labels[-1]}) |",
                      "|---|---|" + "---|" * len(labels) + "---|"] + rows)


def main(argv):
    args = argv[1:]
    source = "paper"
    if args[:1] == ["--source"] and len(args) > 1:
        source, args = args[1], args[2:]
    if not args:
        print(__doc__, file=sys.stderr)
        return 2
    experiments = []
    for arg in args:
        name, file, reports = (arg.split(":", 2) + ["", ""])[:3]
        labelled = [r.split("=", 1) for r in reports.split(",")]
        if not name or not file or any(len(r) != 2 for r in labelled):
            raise SystemExit(f"bad argument '{arg}': expected NAME:EXPERIMENT_FILE:LABEL=DIR,LABEL=DIR...")
        experiments.append((name, file, [(label, Study(d)) for label, d in labelled]))
    print(table(experiments, source))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

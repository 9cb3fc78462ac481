#!/usr/bin/python3
"""The scorecard of a results page: each of the paper's claims, its verdict under each setting
(the authors' effective one, the stated one, each of the authors' variants) and a one-line cause
where another setting or a variant explains a miss, every cell computed from committed reports.

A column is (label, kind): kind "setting" or "variant". A row is (label, {column label:
(experiment file, claim text, Study or None)}); a column the row does not name shows "—". A cell is the claim's verdict (tools/claims.py) on the runs the study has, with
"(k of R replicates)" when a condition of the claim has fewer than the experiment file's R;
"pending (k of R)" when a condition has none yet; "not run yet" when the study has no report.

The cause, from the cells alone: when the first setting's verdict is "not reproduced", each other
column (a setting such as the stated SD, or a variant) whose verdict on its full replicates is
"reproduced" explains the miss, one whose verdict is "not reproduced" does not; one still short of
its replicates is pending.
"""
import os
import sys
import tomllib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import claims  # noqa: E402
import claims_summary  # noqa: E402

DASH = "—"


def _replicates(experiment_file):
    with open(experiment_file, "rb") as f:
        return int(tomllib.load(f).get("replicates", 1))


def _conditions(claim):
    if claim["kind"] == "order":
        return [c for g in claim["groups"] for c in g]
    if claim["kind"] == "ratio":
        return [claim["numerator"]] + list(claim["denominator"])
    return list(claim["conditions"])


def cell(experiment_file, text, study):
    """(shown text, verdict or None when not judged on full replicates) of one claim."""
    claim = claims_summary.claim_of(experiment_file, text)
    replicates = _replicates(experiment_file)
    if study is None:
        return "not run yet", None
    counts = [len(study.samples(c, "seed")) for c in _conditions(claim)]
    if min(counts) == 0:
        return f"pending ({sum(counts)} of {replicates * len(counts)} runs)", None
    verdict = claims_summary.verdicts(claim, [study])[-1][1]
    if min(counts) < replicates:
        return f"{verdict} ({min(counts)} of {replicates} replicates)", None
    return verdict, verdict


def cause(verdicts, columns):
    """The row's cause line from its judged cells ({column label: verdict or None, absent: no claim})."""
    settings = [label for label, kind in columns if kind == "setting" and label in verdicts]
    if not settings or verdicts[settings[0]] != claims.NOT_REPRODUCED:
        return ""
    parts = []
    for label, _ in columns:
        if label == settings[0] or label not in verdicts:
            continue
        verdict = verdicts[label]
        parts.append(f"{label}: " + ("explains it" if verdict == claims.REPRODUCED
                                      else "does not explain it" if verdict == claims.NOT_REPRODUCED
                                      else "pending"))
    return "; ".join(parts)


def table(rows, columns):
    """The Markdown scorecard of rows [(label, {column label: (experiment file, claim text, Study or
    None)})] over columns [(label, kind)]."""
    labels = [label for label, _ in columns]
    for _, cells in rows:
        unknown = set(cells) - set(labels)
        if unknown:
            raise ValueError(f"scorecard row names unknown columns: {', '.join(sorted(unknown))}")
    lines = ["| claim | " + " | ".join(labels) + " | cause of a miss |", "|---|" + "---|" * (len(labels) + 1)]
    for row_label, cells in rows:
        shown, judged = [], {}
        for label in labels:
            if label not in cells:
                shown.append(DASH)
                continue
            text, verdict = cell(*cells[label])
            shown.append(text)
            judged[label] = verdict
        lines.append(f"| {row_label} | " + " | ".join(shown) + f" | {cause(judged, columns) or DASH} |")
    return "\n".join(lines)

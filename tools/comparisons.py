"""Conditions of different committed studies compared run against run, for a results page: the
same task, budget and seeds' numbering, but independent runs, so each pair is an unpaired
two-sided Mann-Whitney test (tools/significance.py) with A12, its p adjusted by Holm's method
over the pairs of its measure, as the report's pairwise tables adjust theirs.

A side is (LABEL, study, CONDITION), a study as tools/study_data.Study reads it; a measure is
named as there (final:qd_score, test:dimension@100, ...). Every measure compared here is one
where higher is better (fitness, test scores, archive size, QD-score).
"""
import significance

ALPHA = significance.ALPHA


def pair(first, second, measure):
    """{n1, n2, median1, median2, u, p, a12} of first's runs against second's on `measure`."""
    (_, s1, c1), (_, s2, c2) = first, second
    x, y = s1.values(c1, measure), s2.values(c2, measure)
    u, p = significance.mann_whitney_u(x, y)
    return {"n1": len(x), "n2": len(y), "median1": s1.median(c1, measure), "median2": s2.median(c2, measure),
            "u": u, "p": p, "a12": significance.a12(x, y)}


def compared(pairs, measure):
    """pair() of each (first, second), with "holm": its p adjusted over these pairs, and
    "verdict": "higher" or "lower" (first against second) where the adjusted p < ALPHA, else
    "no difference shown"."""
    rows = [pair(first, second, measure) for first, second in pairs]
    for row, adjusted in zip(rows, significance.holm([r["p"] for r in rows])):
        row["holm"] = adjusted
        row["verdict"] = ("no difference shown" if adjusted >= ALPHA
                          else "higher" if row["a12"] > 0.5 else "lower")
    return rows


def verdict(pairs, measure, first, second):
    """compared()'s verdict for the pair (first, second), which must be one of `pairs`."""
    if (first, second) not in pairs:
        raise ValueError(f"{first[0]} against {second[0]} is not one of the pairs")
    return compared(pairs, measure)[pairs.index((first, second))]["verdict"]


def verdicts(pairs, measures, first, second):
    """The pair (first, second)'s verdicts over the (label, measure) list, grouped: "higher on A
    and B; lower on C; no difference shown on D" (groups without a measure left out), or "higher
    on every measure" when one verdict holds for all (of two or more)."""
    groups = {}
    for label, measure in measures:
        groups.setdefault(verdict(pairs, measure, first, second), []).append(label)
    if len(groups) == 1 and len(measures) > 1:
        return f"{next(iter(groups))} on every measure"
    return "; ".join(f"{word} on {_joined(groups[word])}" for word in ("higher", "lower", "no difference shown")
                     if word in groups)


def _joined(labels):
    return labels[0] if len(labels) == 1 else ", ".join(labels[:-1]) + " and " + labels[-1]


def table(pairs, measures):
    """A Markdown table: for each (measure label, measure), a row per pair."""
    lines = ["| measure | first | second | n | median first | median second | U | p (Holm) | A12 | first is |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for label, measure in measures:
        for (first, second), r in zip(pairs, compared(pairs, measure)):
            mark = "*" if r["holm"] < ALPHA else ""
            lines.append(f"| {label} | {first[0]} | {second[0]} | {r['n1']} / {r['n2']} | {r['median1']:.4g} | "
                         f"{r['median2']:.4g} | {r['u']:g} | {r['holm']:.3g}{mark} | {r['a12']:.2f} | {r['verdict']} |")
    return "\n".join(lines)

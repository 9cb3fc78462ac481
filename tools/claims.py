"""The [[claim]] tables of an experiment file, checked against its finished runs.

A claim names a measure (or a list of them) and the conditions it is about; the report prints
what was measured and a verdict. Measures, one value per finished replicate:

  final:<key>          summary.json's <key> (for QD-Meta: the best map of the last meta-generation)
  population:<stat>    the last meta-generation's mean over every map of the meta-population
                       (meta.csv population_<stat>_mean, the paper's view of QD-Meta); for an
                       algorithm without a meta-population, summary.json's <stat>
  meta:<column>        meta.csv's last row (e.g. meta:meta_fitness_best)
  test:<test>@<k>      the test phase's best score after k evaluations (or its last, when shorter)
  generalisation:<g>   the generalisation test's mean score in group <g> (generalisation.csv;
                       RHex: damage-training, obstacle-training, damage, obstacle)

Kinds and verdicts:

  near   every condition's mean within `tolerance` (relative) of `value` (a number, or a table
         of condition -> number)
  below  every condition's mean under `value`
  order  `groups` from best to worst: every condition of a group above every condition of the
         next, on every measure, each pair by mean and by a two-sided Mann-Whitney U test
         (p Holm-adjusted over all the claim's pairs) below ALPHA
  ratio  mean(numerator) / mean of the denominators' means within `tolerance` (relative) of `value`
  top    `top` has the highest mean among `conditions` on every measure

"reproduced" when the test holds. A "near" or "below" claim is about magnitudes the paper
measured at its own budget (`budget`): when it fails at a smaller budget the verdict is "not
testable at this budget", unless the claim says `grows = true` (a measure that only rises with
the budget, such as archive size or the best fitness) and some condition's mean is already above
what the claim allows: more evaluations cannot bring it back, so that is "not reproduced". A claim that names a condition with no finished replicate is "not
testable in this experiment"; an "order" claim whose replicates are too few for any p below ALPHA
is "not testable with these replicates".
"""
import math
import os

import numpy as np

import experiment_files
import significance

ALPHA = 0.05
REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
NOT_AT_BUDGET = "not testable at this budget"
NOT_IN_EXPERIMENT = "not testable in this experiment"
TOO_FEW = "not testable with these replicates"


def read_generalisation(run_path):
    """The run's generalisation.csv as {group: mean over the archive's solutions and the group's
    environments}; {} without one. A damaged file is an InputError (experiment_files)."""
    return experiment_files.read_generalisation(os.path.join(run_path, "generalisation.csv"))


def measure_values(runs, measure):
    """One value per run that has the measure."""
    family, _, name = measure.partition(":")
    values = []
    for r in runs:
        if family == "final":
            v = r.summary.get(name)
        elif family == "population":
            column = f"population_{name}_mean"
            v = r.meta[column][-1] if r.meta and column in r.meta else r.summary.get(name)
        elif family == "meta":
            v = r.meta[name][-1] if r.meta and name in r.meta else None
        elif family == "test":
            test, _, at = name.partition("@")
            curve = r.adapt.get(test, {}).get("best_mean")
            v = curve[min(int(at), len(curve)) - 1] if curve is not None and len(curve) else None
        elif family == "generalisation":
            v = read_generalisation(r.path).get(name)
        else:
            raise ValueError(f"unknown measure '{measure}' (families: final, population, meta, test, generalisation)")
        if v is not None:
            values.append(float(v))
    return values


def as_list(x):
    return list(x) if isinstance(x, (list, tuple)) else [x]


def fmt_mean(values):
    if not values:
        return "n/a"
    se = float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else 0.0
    return f"{np.mean(values):.4g} ± {se:.2g}"


def smallest_p(n1, n2):
    """The smallest two-sided exact Mann-Whitney p with these sample sizes: 2 / C(n1 + n2, n1)."""
    return min(1.0, 2.0 / math.comb(n1 + n2, n1))


def check(claim, samples, budget):
    """(what was measured, verdict) for one claim. `samples(condition, measure)` gives the
    replicates' values ([] when the condition is not in the experiment or has no finished run);
    `budget` is the experiment's evaluation budget (None when unknown)."""
    kind = claim["kind"]
    measures = as_list(claim["measure"])
    if kind in ("near", "below", "top"):
        names = list(claim["conditions"])
    elif kind == "order":
        names = [c for g in claim["groups"] for c in g]
    elif kind == "ratio":
        names = [claim["numerator"]] + list(claim["denominator"])
    else:
        raise ValueError(f"claim '{claim['text']}': unknown kind '{kind}' (near, below, order, ratio, top)")
    data = {(c, m): samples(c, m) for c in names for m in measures}
    prefix = (lambda m: f"{m}: ") if len(measures) > 1 else (lambda m: "")
    measured = "; ".join(prefix(m) + ", ".join(f"{c} {fmt_mean(data[c, m])}" for c in names) for m in measures)
    if any(not v for v in data.values()):
        return measured, NOT_IN_EXPERIMENT

    if kind in ("near", "below"):
        def target(c):  # a number, or a table of condition -> number
            return float(claim["value"][c]) if isinstance(claim["value"], dict) else float(claim["value"])

        def upper_limit(c):  # the largest mean the claim allows
            if kind == "below":
                return target(c)
            return target(c) + float(claim["tolerance"]) * abs(target(c))

        def holds(c, m):
            mean = float(np.mean(data[c, m]))
            if kind == "below":
                return mean < upper_limit(c)
            return abs(mean - target(c)) <= float(claim["tolerance"]) * abs(target(c))
        if all(holds(c, m) for c in names for m in measures):
            return measured, REPRODUCED
        overshot = claim.get("grows", False) and any(float(np.mean(data[c, m])) >= upper_limit(c) if kind == "below"
                                                     else float(np.mean(data[c, m])) > upper_limit(c)
                                                     for c in names for m in measures)
        paper_budget = claim.get("budget")
        if not overshot and paper_budget is not None and budget is not None and budget < int(paper_budget):
            return measured, NOT_AT_BUDGET
        return measured, NOT_REPRODUCED

    if kind == "ratio":
        verdicts = []
        parts = []
        for m in measures:
            numerator = float(np.mean(data[claim["numerator"], m]))
            denominator = float(np.mean([np.mean(data[c, m]) for c in claim["denominator"]]))
            ratio = numerator / denominator if denominator != 0 else math.inf
            parts.append(f"ratio {ratio:.3g}")
            target = float(claim["value"])
            verdicts.append(abs(ratio - target) <= float(claim["tolerance"]) * abs(target))
        return measured + " (" + ", ".join(parts) + ")", REPRODUCED if all(verdicts) else NOT_REPRODUCED

    if kind == "top":  # strictly highest: a tie is not a top rank
        def strictly_top(m):
            mean = float(np.mean(data[claim["top"], m]))
            return all(mean > float(np.mean(data[c, m])) for c in names if c != claim["top"])
        winners = [max(names, key=lambda c: float(np.mean(data[c, m]))) for m in measures]
        measured += " (highest: " + ", ".join(winners) + ")"
        return measured, REPRODUCED if all(strictly_top(m) for m in measures) else NOT_REPRODUCED

    # order: every adjacent pair of groups, every member pair, every measure.
    groups = claim["groups"]
    pairs = [(a, b, m) for m in measures for upper, lower in zip(groups, groups[1:]) for a in upper for b in lower]
    tests = [significance.mann_whitney_u(data[a, m], data[b, m]) for a, b, m in pairs]
    adjusted = significance.holm([p for _, p in tests])
    ordered = [float(np.mean(data[a, m])) > float(np.mean(data[b, m])) for a, b, m in pairs]
    worst = max(adjusted)
    measured += f" (largest Holm-adjusted p over {len(pairs)} pair{'s' if len(pairs) > 1 else ''}: {worst:.3g})"
    if all(ordered) and worst < ALPHA:
        return measured, REPRODUCED
    if all(ordered) and max(smallest_p(len(data[a, m]), len(data[b, m])) for a, b, m in pairs) >= ALPHA:
        return measured, TOO_FEW
    return measured, NOT_REPRODUCED

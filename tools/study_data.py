"""A committed report's data (DIR/report.md's budget, DIR/data/runs.csv, curves.csv and
generalisation.csv, as `qdmeta report` writes them), for the results pages and the claims
summary: the numbers a page quotes are computed from these files, never typed in.

A measure is named as in a [[claim]] (tools/claims.py) or by a column of runs.csv:

  population:<stat>   runs.csv population_<stat> (QD-Meta: the mean over its meta-population)
  final:<key>         runs.csv <key> (QD-Meta: the best map)
  meta:<column>       runs.csv <column> (meta_fitness_best, meta_fitness_mean)
  test:<test>@<k>     runs.csv test_<test>_at_<k> (k in 1, 10, 100)
  <column>            any column of runs.csv, e.g. meta_generations or wall_seconds
"""
import csv
import math
import os
import re

import numpy as np

import significance

# The line report.py begins report.md with: "... replicates (seeds 1..R), N evaluations each."
_BUDGET = re.compile(r"\(seeds 1\.\.\d+\), ([\d,]+) evaluations each\.")


class StudyError(ValueError):
    """A committed study lacks what a page asks of it."""


def column_of(measure):
    family, colon, name = measure.partition(":")
    if not colon:
        return measure
    if family == "population":
        return f"population_{name}"
    if family in ("final", "meta"):
        return name
    if family == "test":
        test, _, at = name.partition("@")
        return f"test_{test}_at_{at}"
    raise StudyError(f"measure '{measure}' has no column in runs.csv")


def _read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


class Study:
    """One committed report directory."""

    def __init__(self, directory):
        self.directory = directory
        with open(os.path.join(directory, "report.md")) as f:
            found = _BUDGET.search(f.read(2000))
        if not found:
            raise StudyError(f"{directory}/report.md does not state its evaluations per run")
        self.budget = int(found.group(1).replace(",", ""))
        self.runs = _read_csv(os.path.join(directory, "data", "runs.csv"))
        self.columns = list(self.runs[0]) if self.runs else []
        self.conditions = list(dict.fromkeys(r["condition"] for r in self.runs))
        curves = os.path.join(directory, "data", "curves.csv")
        self.curves = _read_csv(curves) if os.path.exists(curves) else []
        table2 = os.path.join(directory, "data", "generalisation.csv")
        self.generalisation = _read_csv(table2) if os.path.exists(table2) else []

    def __repr__(self):
        return f"Study({self.directory!r})"

    # --- one value per run
    def samples(self, condition, measure):
        """Every finished replicate's value ([] for a condition the study does not have, as the
        claims' samples)."""
        column = column_of(measure)
        if column not in self.columns:
            raise StudyError(f"{self.directory}: runs.csv has no column '{column}' (for '{measure}')")
        return [float(r[column]) for r in self.runs if r["condition"] == condition and r[column] != ""]

    def pairs_with(self, earlier):
        """pairs(condition, measure): [(value here, value in `earlier`)] of the runs (seeds) both
        studies have: the same runs at two budgets, as the claims' trend pairs them."""
        def pairs(condition, measure):
            column = column_of(measure)
            then = {r["seed"]: float(r[column]) for r in earlier.runs
                    if r["condition"] == condition and r.get(column, "") != ""}
            return [(float(r[column]), then[r["seed"]]) for r in self.runs
                    if r["condition"] == condition and r[column] != "" and r["seed"] in then]
        return pairs

    def values(self, condition, measure):
        """As samples, but a condition without values is an error: a page quotes what exists."""
        v = self.samples(condition, measure)
        if not v:
            raise StudyError(f"{self.directory}: no values of '{measure}' for condition '{condition}' "
                             f"(conditions: {', '.join(self.conditions)})")
        return v

    def n(self, condition):
        return len(self.values(condition, "seed"))

    def mean(self, condition, measure):
        return float(np.mean(self.values(condition, measure)))

    def se(self, condition, measure):
        v = self.values(condition, measure)
        return float(np.std(v, ddof=1) / math.sqrt(len(v))) if len(v) > 1 else 0.0

    def median(self, condition, measure):
        return float(np.median(self.values(condition, measure)))

    def min(self, condition, measure):
        return min(self.values(condition, measure))

    def max(self, condition, measure):
        return max(self.values(condition, measure))

    def pm(self, condition, measure, digits=4):
        """"mean ± SE" as the report prints it."""
        return f"{self.mean(condition, measure):.{digits}g} ± {self.se(condition, measure):.2g}"

    # --- pairs of conditions, as the report's pairwise tables
    def u(self, first, second, measure):
        """Mann-Whitney U of `first` over `second` (pairs first > second, ties 1/2)."""
        return significance.u_statistic(self.values(first, measure), self.values(second, measure))

    def p(self, first, second, measure):
        """The two-sided Mann-Whitney p of this one pair, unadjusted."""
        return significance.mann_whitney_u(self.values(first, measure), self.values(second, measure))[1]

    def holm(self, first, second, measure):
        """The pair's p adjusted by Holm's method over every pair of the study's conditions that
        have the measure: the p of the report's pairwise table for that measure."""
        names = [c for c in self.conditions if self.samples(c, measure)]
        pairs = [(a, b) for i, a in enumerate(names) for b in names[i + 1:]]
        tested = significance.pairwise([(self.values(a, measure), self.values(b, measure)) for a, b in pairs])
        for (a, b), (_, p) in zip(pairs, tested):
            if {a, b} == {first, second}:
                return p
        raise StudyError(f"{self.directory}: no pair '{first}', '{second}' on '{measure}'")

    def a12(self, first, second, measure):
        return significance.a12(self.values(first, measure), self.values(second, measure))

    # --- curves.csv and generalisation.csv
    def curve(self, condition, view, statistic, evals):
        """(mean, se) of curves.csv's row for the condition, view ("best map", "meta-population"
        or "test") and statistic at the last grid point at or before `evals`."""
        rows = [r for r in self.curves if r["condition"] == condition and r["view"] == view
                and r["statistic"] == statistic and float(r["evals"]) <= evals]
        if not rows:
            raise StudyError(f"{self.directory}: curves.csv has no {view} {statistic} of '{condition}' by {evals}")
        last = max(rows, key=lambda r: float(r["evals"]))
        return float(last["mean"]), float(last["se"])

    def curve_points(self, condition, view, statistic):
        """[(evals, mean, se)] of curves.csv's rows for the condition, view and statistic, in order,
        without the grid points before the first logged row (NaN)."""
        points = [(float(r["evals"]), float(r["mean"]), float(r["se"])) for r in self.curves
                  if r["condition"] == condition and r["view"] == view and r["statistic"] == statistic]
        points = [p for p in points if not math.isnan(p[1])]
        if not points:
            raise StudyError(f"{self.directory}: curves.csv has no {view} {statistic} of '{condition}'")
        return points

    def table2(self, condition, group):
        """generalisation.csv's row: {"n", "mean", "sd", "trained"}."""
        for r in self.generalisation:
            if r["condition"] == condition and r["group"] == group:
                return {"n": int(r["n"]), "mean": float(r["mean"]),
                        "sd": float(r["sd"]) if r["sd"] else float("nan"), "trained": r["trained"] == "1"}
        raise StudyError(f"{self.directory}: generalisation.csv has no row for '{condition}', '{group}'")

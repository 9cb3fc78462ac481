"""The [[claim]] tables of an experiment file, checked against its finished runs.

A claim names a measure (or a list of them) and the conditions it is about; the report prints
what was measured and a verdict. Measures, one value per finished replicate:

  final:<key>          summary.json's <key> (for QD-Meta: the best map of the last meta-generation)
  population:<stat>    the last meta-generation's mean over every map of the meta-population
                       (meta.csv population_<stat>_mean, the paper's view of QD-Meta); for an
                       algorithm without a meta-population, summary.json's <stat>
  meta:<column>        meta.csv's last row (e.g. meta:meta_fitness_mean, the paper's Fig S1)
  test:<test>@<k>      the test phase's best score after k evaluations (or its last, when shorter)
  generalisation:<g>   the generalisation test's mean score in group <g> (generalisation.csv;
                       RHex: damage-training, obstacle-training, damage, obstacle)

Kinds. The magnitude kinds give each condition a band its mean must lie in:

  near     within `tolerance` (relative) of `value` (a number, or a table of condition -> number):
           [value - tolerance |value|, value + tolerance |value|]
  below    under `value`; with `tolerance`, "just below": [value - tolerance |value|, value)
  between  [low, high], a range the paper states
  ratio    mean(numerator) / mean of the denominators' means within `tolerance` (relative) of `value`

and the comparative kinds:

  order    `groups` from best to worst: every condition of a group above every condition of the
           next, on every measure, each pair by mean and by a two-sided Mann-Whitney U test
           (p Holm-adjusted over all the claim's pairs) below ALPHA
  top      `top` has the strictly highest mean among `conditions` on every measure, and beats the
           runner-up (the best of the other conditions) on each by the same test, p Holm-adjusted
           over the claim's measures below ALPHA: a lead in means alone can be chance

The verdict is about the budget the runs were checked at, one rule both ways: "reproduced" when
the test holds, "not reproduced" when it fails. One exception, for a magnitude claim whose
`budget` (the paper's) is larger than the experiment's: when it fails, each mean outside its
band is compared with its value at a smaller budget (`earlier`: the report takes each run's own
logged curve at half the budget; a results page the committed study at the smaller budget). The
verdict is "not testable at this budget" when every such mean

  - has come closer to its band by more than TREND_SE standard errors of the change (the SE of
    the mean change over the runs measured at both budgets, which are the same runs; when they
    cannot be paired, sqrt(SE_now^2 + SE_then^2)), and
  - at that pace would reach the band by the claim's budget (a straight line through the two
    budgets: optimistic, as QD measures change ever more slowly);

more evaluations may then still bring it there. A mean that moved away, did not move by that
much, moves too slowly or has no earlier value makes the claim "not reproduced". A claim that
names a condition with no finished replicate is "not testable in this experiment"; an "order" or
"top" claim whose replicates are too few for any p below ALPHA is "not testable with these
replicates".
"""
import math

import numpy as np

import significance

ALPHA = significance.ALPHA
REPRODUCED = "reproduced"
NOT_REPRODUCED = "not reproduced"
NOT_AT_BUDGET = "not testable at this budget"
NOT_IN_EXPERIMENT = "not testable in this experiment"
TOO_FEW = "not testable with these replicates"


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
            v = r.generalisation().get(name)
        else:
            raise ValueError(f"unknown measure '{measure}' (families: final, population, meta, test, generalisation)")
        if v is not None:
            values.append(float(v))
    return values


def measure_values_at(runs, measure, evals):
    """The measure's value in each run that logged it at or before `evals` evaluations: the last
    logged row at or before that count of metrics.csv, or of meta.csv for QD-Meta's
    meta-population view and meta columns (the same files measure_values reads the last row
    of). Test and generalisation measures have no curve: []."""
    family, _, name = measure.partition(":")
    values = []
    for r in runs:
        meta, metrics = getattr(r, "meta", None) or {}, getattr(r, "metrics", None) or {}
        if family == "population":
            table, column = ((meta, f"population_{name}_mean") if f"population_{name}_mean" in meta
                             else (metrics, name))
        elif family == "final":
            table, column = metrics, name
        elif family == "meta":
            table, column = meta, name
        else:
            return []
        if column not in table or "evals" not in table:
            continue
        i = int(np.searchsorted(table["evals"], evals, side="right")) - 1
        if i >= 0:
            values.append(float(table[column][i]))
    return values


def as_list(x):
    return list(x) if isinstance(x, (list, tuple)) else [x]


def mean_se(values):
    """Mean and standard error over replicates (SE 0 for one)."""
    se = float(np.std(values, ddof=1) / math.sqrt(len(values))) if len(values) > 1 else 0.0
    return float(np.mean(values)), se


def fmt_mean(values):
    if not values:
        return "n/a"
    mean, se = mean_se(values)
    return f"{mean:.4g} ± {se:.2g}"


def fmt_number(x):
    """A band's bound: 10,000 and 2,700 with separators, -85 and 0.425 as they are."""
    if math.isinf(x):
        return "-inf" if x < 0 else "inf"
    v = float(f"{x:.6g}")
    if v == int(v):
        return f"{int(v):,}"
    return f"{v:,.6g}" if abs(v) >= 1000 else f"{v:.4g}"


def smallest_p(n1, n2):
    """The smallest two-sided exact Mann-Whitney p with these sample sizes: 2 / C(n1 + n2, n1)."""
    return min(1.0, 2.0 / math.comb(n1 + n2, n1))


class Band:
    """The interval a magnitude claim allows: [low, high], or [low, high) for "below"."""

    def __init__(self, low, high, high_included=True):
        self.low, self.high, self.high_included = low, high, high_included

    def holds(self, x):
        return self.low <= x and (x <= self.high if self.high_included else x < self.high)

    def distance(self, x):
        """How far x is outside the band (0 inside, and on an excluded upper bound)."""
        return max(self.low - x, x - self.high, 0.0)

    def __str__(self):
        if math.isinf(self.low):
            return f"below {fmt_number(self.high)}"
        if not self.high_included:
            return f"{fmt_number(self.low)} to under {fmt_number(self.high)}"
        return f"{fmt_number(self.low)} to {fmt_number(self.high)}"


def bands(claim, names):
    """{condition: Band} of a near, below or between claim."""
    def target(c):  # a number, or a table of condition -> number
        return float(claim["value"][c]) if isinstance(claim["value"], dict) else float(claim["value"])

    out = {}
    for c in names:
        if claim["kind"] == "between":
            out[c] = Band(float(claim["low"]), float(claim["high"]))
        elif claim["kind"] == "below":
            t = target(c)
            low = t - float(claim["tolerance"]) * abs(t) if "tolerance" in claim else -math.inf
            out[c] = Band(low, t, high_included=False)
        else:
            t = target(c)
            out[c] = Band(t - float(claim["tolerance"]) * abs(t), t + float(claim["tolerance"]) * abs(t))
    return out


TREND_SE = 2.0
TOWARD, AWAY, LEVEL, SLOW = "toward", "away", "level", "too slow"


def trend(now, then, band, change_se=None):
    """Whether a statistic (mean, se) moved toward `band` since (mean, se) `then`: its distance to
    the band shrank (TOWARD) or grew (AWAY) by more than TREND_SE standard errors of the change,
    else LEVEL. `change_se`: the change's SE from runs paired across the two budgets; without it,
    that of two independent means."""
    change = band.distance(then[0]) - band.distance(now[0])
    margin = TREND_SE * (change_se if change_se is not None else math.hypot(now[1], then[1]))
    return TOWARD if change > margin else AWAY if -change > margin else LEVEL


def paired_se(pairs):
    """The SE of the mean change over runs measured at both budgets ([(now, then)]), None with
    fewer than 2 such runs."""
    if not pairs or len(pairs) < 2:
        return None
    d = [a - b for a, b in pairs]
    return float(np.std(d, ddof=1) / math.sqrt(len(d)))


def ratio_stat(numerator, denominators):
    """mean(numerator) / mean of the denominators' means, and its standard error by the delta
    method (the conditions' replicates independent)."""
    m_n, s_n = mean_se(numerator)
    stats = [mean_se(d) for d in denominators]
    m_d = float(np.mean([m for m, _ in stats]))
    s_d = math.sqrt(sum(s * s for _, s in stats)) / len(stats)
    if m_d == 0:
        return math.inf, 0.0
    ratio = m_n / m_d
    se = abs(ratio) * math.hypot(s_n / m_n if m_n else 0.0, s_d / m_d)
    return ratio, se


def reaches(now, then, band, budgets):
    """Whether the straight line through (earlier budget, then) and (budget, now) meets the band
    by the paper's budget (`budgets`: earlier, now, paper). QD measures change ever more slowly, so
    the straight line is an optimistic extension: one that falls short will not get there."""
    earlier, budget, paper = budgets
    gain = band.distance(then) - band.distance(now)
    return gain * (paper - budget) / (budget - earlier) >= band.distance(now)


def judge_magnitude(claim, failing, budget, earlier):
    """The verdict of a magnitude claim some of whose statistics (`failing`: [(label, band, now
    (mean, se), then(): (mean, se) or None, change_se(): paired SE or None)]) are outside their
    band, and what the trend showed."""
    paper_budget = claim.get("budget")
    if paper_budget is None or budget is None or budget >= int(paper_budget):
        return "", NOT_REPRODUCED
    if earlier is None or not earlier[0] < budget:
        return " no smaller budget to compare with", NOT_REPRODUCED
    budgets = (earlier[0], budget, int(paper_budget))
    notes, moving = [], []
    for label, band, now, then, change_se in failing:
        past = then()
        if past is None:
            notes.append(f"{label}: no value")
            moving.append(LEVEL)
            continue
        moving.append(trend(now, past, band, change_se()))
        note = f"{label} {past[0]:.4g} ± {past[1]:.2g}, {moving[-1]}"
        if moving[-1] == TOWARD and not reaches(now[0], past[0], band, budgets):
            moving[-1] = SLOW
            note += f", too slowly to reach it by {budgets[2]:,}"
        notes.append(note)
    verdict = NOT_AT_BUDGET if all(m == TOWARD for m in moving) else NOT_REPRODUCED
    return f" at {earlier[0]:,}: " + "; ".join(notes), verdict


def check(claim, samples, budget, earlier=None):
    """(what was measured, verdict) for one claim. `samples(condition, measure)` gives the
    replicates' values ([] when the condition is not in the experiment or has no finished run);
    `budget` is the experiment's evaluation budget (None when unknown); `earlier`, for the trend
    of a magnitude claim about a larger budget, is None or (evaluations, samples at that smaller
    budget[, pairs]) with pairs(condition, measure) the [(now, then)] values of the runs measured
    at both budgets (the same runs), or None when they cannot be paired."""
    kind = claim["kind"]
    measures = as_list(claim["measure"])
    if kind in ("near", "below", "between", "top"):
        names = list(claim["conditions"])
    elif kind == "order":
        names = [c for g in claim["groups"] for c in g]
    elif kind == "ratio":
        names = [claim["numerator"]] + list(claim["denominator"])
    else:
        raise ValueError(f"claim '{claim['text']}': unknown kind '{kind}' (near, below, between, order, ratio, top)")
    data = {(c, m): samples(c, m) for c in names for m in measures}
    prefix = (lambda m: f"{m}: ") if len(measures) > 1 else (lambda m: "")
    measured = "; ".join(prefix(m) + ", ".join(f"{c} {fmt_mean(data[c, m])}" for c in names) for m in measures)
    if any(not v for v in data.values()):
        return measured, NOT_IN_EXPERIMENT

    def then_of(c, m):
        def then():
            values = earlier[1](c, m) if earlier else []
            return mean_se(values) if values else None
        return then

    def pairs_of(c, m):
        return earlier[2](c, m) if earlier and len(earlier) > 2 else None

    if kind in ("near", "below", "between"):
        band = bands(claim, names)
        shown = {str(b) for b in band.values()}
        measured += " (allowed: " + (shown.pop() if len(shown) == 1 else
                                     ", ".join(f"{c} {band[c]}" for c in names)) + ")"
        failing = [(prefix(m) + c, band[c], mean_se(data[c, m]), then_of(c, m),
                    lambda c=c, m=m: paired_se(pairs_of(c, m)))
                   for m in measures for c in names if not band[c].holds(float(np.mean(data[c, m])))]
        if not failing:
            return measured, REPRODUCED
        note, verdict = judge_magnitude(claim, failing, budget, earlier)
        return measured + (f" ({note.strip()})" if note else ""), verdict

    if kind == "ratio":
        t = float(claim["value"])
        band = Band(t - float(claim["tolerance"]) * abs(t), t + float(claim["tolerance"]) * abs(t))
        parts, failing = [], []
        for m in measures:
            now = ratio_stat(data[claim["numerator"], m], [data[c, m] for c in claim["denominator"]])
            parts.append(f"{prefix(m)}ratio {now[0]:.3g} ± {now[1]:.2g}")
            if not band.holds(now[0]):
                def then(m=m):
                    if earlier is None:
                        return None
                    values = [earlier[1](c, m) for c in [claim["numerator"]] + list(claim["denominator"])]
                    return ratio_stat(values[0], values[1:]) if all(values) else None

                def change_se(m=m):
                    ses = [paired_se(pairs_of(c, m)) for c in [claim["numerator"]] + list(claim["denominator"])]
                    if any(se is None for se in ses):
                        return None
                    numerator = float(np.mean(data[claim["numerator"], m]))
                    denominator = float(np.mean([np.mean(data[c, m]) for c in claim["denominator"]]))
                    se_d = math.sqrt(sum(se * se for se in ses[1:])) / len(ses[1:])
                    # The delta method: d(N/D) = dN/D - N dD/D^2.
                    return math.sqrt((ses[0] / denominator) ** 2 + (numerator * se_d / denominator ** 2) ** 2)
                failing.append((prefix(m) + "ratio", band, now, then, change_se))
        measured += " (" + ", ".join(parts) + f"; allowed: {band})"
        if not failing:
            return measured, REPRODUCED
        note, verdict = judge_magnitude(claim, failing, budget, earlier)
        return measured + (f" ({note.strip()})" if note else ""), verdict

    def mean(c, m):
        return float(np.mean(data[c, m]))

    def tested(pairs):
        """Each (a, b, m) pair's Holm-adjusted p over all the pairs (a above b), the largest, and
        the verdict: reproduced when every a is above its b by mean with every adjusted p below
        ALPHA; too few replicates when no p could be."""
        adjusted = [p for _, p in significance.pairwise([(data[a, m], data[b, m]) for a, b, m in pairs])]
        ordered = all(mean(a, m) > mean(b, m) for a, b, m in pairs)
        if ordered and max(adjusted) < ALPHA:
            return adjusted, REPRODUCED
        if ordered and max(smallest_p(len(data[a, m]), len(data[b, m])) for a, b, m in pairs) >= ALPHA:
            return adjusted, TOO_FEW
        return adjusted, NOT_REPRODUCED

    if kind == "top":  # strictly highest (a tie is not a top rank), and significantly above the runner-up
        winners = [max(names, key=lambda c: mean(c, m)) for m in measures]
        others = [c for c in names if c != claim["top"]]
        if not others:
            return measured + " (highest: " + ", ".join(winners) + ")", REPRODUCED
        pairs = [(claim["top"], max(others, key=lambda c: mean(c, m)), m) for m in measures]
        adjusted, verdict = tested(pairs)
        against = ", ".join(f"{prefix(m)}{b} {p:.3g}" for (_, b, m), p in zip(pairs, adjusted))
        measured += " (highest: " + ", ".join(winners) + f"; Holm-adjusted p against the best other condition: {against})"
        return measured, verdict

    # order: every adjacent pair of groups, every member pair, every measure.
    groups = claim["groups"]
    pairs = [(a, b, m) for m in measures for upper, lower in zip(groups, groups[1:]) for a in upper for b in lower]
    adjusted, verdict = tested(pairs)
    measured += f" (largest Holm-adjusted p over {len(pairs)} pair{'s' if len(pairs) > 1 else ''}: {max(adjusted):.3g})"
    return measured, verdict

"""Significance tests for the report (issue 18's statistics), in plain Python so that Debian's
python3 needs nothing beyond itself:

- mann_whitney_u(x, y): the two-sided Mann-Whitney U test as SciPy's `mannwhitneyu` computes it
  by default (method "auto"): the exact distribution of U when a sample has at most 8 values and
  no value is tied, else the normal approximation with the tie correction and a continuity
  correction of 1/2.
- holm(p_values): Holm's step-down adjustment over the comparisons of one table.
- pairwise(sample_pairs): each pair's U and p Holm-adjusted over the pairs, the one rule behind
  every pairwise table and verdict.
- a12(x, y): the Vargha-Delaney effect size, P(X > Y) + P(X = Y) / 2.
- ALPHA: the level below which an adjusted p counts as a difference, in every table and verdict
  (the report's * marks, the claims' order and top rules, the results pages' comparisons).
"""
import math

ALPHA = 0.05


def _ranks(values):
    """Mid-ranks (1-based) of `values`, ties sharing their mean rank, and the tie group sizes."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    ranks = [0.0] * len(values)
    ties = []
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            ranks[order[k]] = (i + j) / 2 + 1
        if j > i:
            ties.append(j - i + 1)
        i = j + 1
    return ranks, ties


def _u_and_ties(x, y):
    """U of x (from its rank sum) and the tie group sizes of the pooled sample."""
    ranks, ties = _ranks([float(v) for v in x] + [float(v) for v in y])
    n1 = len(x)
    return sum(ranks[:n1]) - n1 * (n1 + 1) / 2, ties


def u_statistic(x, y):
    """U of the first sample: the number of pairs (xi, yj) with xi > yj, ties counting 1/2."""
    return _u_and_ties(x, y)[0]


def exact_distribution(n1, n2):
    """How many of the C(n1 + n2, n1) arrangements of n1 x's and n2 y's (no ties) give U = 0, 1,
    ..., n1 n2: the coefficients of the Gaussian binomial [n1 + n2, m] in q, the product over
    k = 1..m of (1 - q^(n + k)) / (1 - q^k) with m, n the smaller and larger size; exact integers."""
    m, n = min(n1, n2), max(n1, n2)
    size = m * n + n + m + 1
    c = [0] * size
    c[0] = 1
    for k in range(1, m + 1):
        for i in range(size - 1, n + k - 1, -1):  # times (1 - q^(n + k))
            c[i] -= c[i - (n + k)]
        for i in range(k, size):  # divided by (1 - q^k): exact, the quotient is a polynomial
            c[i] += c[i - k]
    return c[:m * n + 1]


def _exact_p(u, n1, n2):
    counts = exact_distribution(n1, n2)
    upper = int(max(u, n1 * n2 - u))  # two-sided: as extreme as the larger of U1 and U2
    return min(1.0, 2 * sum(counts[upper:]) / math.comb(n1 + n2, n1))


def mann_whitney_u(x, y):
    """(U of x, two-sided p). Raises ValueError for an empty sample."""
    x, y = list(x), list(y)
    n1, n2 = len(x), len(y)
    if n1 == 0 or n2 == 0:
        raise ValueError("mann_whitney_u: both samples need at least one value")
    u1, ties = _u_and_ties(x, y)
    if (n1 <= 8 or n2 <= 8) and not ties:
        return u1, _exact_p(u1, n1, n2)
    n = n1 + n2
    mean = n1 * n2 / 2
    tie_term = sum(t ** 3 - t for t in ties) / (n * (n - 1))
    sd = math.sqrt(n1 * n2 / 12 * ((n + 1) - tie_term))
    if sd == 0:  # every value equal: no evidence either way
        return u1, 1.0
    z = (max(u1, n1 * n2 - u1) - mean - 0.5) / sd
    return u1, min(1.0, math.erfc(z / math.sqrt(2)))  # 2 * P(Z > z)


def holm(p_values):
    """Holm-adjusted p-values, in the input's order."""
    m = len(p_values)
    order = sorted(range(m), key=lambda i: p_values[i])
    adjusted = [0.0] * m
    running = 0.0
    for rank, i in enumerate(order):
        running = max(running, min(1.0, (m - rank) * p_values[i]))
        adjusted[i] = running
    return adjusted


def pairwise(sample_pairs):
    """For each (x, y) of `sample_pairs`: (U of x over y, its two-sided Mann-Whitney p adjusted
    by Holm's method over all the pairs)."""
    tests = [mann_whitney_u(x, y) for x, y in sample_pairs]
    return [(u, p) for (u, _), p in zip(tests, holm([p for _, p in tests]))]


def a12(x, y):
    """Vargha-Delaney A12 of x over y: 0.5 is no effect, 1 is x always larger."""
    if not x or not y:
        raise ValueError("a12: both samples need at least one value")
    return u_statistic(x, y) / (len(x) * len(y))

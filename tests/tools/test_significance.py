"""tools/significance.py against values computed by hand and, where Debian's python3-scipy is
present, against SciPy's mannwhitneyu."""
import itertools
import math
import pathlib
import random
import sys

import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import significance as sig  # noqa: E402


def test_u_and_exact_p_by_hand():
    # x = 1, 2; y = 3, 4, 5: every x below every y, U(x) = 0. Of C(5, 2) = 10 arrangements one
    # gives U = 0 and one U = 6, so p = 2 / 10.
    u, p = sig.mann_whitney_u([1, 2], [3, 4, 5])
    assert u == 0 and p == pytest.approx(0.2)
    # x = 1, 4; y = 2, 3: U(x) = 2 = n1 n2 / 2, the centre: p = 1.
    assert sig.mann_whitney_u([1, 4], [2, 3]) == (2.0, 1.0)
    # x = 3, 4; y = 1, 2: U = 4 (max); P(U >= 4) = 1/6, so p = 1/3.
    u, p = sig.mann_whitney_u([3, 4], [1, 2])
    assert u == 4 and p == pytest.approx(1 / 3)


def test_the_exact_distribution_counts_every_arrangement():
    n1, n2 = 3, 4
    counts = [0] * (n1 * n2 + 1)
    for xs in itertools.combinations(range(n1 + n2), n1):
        ys = [v for v in range(n1 + n2) if v not in xs]
        counts[int(sig.u_statistic(list(xs), ys))] += 1
    assert counts == sig.exact_distribution(n1, n2) == sig.exact_distribution(n2, n1)
    assert sum(counts) == math.comb(7, 3)


def test_ties_use_mid_ranks_and_the_normal_approximation():
    x, y = [1, 2, 2, 3], [2, 3, 3, 4]
    # Pairs x > y, ties 1/2: each x = 2 ties y = 2 (2 x 0.5 = 1); x = 3 beats y = 2 (1) and ties
    # both y = 3 (1). U = 3.
    u, p = sig.mann_whitney_u(x, y)
    assert u == 3.0
    # n = 8; tie groups: value 2 (three of them) and value 3 (three): sum(t^3 - t) = 24 + 24.
    sd = math.sqrt(16 / 12 * (9 - 48 / 56))
    z = (max(3, 13) - 8 - 0.5) / sd
    assert p == pytest.approx(math.erfc(z / math.sqrt(2)))
    assert sig.mann_whitney_u([5, 5, 5], [5, 5]) == (3.0, 1.0)


def test_holm_by_hand():
    assert sig.holm([0.01, 0.04, 0.03]) == pytest.approx([0.03, 0.06, 0.06])
    assert sig.holm([0.5, 0.9]) == pytest.approx([1.0, 1.0])
    assert sig.holm([]) == []


def test_a12_by_hand():
    assert sig.a12([3, 4], [1, 2]) == 1.0
    assert sig.a12([1, 2], [3, 4]) == 0.0
    assert sig.a12([1, 2, 2, 3], [2, 3, 3, 4]) == pytest.approx(3 / 16)
    with pytest.raises(ValueError):
        sig.a12([], [1])


def test_agrees_with_scipy_when_present():
    stats = pytest.importorskip("scipy.stats")
    rng = random.Random(7)
    cases = [([rng.random() for _ in range(n1)], [rng.random() + shift for _ in range(n2)])
             for n1, n2, shift in [(5, 6, 0.3), (7, 7, 0.0), (20, 20, 0.2), (3, 12, -0.4), (8, 40, 0.1)]]
    cases.append(([round(rng.gauss(0, 1), 1) for _ in range(20)], [round(rng.gauss(0.5, 1), 1) for _ in range(20)]))
    cases.append(([1, 2, 2, 3], [2, 3, 3, 4]))
    for x, y in cases:
        u, p = sig.mann_whitney_u(x, y)
        reference = stats.mannwhitneyu(x, y, alternative="two-sided")
        assert u == pytest.approx(reference.statistic)
        assert p == pytest.approx(reference.pvalue, rel=1e-9, abs=1e-12), (x, y)


def test_pairwise_adjusts_each_pairs_p_over_all_the_pairs():
    # (x1, y1): every x above every y, U = 4, exact p = 1/3; (x2, y2): the centre, U = 2, p = 1.
    # Holm over the two: 2 x 1/3 = 2/3 for the smaller, then max(2/3, 1 x 1) = 1.
    tested = sig.pairwise([([3, 4], [1, 2]), ([1, 4], [2, 3])])
    assert tested == [(4.0, pytest.approx(2 / 3)), (2.0, 1.0)]
    assert sig.pairwise([([3, 4], [1, 2])]) == [(4.0, pytest.approx(1 / 3))]
    assert sig.pairwise([]) == []

"""bench/peers/common.py's CMA-MAE paper domains (pyribs's side) against the values worked out by
hand that tests/bench/cma_domains_test.cpp checks in the C++ (cma_peer's side)."""
import math
import pathlib
import sys

import numpy as np
import pytest

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "bench" / "peers"))
import common  # noqa: E402

GENES = 100


def one(f, x):
    objective, measures = f(np.asarray([x], dtype=np.float64))
    return objective[0], measures[0, 0], measures[0, 1]


def test_sphere_optimum_origin_corner_and_fold():
    assert one(common.lin_proj_sphere, [2.048] * GENES) == pytest.approx((100.0, 102.4, 102.4), abs=1e-9)
    # S / W = (2.048 / 7.168)^2 = 4 / 49.
    assert one(common.lin_proj_sphere, [0.0] * GENES) == pytest.approx((100 * 45 / 49, 0.0, 0.0), abs=1e-9)
    # -5.12 is inside the box (kept).
    assert one(common.lin_proj_sphere, [-5.12] * GENES) == pytest.approx((0.0, -256.0, -256.0), abs=1e-9)
    # 10.24 folds to 0.5; S / W = (64 / 49 + 1) / 2 = 113 / 98.
    mixed = [10.24] * (GENES // 2) + [-5.12] * (GENES // 2)
    assert one(common.lin_proj_sphere, mixed) == pytest.approx((-1500 / 98, 25.0, -256.0), abs=1e-9)
    evaluate, bound, sigma0 = common.CMA_DOMAINS["sphere"]
    assert evaluate is common.lin_proj_sphere and bound(GENES) == 256.0 and sigma0 == 0.5


def test_arm_straight_zigzag_closed_and_back():
    assert one(common.arm_repertoire, [0.0] * GENES) == pytest.approx((100.0, 100.0, 0.0), abs=1e-12)
    zigzag = [0.5 if j % 2 == 0 else -0.5 for j in range(GENES)]
    expected = (75.0, 50 + 50 * math.cos(0.5), 50 * math.sin(0.5))
    assert one(common.arm_repertoire, zigzag) == pytest.approx(expected, abs=1e-9)
    assert one(common.arm_repertoire, [2 * math.pi / GENES] * GENES) == pytest.approx((100.0, 0.0, 0.0), abs=1e-9)
    back = [math.pi] + [0.0] * (GENES - 1)
    assert one(common.arm_repertoire, back) == pytest.approx((100 - 0.99 * math.pi ** 2, -100.0, 0.0), abs=1e-9)
    evaluate, bound, sigma0 = common.CMA_DOMAINS["arm"]
    assert evaluate is common.arm_repertoire and bound(GENES) == 100.0 and sigma0 == 0.1


def test_rows_are_evaluated_independently():
    x = np.array([[2.048] * GENES, [0.0] * GENES])
    objective, measures = common.lin_proj_sphere(x)
    assert objective == pytest.approx([100.0, 100 * 45 / 49]) and measures.shape == (2, 2)

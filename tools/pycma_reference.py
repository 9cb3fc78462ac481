#!/usr/bin/env python3
"""One-off reference measurement for tests/meta/cma_es_test.cpp (not part of the build).

Runs pycma (the `cma` package from the Python package index) on the three 10-D test functions
with the same x0, sigma0 and population size as the C++ tests, stops at f < 1e-8, and prints the median
number of evaluations over several seeds.

    python3 -m venv /tmp/pycma && /tmp/pycma/bin/pip install cma numpy
    /tmp/pycma/bin/python tools/pycma_reference.py            # pycma defaults (active CMA on)
    /tmp/pycma/bin/python tools/pycma_reference.py --no-active # closer to qdmeta::CmaEs
"""
import argparse
import statistics
import warnings

warnings.filterwarnings("ignore")  # pycma warns that matplotlib is missing

import cma  # noqa: E402
import numpy as np  # noqa: E402

N = 10
POPSIZE = 10          # default for n = 10: 4 + floor(3 ln 10)
FTARGET = 1e-8
ELLIPSOID_SCALES = 10.0 ** (6.0 * np.arange(N) / (N - 1))  # condition number 1e6


def sphere(x):
    return float(np.sum(np.asarray(x) ** 2))


def ellipsoid(x):
    return float(np.sum(ELLIPSOID_SCALES * np.asarray(x) ** 2))


def rosenbrock(x):
    x = np.asarray(x)
    return float(np.sum(100.0 * (x[1:] - x[:-1] ** 2) ** 2 + (1.0 - x[:-1]) ** 2))


# name, function, x0 (every coordinate), sigma0 -- keep in sync with the C++ tests.
CASES = [
    ("sphere", sphere, 1.0, 0.5),
    ("ellipsoid", ellipsoid, 1.0, 0.5),
    ("rosenbrock", rosenbrock, 0.0, 0.1),
]


def run(fun, x0, sigma0, seed, active):
    opts = {
        "popsize": POPSIZE,
        "ftarget": FTARGET,
        "seed": seed,
        "verbose": -9,
        "maxfevals": 200000,
        "CMA_active": active,
    }
    es = cma.CMAEvolutionStrategy(N * [x0], sigma0, opts)
    while not es.stop():
        xs = es.ask()
        es.tell(xs, [fun(x) for x in xs])
    return es.result.evaluations, es.result.fbest


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--seeds", type=int, default=21)
    parser.add_argument("--no-active", action="store_true")
    args = parser.parse_args()
    active = not args.no_active
    print(f"cma {cma.__version__}, n={N}, popsize={POPSIZE}, ftarget={FTARGET}, "
          f"CMA_active={active}, seeds 1..{args.seeds}")
    for name, fun, x0, sigma0 in CASES:
        evals, failures = [], 0
        for seed in range(1, args.seeds + 1):
            e, f = run(fun, x0, sigma0, seed, active)
            if f < FTARGET:
                evals.append(e)
            else:
                failures += 1
        print(f"{name:10s} x0={x0} sigma0={sigma0}: median {statistics.median(evals):.0f} "
              f"evaluations (min {min(evals)}, max {max(evals)}, "
              f"{failures} of {args.seeds} runs missed the target)")


if __name__ == "__main__":
    main()

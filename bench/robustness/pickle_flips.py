#!/usr/bin/python3
"""Pickled qdmeta state with one bit flipped: every such pickle must be refused (any exception
from pickle.loads) or load as the original (a flip in pickle's own framing may change nothing);
one that loads as other data (other elites, config, counters) is a defect. A flip in pickle's
opcodes may make it load another object altogether (a str: no qdmeta state was read), counted
apart as fine.

Usage: PYTHONPATH=build/python bench/robustness/pickle_flips.py [--quick] [--every N]

Pickles a MAP-Elites algorithm after 3 steps and a grid, a CVT and an unstructured archive,
flips bit k of each for every N-th k (default: every bit; --quick: 400 flips spread over each
pickle) and loads it. Prints `<object>: F flips, R refused, S same, N not a qdmeta object, D
other data` per object,
then `N cases, M defects`; exits 1 when there is a defect. ctest robustness_pickle_flips runs
it with --quick.
"""
import argparse
import pickle
import sys

import numpy as np

import qdmeta

ME = {"algorithm": "map-elites", "seed": 7, "archive": {"bins": [10, 10]},
      "task": {"name": "rastrigin", "dimensions": 6}}


def archives():
    rng = np.random.default_rng(3)
    solutions = rng.random((400, 6), dtype=np.float32)
    objectives = rng.normal(size=400).astype(np.float32)
    measures = rng.random((400, 2), dtype=np.float32)
    grid = qdmeta.GridArchive(solution_dim=6, dims=[7, 9], lower=-0.5, upper=1.5, base_feature_dim=2, seed=11)
    grid.add(solutions, objectives, measures, base_features=measures * 0.5)
    cvt = qdmeta.CvtArchive(solution_dim=6, centroids=rng.random((30, 2)), seed=12)
    cvt.add(solutions, objectives, measures)
    unstructured = qdmeta.UnstructuredArchive(solution_dim=6, measure_dim=2, target_size=50, seed=13)
    unstructured.add(solutions, objectives, measures, threshold=0.1)
    return [("GridArchive", grid), ("CvtArchive", cvt), ("UnstructuredArchive", unstructured)]


def fingerprint(obj):
    """What must come back unchanged: the elites, and an algorithm's config and counters or an
    archive's seed."""
    data = obj.data()
    values = [(k, data[k].dtype.str, data[k].tobytes()) for k in sorted(data)]
    if isinstance(obj, qdmeta.Algorithm):
        return values, repr(obj.config), obj.generation, obj.evaluations
    return values, obj.seed, len(obj)


def flips(obj, every):
    """(flips, refused, same, not a qdmeta object, other data) of the pickle of `obj`."""
    data = pickle.dumps(obj)
    expected = fingerprint(obj)
    counts = [0, 0, 0, 0, 0]
    for bit in range(0, 8 * len(data), every(len(data))):
        damaged = bytearray(data)
        damaged[bit // 8] ^= 1 << (bit % 8)
        counts[0] += 1
        try:
            twin = pickle.loads(bytes(damaged))
        except Exception:  # noqa: BLE001 (any refusal is fine)
            counts[1] += 1
            continue
        if type(twin) is not type(obj):
            counts[3] += 1
            continue
        counts[2 if fingerprint(twin) == expected else 4] += 1
    return counts


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="400 flips per pickle (the test suite's)")
    parser.add_argument("--every", type=int, default=1, help="flip every N-th bit")
    args = parser.parse_args(argv[1:])
    # Some damaged opcodes make pickle itself print "deallocated bytearray object has exported
    # buffers" as it drops what it built: pickle's, not qdmeta's, and counted as refused.
    sys.unraisablehook = lambda unraisable: None
    every = (lambda n: max(1, 8 * n // 400)) if args.quick else (lambda n: args.every)
    algorithm = qdmeta.Algorithm(ME)
    for _ in range(3):
        algorithm.step(threads=1)
    cases = defects = 0
    for name, obj in [("Algorithm (map-elites)", algorithm)] + archives():
        total, refused, same, foreign, other = flips(obj, every)
        print(f"{name}: {total} flips, {refused} refused, {same} same, {foreign} not a qdmeta object, {other} other "
              "data", flush=True)
        cases += total
        defects += other
    print(f"{cases} cases, {defects} defects")
    return 1 if defects else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""The workloads of novelty_archives_bench.cpp timed through pyribs 0.12 and through qdmeta's
Python module, side by side in one process (milliseconds per batch of 540, best of 5 runs of 20):

    python3 -m venv /tmp/ribs && /tmp/ribs/bin/pip install ribs==0.12.0
    PYTHONPATH=build/python /tmp/ribs/bin/python bench/archive/novelty_archives_pyribs.py
"""

import time

import numpy as np
import qdmeta
from ribs.archives import ProximityArchive, SlidingBoundariesArchive


def best_ms(step, repeats=5, n=20):
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(n):
            step()
        times.append((time.perf_counter() - start) / n * 1e3)
    return min(times)


def batches(seed):
    rng = np.random.default_rng(seed)
    while True:
        yield rng.random((540, 3)), rng.random(540), rng.random((540, 2))


def proximity(module, elites, **settings):
    a = module.ProximityArchive(solution_dim=3, measure_dim=2, k_neighbors=15, **settings)
    rng = np.random.default_rng(1)
    a.add(rng.random((elites, 3)), rng.random(elites), rng.random((elites, 2)))
    return a


def main():
    libraries = {"pyribs": __import__("ribs.archives", fromlist=["x"]), "qdmeta": qdmeta}
    rows = []
    for elites in (1_000, 10_000):
        queries = np.random.default_rng(4).random((540, 2))
        times = {name: best_ms(lambda a=proximity(lib, elites, novelty_threshold=0.0): a.compute_novelty(queries))
                 for name, lib in libraries.items()}
        rows.append((f"proximity novelty, 540 vs {elites:,}", times))
        times = {}
        for name, lib in libraries.items():
            a = proximity(lib, elites, novelty_threshold=1.0, local_competition=True)
            source = batches(10)
            times[name] = best_ms(lambda: a.add(*next(source)))
        rows.append((f"proximity add 540, local competition, {elites:,}", times))
    times = {}
    for name, lib in libraries.items():
        a = lib.SlidingBoundariesArchive(solution_dim=3, dims=[100, 100], ranges=[(0, 1), (0, 1)])
        source = batches(10)
        times[name] = best_ms(lambda: a.add(*next(source)))
    rows.append(("sliding boundaries add 540 (100 x 100)", times))
    print(f"{'workload':48} {'pyribs ms':>10} {'qdmeta ms':>10} {'ratio':>7}")
    for label, t in rows:
        print(f"{label:48} {t['pyribs']:10.3f} {t['qdmeta']:10.3f} {t['pyribs'] / t['qdmeta']:7.1f}")


if __name__ == "__main__":
    main()

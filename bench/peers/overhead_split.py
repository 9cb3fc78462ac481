"""Where qdmeta's overhead from Python goes on the arm's shapes: ask() and tell() timed apart.

    python3 bench/peers/overhead_split.py [--batches 2500] [--repeats 3]

The peers' loop (peer_qdmeta_python.py) without the task: 100 genes, 2 measures, batches of 400
after 2,000 initial solutions, the Gaussian operator (rate 0.10, SD 0.05) or iso+line, on the
100 x 100 grid and on 10,000 CVT centroids in 2-D (`auto` search). tell() is handed a fixed set
of random objectives and measures in [0, 1] (drawn once, reused in turn), so the archive fills
as a real run's does but no time goes to a task. Prints nanoseconds per evaluation, the median of
the repeats, for ask() (parent choice, variation, the copy into numpy) and tell() (the checks and
the archive's insertion). The module is build/python's (`make build`).
"""
import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "build" / "python"))
import qdmeta  # noqa: E402

import common  # noqa: E402


def config(algorithm, operator):
    if operator == "gaussian":
        mutation = {"kind": "gaussian", "rate": common.MUTATION_RATE, "sigma": common.MUTATION_SD}
    else:
        mutation = {"kind": "iso-line", "iso_sigma": common.ISO_SIGMA, "line_sigma": common.LINE_SIGMA}
    c = {"seed": 1, "mutation": mutation, "map_elites": {"batch_size": common.BATCH, "initial_population": common.INITIAL}}
    if algorithm == "map-elites":
        c.update(algorithm="map-elites", archive={"bins": list(common.GRID), "measures": [0, 1]})
    else:
        c.update(algorithm="cvt-map-elites", cvt={"centroids": 10000, "samples": 100000, "init": "random",
                                                  "init_samples": 100000, "method": "lloyd", "iterations": 10,
                                                  "seed": 1})
    return c


def time_split(algorithm, operator, batches):
    def never_called(genotypes):
        raise RuntimeError("the split times ask() and tell() only")

    task = qdmeta.Task(never_called, genotype_size=common.ARM_JOINTS, base_feature_size=2, name="arm-shapes")
    algo = qdmeta.Algorithm(config(algorithm, operator), task=task)
    rng = np.random.default_rng(1)
    first = algo.ask()
    algo.tell(-rng.random(len(first)).astype(np.float32), rng.random((len(first), 2)).astype(np.float32))
    objectives = [-rng.random(common.BATCH).astype(np.float32) for _ in range(64)]
    measures = [rng.random((common.BATCH, 2)).astype(np.float32) for _ in range(64)]
    ask_s = tell_s = 0.0
    evals = 0
    for i in range(batches):
        t0 = time.perf_counter()
        genotypes = algo.ask()
        t1 = time.perf_counter()
        algo.tell(objectives[i % 64], measures[i % 64])
        t2 = time.perf_counter()
        ask_s += t1 - t0
        tell_s += t2 - t1
        evals += len(genotypes)
    return ask_s / evals * 1e9, tell_s / evals * 1e9


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--batches", type=int, default=2500, help="batches of 400 per timing (default 2500: 1M evaluations)")
    p.add_argument("--repeats", type=int, default=3)
    args = p.parse_args()
    print("| archive | operator | ask() ns/evaluation | tell() ns/evaluation | total |")
    print("|---|---|---|---|---|")
    for algorithm in ("map-elites", "cvt"):
        for operator in ("gaussian", "iso-line"):
            runs = [time_split(algorithm, operator, args.batches) for _ in range(args.repeats)]
            ask = statistics.median(r[0] for r in runs)
            tell = statistics.median(r[1] for r in runs)
            print(f"| {algorithm} | {operator} | {ask:.0f} | {tell:.0f} | {ask + tell:.0f} |", flush=True)


if __name__ == "__main__":
    main()

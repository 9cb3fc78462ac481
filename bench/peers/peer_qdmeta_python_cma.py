"""qdmeta's Python module in the CMA-MAE paper's comparison: peer_pyribs_cma.py's loop with
pyribs's names swapped for qdmeta's (docs/tutorials/pyribs-cma-mae.md), on the same numpy
domains (common.CMA_DOMAINS) and settings: 15 EvolutionStrategyEmitters of batch 36 from x0 = 0,
selection "mu", restart "basic"; CMA-ME ranks by "2imp", CMA-MAE by "imp" over an archive of
learning_rate 0.01 and threshold_min 0 (whose cells keep their best elites, pyribs's result
archive). Prints one JSON line (common.emit). The scheduler asks and tells its emitters on every
core the process may use (taskset -c 0 gives it one); the note says how many that was.

    python peer_qdmeta_python_cma.py --domain sphere --algorithm cma-mae --iterations 300 --seed 1
"""
import argparse
import os
import sys
import time
from pathlib import Path

import numpy as np

try:
    import qdmeta  # a PYTHONPATH's module first (the tests name their build's)
except ImportError:
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "build" / "python"))
    import qdmeta

import common  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--domain", choices=sorted(common.CMA_DOMAINS), required=True)
    p.add_argument("--algorithm", choices=["cma-me", "cma-mae"], required=True)
    p.add_argument("--iterations", type=int, default=10_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--genes", type=int, default=100)
    args = p.parse_args()
    evaluate, bound_of, sigma0 = common.CMA_DOMAINS[args.domain]
    bound = bound_of(args.genes)
    mae = args.algorithm == "cma-mae"
    archive = qdmeta.GridArchive(solution_dim=args.genes, dims=list(common.CMA_GRID), ranges=[(-bound, bound)] * 2,
                                 learning_rate=0.01 if mae else None, threshold_min=0.0 if mae else -np.inf)
    emitters = [qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(args.genes), sigma0=sigma0,
                                                ranker="imp" if mae else "2imp", selection_rule="mu",
                                                restart_rule="basic", batch_size=common.CMA_EMITTER_BATCH,
                                                seed=args.seed * 1000 + i)
                for i in range(common.CMA_EMITTERS)]
    scheduler = qdmeta.Scheduler(archive, emitters)
    obj_max = -np.inf
    task_s = 0.0
    evals = 0
    start = time.perf_counter()
    for _ in range(args.iterations):
        solutions = scheduler.ask()
        task_start = time.perf_counter()
        objectives, measures = evaluate(solutions)
        task_s += time.perf_counter() - task_start
        obj_max = max(obj_max, float(np.max(objectives)))
        scheduler.tell(objectives, measures)
        evals += len(solutions)
    wall = time.perf_counter() - start
    elites = archive.data("objective")
    cells = common.CMA_GRID[0] * common.CMA_GRID[1]
    cores = len(os.sched_getaffinity(0))
    common.emit(library="qdmeta-py", version=qdmeta.__version__, algorithm=args.algorithm, domain=args.domain,
                iterations=args.iterations, evals=evals, wall_s=wall, task_s=task_s, num_elites=len(elites),
                qd_score=float(np.sum(elites, dtype=np.float64)) / cells, coverage=100.0 * len(elites) / cells,
                obj_max=obj_max, seed=args.seed,
                note=f"qdmeta.Scheduler over EvolutionStrategyEmitter x 15, {cores} core(s)")


if __name__ == "__main__":
    main()

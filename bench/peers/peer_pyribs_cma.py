"""pyribs runner for the CMA-MAE paper's comparison: CMA-ME or CMA-MAE on the linear-projection
sphere or the planar arm (common.CMA_DOMAINS) through pyribs's public API, with the settings of
pyribs's own sphere example for the paper (examples/sphere.py, "cma_me_basic" and "cma_mae"):
15 EvolutionStrategyEmitters of batch 36 from x0 = 0 with the domain's sigma0, selection "mu",
restart "basic"; CMA-ME ranks by "2imp" on one GridArchive; CMA-MAE ranks by "imp" on a
GridArchive with learning_rate 0.01 and threshold_min 0, beside a plain GridArchive as its result
archive. Prints one JSON line (common.emit); the QD-score is the paper's (the elites' objectives
summed over all cells), coverage in percent, both of the result archive.

Run by cma_peers.py with the venv's python (run.sh makes it).
"""
import argparse
import time

import numpy as np
import ribs
from ribs.archives import GridArchive
from ribs.emitters import EvolutionStrategyEmitter
from ribs.schedulers import Scheduler

import common


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
    grid = {"solution_dim": args.genes, "dims": common.CMA_GRID, "ranges": [(-bound, bound)] * 2}
    mae = args.algorithm == "cma-mae"
    if mae:
        archive = GridArchive(**grid, learning_rate=0.01, threshold_min=0.0, seed=args.seed)
        result = GridArchive(**grid, seed=args.seed)
    else:
        archive = result = GridArchive(**grid, seed=args.seed)
    # Each emitter its own seed, as the paper's scripts give them (seed, seed + 1, ...).
    emitters = [EvolutionStrategyEmitter(archive, x0=np.zeros(args.genes), sigma0=sigma0,
                                         ranker="imp" if mae else "2imp", selection_rule="mu",
                                         restart_rule="basic", batch_size=common.CMA_EMITTER_BATCH,
                                         seed=args.seed * 1000 + i)
                for i in range(common.CMA_EMITTERS)]
    scheduler = Scheduler(archive, emitters, result_archive=result if mae else None)
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
    elites = result.data("objective")
    cells = common.CMA_GRID[0] * common.CMA_GRID[1]
    common.emit(library="pyribs", version=ribs.__version__, algorithm=args.algorithm, domain=args.domain,
                iterations=args.iterations, evals=evals, wall_s=wall, task_s=task_s, num_elites=len(result),
                qd_score=float(np.sum(elites, dtype=np.float64)) / cells, coverage=100.0 * len(result) / cells,
                obj_max=obj_max, seed=args.seed, note="EvolutionStrategyEmitter x 15, Scheduler")


if __name__ == "__main__":
    main()

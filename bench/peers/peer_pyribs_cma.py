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
import numpy as np
import ribs
from ribs.archives import GridArchive
from ribs.emitters import EvolutionStrategyEmitter
from ribs.schedulers import Scheduler

import common


def main():
    args = common.cma_arguments(__doc__)
    evaluate, bound_of, sigma0 = common.CMA_DOMAINS[args.domain]
    bound = bound_of(args.genes)
    grid = {"solution_dim": args.genes, "dims": common.CMA_GRID, "ranges": [(-bound, bound)] * 2}
    mae = args.algorithm == "cma-mae"
    if mae:
        archive = GridArchive(**grid, learning_rate=0.01, threshold_min=0.0, seed=args.seed)
        result = GridArchive(**grid, seed=args.seed)
    else:
        archive = result = GridArchive(**grid, seed=args.seed)
    emitters = [EvolutionStrategyEmitter(archive, **settings) for settings in common.cma_emitter_settings(args, sigma0)]
    scheduler = Scheduler(archive, emitters, result_archive=result if mae else None)
    loop = common.run_cma_loop(scheduler, evaluate, args.iterations)
    common.emit_cma(args, "pyribs", ribs.__version__, loop, result.data("objective"),
                    "EvolutionStrategyEmitter x 15, Scheduler")


if __name__ == "__main__":
    main()

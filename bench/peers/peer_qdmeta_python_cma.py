"""qdmeta's Python module in the CMA-MAE paper's comparison: peer_pyribs_cma.py's loop with
pyribs's names swapped for qdmeta's (docs/tutorials/pyribs-cma-mae.md), on the same numpy
domains (common.CMA_DOMAINS) and settings: 15 EvolutionStrategyEmitters of batch 36 from x0 = 0,
selection "mu", restart "basic"; CMA-ME ranks by "2imp", CMA-MAE by "imp" over an archive of
learning_rate 0.01 and threshold_min 0 (whose cells keep their best elites, pyribs's result
archive). Prints one JSON line (common.emit). The scheduler asks and tells its emitters on every
core the process may use (taskset -c 0 gives it one); the note says how many that was.

    python peer_qdmeta_python_cma.py --domain sphere --algorithm cma-mae --iterations 300 --seed 1
"""
import os
import sys
from pathlib import Path

import numpy as np

try:
    import qdmeta  # a PYTHONPATH's module first (the tests name their build's)
except ImportError:
    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "build" / "python"))
    import qdmeta

import common  # noqa: E402


def main():
    args = common.cma_arguments(__doc__)
    evaluate, bound_of, sigma0 = common.CMA_DOMAINS[args.domain]
    bound = bound_of(args.genes)
    mae = args.algorithm == "cma-mae"
    archive = qdmeta.GridArchive(solution_dim=args.genes, dims=list(common.CMA_GRID), ranges=[(-bound, bound)] * 2,
                                 learning_rate=0.01 if mae else None, threshold_min=0.0 if mae else -np.inf)
    emitters = [qdmeta.EvolutionStrategyEmitter(archive, **settings)
                for settings in common.cma_emitter_settings(args, sigma0)]
    scheduler = qdmeta.Scheduler(archive, emitters)
    loop = common.run_cma_loop(scheduler, evaluate, args.iterations)
    cores = len(os.sched_getaffinity(0))
    common.emit_cma(args, "qdmeta-py", qdmeta.__version__, loop, archive.data("objective"),
                    f"qdmeta.Scheduler over EvolutionStrategyEmitter x 15, {cores} core(s)")


if __name__ == "__main__":
    main()

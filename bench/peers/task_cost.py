"""The numpy task's own cost, timed alone: the evaluation of a run's batches (2,000 initial
solutions, then batches of 400) of uniform random genotypes, with nothing else in the loop.
Prints one JSON line (library "numpy-task", algorithm "<task>-task")."""
import argparse
import time

import numpy as np

import common


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("--task", choices=sorted(common.TASKS), required=True)
    p.add_argument("--evals", type=int, default=1_000_000)
    p.add_argument("--seed", type=int, default=1)
    args = p.parse_args()
    task = common.TASKS[args.task]
    rng = np.random.default_rng(args.seed)
    wall = 0.0
    for n in common.batches(args.evals):
        genotypes = rng.random((n, task.genes))
        start = time.perf_counter()
        task.evaluate(genotypes)
        wall += time.perf_counter() - start
    common.emit(library="numpy-task", version=np.__version__, algorithm=f"{task.name}-task", evals=args.evals,
                wall_s=wall, task_s=wall, note=f"the numpy {task.name} alone on uniform random batches")


if __name__ == "__main__":
    main()

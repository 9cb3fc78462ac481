"""What every peer runner shares: the tasks, the operators and one result line.

Rastrigin (docs/fidelity.md): genotype g in [0,1]^20, x = -5.12 + 10.24 g, objective
f = -[10 N + sum(x^2 - 10 cos 2 pi x)] (maximum 0), measures (g0, g1) on a 100 x 100 grid or
all 20 genes for CVT. QD-score offset -2000.

The planar arm (examples/own-task/arm_task.cpp): 100 joints on links of length 1/100, gene g_j
in [0,1] is the joint angle a_j = (g_j - 0.5) 2 pi relative to the link before; objective =
-variance of the angles (maximum 0: a straight arm); measures = the end effector's (x, y),
each scaled from [-1, 1] to [0, 1], on a 100 x 100 grid or as the CVT descriptor (2-D).
QD-score offset -pi^2 (the lowest objective).

The operators: "gaussian", each gene mutated with probability 0.10 by a Gaussian of SD 0.05,
clamped to [0, 1]; "iso-line" (Vassiliades & Mouret 2018), x_i + 0.01 N(0, I) + 0.2 N(0, 1)
(x_j - x_i) for two uniformly chosen elites, clamped.
"""
import argparse
import json
import sys
import time

import numpy as np

DIMENSIONS = 20
GRID = (100, 100)
BATCH = 400
INITIAL = 2000
MUTATION_RATE = 0.10
MUTATION_SD = 0.05
QD_OFFSET = -2000.0
ISO_SIGMA = 0.01
LINE_SIGMA = 0.2
ARM_JOINTS = 100
ARM_QD_OFFSET = -np.pi ** 2


def rastrigin(genotypes):
    """Objective of each row of a (n, 20) array in [0,1], computed in float32 as qdmeta's own task
    and QDax's jax do (numpy's float32 cosine is vectorised: about 4x faster than float64's)."""
    x = np.float32(-5.12) + np.float32(10.24) * np.asarray(genotypes, dtype=np.float32)
    terms = x * x - np.float32(10.0) * np.cos(np.float32(2.0 * np.pi) * x)
    return -(np.float32(10.0 * x.shape[1]) + np.sum(terms, axis=1))


def arm(genotypes):
    """Objective and (n, 2) measures of each row of a (n, joints) array in [0,1], in float32 like
    the Rastrigin task (the C++ arm computes in double: its measures agree to about 1e-6)."""
    angles = (np.asarray(genotypes, dtype=np.float32) - np.float32(0.5)) * np.float32(2.0 * np.pi)
    objective = -np.var(angles, axis=1)
    heading = np.cumsum(angles, axis=1)
    link = np.float32(1.0 / angles.shape[1])
    xy = np.stack([link * np.sum(np.cos(heading), axis=1), link * np.sum(np.sin(heading), axis=1)], axis=1)
    return objective, np.clip((xy + np.float32(1.0)) / np.float32(2.0), np.float32(0.0), np.float32(1.0))


class Task:
    """A task as the runners see it: genes, the measures of the grid and of CVT, the QD offset."""

    def __init__(self, name, genes, cvt_dimensions, qd_offset, evaluate):
        self.name = name
        self.genes = genes
        self.cvt_dimensions = cvt_dimensions
        self.qd_offset = qd_offset
        self.evaluate = evaluate  # genotypes -> (objectives, grid measures, CVT measures)


TASKS = {
    "rastrigin": Task("rastrigin", DIMENSIONS, DIMENSIONS, QD_OFFSET, lambda g: (rastrigin(g), g[:, :2], g)),
    "arm": Task("arm", ARM_JOINTS, 2, ARM_QD_OFFSET, lambda g: (lambda f, m: (f, m, m))(*arm(g))),
}


# The CMA-MAE paper's domains (Fontaine & Nikolaidis 2023; its experiments' lin_proj.py and
# arm.py), as bench/peers/cma_domains.hpp has them in C++: unbounded genes, objectives normalised
# so that 100 is the optimum, measures on a 100 x 100 grid over [-CMA_BOUND, CMA_BOUND]^2.
SPHERE_BOUND = 5.12
SPHERE_SHIFT = 0.4 * SPHERE_BOUND


def lin_proj_sphere(solutions):
    """Objective and (n, 2) measures of each row of a (n, genes) array: the sphere with its
    optimum at 2.048 in every gene, 100 (W - S) / W with W = genes (5.12 + 2.048)^2; the measures
    sum the first and the last genes / 2 genes after each gene outside [-5.12, 5.12] is folded to
    5.12 / x. In float64, as pyribs's example."""
    x = np.asarray(solutions, dtype=np.float64)
    genes = x.shape[1]
    worst = genes * (SPHERE_BOUND + SPHERE_SHIFT) ** 2
    objective = 100.0 * (worst - np.sum((x - SPHERE_SHIFT) ** 2, axis=1)) / worst
    folded = np.where(np.abs(x) <= SPHERE_BOUND, x, SPHERE_BOUND / np.where(x == 0.0, 1.0, x))
    half = genes // 2
    return objective, np.stack([folded[:, :half].sum(axis=1), folded[:, half:].sum(axis=1)], axis=1)


def arm_repertoire(solutions):
    """Objective and (n, 2) measures of each row of a (n, joints) array of joint angles, links of
    length 1: 100 (1 - Var(angles)), and the end effector's (x, y)."""
    angles = np.asarray(solutions, dtype=np.float64)
    heading = np.cumsum(angles, axis=1)
    objective = 100.0 * (1.0 - np.var(angles, axis=1))
    return objective, np.stack([np.cos(heading).sum(axis=1), np.sin(heading).sum(axis=1)], axis=1)


# name -> (evaluate, half-width of the measure grid for `genes` genes, the paper's sigma0)
CMA_DOMAINS = {
    "sphere": (lin_proj_sphere, lambda genes: genes // 2 * SPHERE_BOUND, 0.5),
    "arm": (arm_repertoire, lambda genes: float(genes), 0.1),
}
CMA_EMITTERS = 15
CMA_EMITTER_BATCH = 36
CMA_GRID = (100, 100)


def cma_arguments(description):
    """The command line of a CMA-ME / CMA-MAE runner (peer_pyribs_cma.py, peer_qdmeta_python_cma.py)."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--domain", choices=sorted(CMA_DOMAINS), required=True)
    p.add_argument("--algorithm", choices=["cma-me", "cma-mae"], required=True)
    p.add_argument("--iterations", type=int, default=10_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--genes", type=int, default=100)
    return p.parse_args()


def cma_emitter_settings(args, sigma0):
    """Each emitter's keyword arguments but its archive, as the paper's sphere example sets them
    (both libraries take the same names): CMA-ME ranks by "2imp", CMA-MAE by "imp"; emitter i
    is seeded seed * 1000 + i, as the paper's scripts give them their own seeds."""
    ranker = "imp" if args.algorithm == "cma-mae" else "2imp"
    return [dict(x0=np.zeros(args.genes), sigma0=sigma0, ranker=ranker, selection_rule="mu", restart_rule="basic",
                 batch_size=CMA_EMITTER_BATCH, seed=args.seed * 1000 + i) for i in range(CMA_EMITTERS)]


def run_cma_loop(scheduler, evaluate, iterations):
    """`iterations` of ask, evaluate (timed apart: the task's share) and tell; returns the loop's
    wall seconds, the task's seconds, the evaluations and the best objective seen."""
    obj_max = -np.inf
    task_s = 0.0
    evals = 0
    start = time.perf_counter()
    for _ in range(iterations):
        solutions = scheduler.ask()
        task_start = time.perf_counter()
        objectives, measures = evaluate(solutions)
        task_s += time.perf_counter() - task_start
        obj_max = max(obj_max, float(np.max(objectives)))
        scheduler.tell(objectives, measures)
        evals += len(solutions)
    return time.perf_counter() - start, task_s, evals, obj_max


def emit_cma(args, library, version, loop, elites, note):
    """The CMA runner's result line: `loop` is run_cma_loop's, `elites` the result archive's
    objectives; the QD-score is the paper's (summed over all cells), coverage in percent."""
    wall, task_s, evals, obj_max = loop
    cells = CMA_GRID[0] * CMA_GRID[1]
    emit(library=library, version=version, algorithm=args.algorithm, domain=args.domain, iterations=args.iterations,
         evals=evals, wall_s=wall, task_s=task_s, num_elites=len(elites),
         qd_score=float(np.sum(elites, dtype=np.float64)) / cells, coverage=100.0 * len(elites) / cells,
         obj_max=obj_max, seed=args.seed, note=note)


def mutate(parents, rng):
    """The Gaussian operator on a (n, genes) array of parents."""
    mask = rng.random(parents.shape) < MUTATION_RATE
    noise = rng.normal(0.0, MUTATION_SD, parents.shape)
    return np.clip(parents + mask * noise, 0.0, 1.0)


def batches(evals):
    """Batch sizes of one run: the initial random solutions, then batches of 400."""
    if evals < INITIAL:
        raise SystemExit(f"--evals must be at least {INITIAL} (the initial random solutions)")
    sizes = [INITIAL]
    left = evals - INITIAL
    while left > 0:
        sizes.append(min(BATCH, left))
        left -= sizes[-1]
    return sizes


def qd_score(objectives, offset=QD_OFFSET):
    """Sum over elites of (objective - offset): the same formula for every library."""
    return float(np.sum(np.asarray(objectives, dtype=np.float64) - offset))


def emit(**fields):
    """The runner's one result line for the driver."""
    json.dump(fields, sys.stdout)
    sys.stdout.write("\n")
    sys.stdout.flush()


def main(description, library, make_centroids, run, kmeans_iterations=False):
    """A runner's command line: --algorithm cvt-centroids builds and saves centroids, else runs."""
    p = argparse.ArgumentParser(description=description)
    p.add_argument("--algorithm", choices=["map-elites", "cvt", "cvt-centroids"], required=True)
    p.add_argument("--evals", type=int, default=1_000_000)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--centroids", type=int, default=10_000)
    p.add_argument("--samples", type=int, default=100_000)
    if kmeans_iterations:
        p.add_argument("--kmeans-iterations", type=int, default=10)
    p.add_argument("--centroids-file", default=f"centroids-{library}.npy")
    p.add_argument("--task", choices=sorted(TASKS), default="rastrigin")
    p.add_argument("--operator", choices=["gaussian", "iso-line"], default="gaussian")
    args = p.parse_args()
    args.task = TASKS[args.task]
    if args.algorithm == "cvt-centroids":
        make_centroids(args)
    else:
        run(args)

"""What every peer runner shares: the Rastrigin task (docs/fidelity.md) and one result line.

The task: genotype g in [0,1]^20, x = -5.12 + 10.24 g, objective
f = -[10 N + sum(x^2 - 10 cos 2 pi x)] (maximum 0), measures (g0, g1) on a 100 x 100 grid or
all 20 genes for CVT. The operator: each gene mutated with probability 0.10 by a Gaussian of
SD 0.05, clamped to [0, 1]. QD-score offset -2000 for everyone.
"""
import argparse
import json
import sys

import numpy as np

DIMENSIONS = 20
GRID = (100, 100)
BATCH = 400
INITIAL = 2000
MUTATION_RATE = 0.10
MUTATION_SD = 0.05
QD_OFFSET = -2000.0


def rastrigin(genotypes):
    """Objective of each row of a (n, 20) array in [0,1], computed in float32 as qdmeta's own task
    and QDax's jax do (numpy's float32 cosine is vectorised: about 4x faster than float64's)."""
    x = np.float32(-5.12) + np.float32(10.24) * np.asarray(genotypes, dtype=np.float32)
    terms = x * x - np.float32(10.0) * np.cos(np.float32(2.0 * np.pi) * x)
    return -(np.float32(10.0 * x.shape[1]) + np.sum(terms, axis=1))


def mutate(parents, rng):
    """The paper's operator on a (n, 20) array of parents."""
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


def qd_score(objectives):
    """Sum over elites of (objective - offset): the same formula for every library."""
    return float(np.sum(np.asarray(objectives, dtype=np.float64) - QD_OFFSET))


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
    args = p.parse_args()
    if args.algorithm == "cvt-centroids":
        make_centroids(args)
    else:
        run(args)

"""qdmeta driven from Python: MAP-Elites or CVT-MAP-Elites on the shared numpy task (common.py),
an ask/tell loop as a pyribs user writes it, with qdmeta's operator (the same as the peers').
Prints one JSON line. The module is the one `make build` puts in build/python.
"""
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "build" / "python"))
import qdmeta  # noqa: E402

import common  # noqa: E402


def evaluate(genotypes):
    """The shared task: the objective, and the genes as base features (the grid reads the first two)."""
    return common.rastrigin(genotypes), genotypes


def config(args):
    c = {"seed": args.seed,
         "mutation": {"kind": "gaussian", "rate": common.MUTATION_RATE, "sigma": common.MUTATION_SD},
         "map_elites": {"batch_size": common.BATCH, "initial_population": common.INITIAL}}
    if args.algorithm == "map-elites":
        c.update(algorithm="map-elites", archive={"bins": list(common.GRID), "measures": [0, 1]})
    else:
        # qdmeta's own k-means over the peers' sample count, from the cache the CLI's run filled
        # (peers.py's work folder, beside the centroids file).
        c.update(algorithm="cvt-map-elites",
                 cvt={"centroids": args.centroids, "samples": args.samples, "init": "random",
                      "init_samples": args.samples, "method": "lloyd", "iterations": args.kmeans_iterations,
                      "seed": 1, "cache_dir": str(Path(args.centroids_file).parent / "centroid-cache")})
    return c


def make_centroids(args):
    """The CLI's centroids, loaded from its cache (peers.py makes them first); a marker file
    tells peers.py that this peer's CVT runs can go."""
    task = qdmeta.Task(evaluate, common.DIMENSIONS, common.DIMENSIONS, name="numpy-rastrigin")
    start = time.perf_counter()
    qdmeta.Algorithm(config(args), task=task).ask()
    wall = time.perf_counter() - start
    np.save(args.centroids_file, np.zeros(1))
    common.emit(library="qdmeta-py", version=qdmeta.__version__, algorithm="cvt-centroids", evals=0, wall_s=wall,
                note="the CLI's centroids, read from its cache")


def run(args):
    task = qdmeta.Task(evaluate, genotype_size=common.DIMENSIONS, base_feature_size=common.DIMENSIONS,
                       name="numpy-rastrigin", qd_offset=common.QD_OFFSET)
    algorithm = qdmeta.Algorithm(config(args), task=task)
    sizes = common.batches(args.evals)
    start = time.perf_counter()
    evals = 0
    for _ in sizes:
        genotypes = algorithm.ask()
        algorithm.tell(*evaluate(genotypes))
        evals += len(genotypes)
    wall = time.perf_counter() - start
    objectives = algorithm.data()["objective"]
    common.emit(library="qdmeta-py", version=qdmeta.__version__, algorithm=args.algorithm, evals=evals, wall_s=wall,
                num_elites=len(objectives), qd_score=common.qd_score(objectives), obj_max=float(np.max(objectives)),
                note="Python ask/tell loop, numpy task")


if __name__ == "__main__":
    common.main(__doc__, "qdmeta-python", make_centroids, run, kmeans_iterations=True)

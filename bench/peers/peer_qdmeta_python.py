"""qdmeta driven from Python: MAP-Elites or CVT-MAP-Elites on a shared numpy task (common.py),
an ask/tell loop as a pyribs user writes it, with qdmeta's operators (the same as the peers').
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


def make_task(task):
    """The shared task: the objective, and the CVT measures as base features (the grid reads the
    first two: Rastrigin's g0, g1, the arm's x, y)."""
    def evaluate(genotypes):
        objectives, _, base = task.evaluate(genotypes)
        return objectives, base

    return evaluate, qdmeta.Task(evaluate, genotype_size=task.genes, base_feature_size=task.cvt_dimensions,
                                 name=f"numpy-{task.name}", qd_offset=task.qd_offset)


def config(args):
    if args.operator == "gaussian":
        mutation = {"kind": "gaussian", "rate": common.MUTATION_RATE, "sigma": common.MUTATION_SD}
    else:
        mutation = {"kind": "iso-line", "iso_sigma": common.ISO_SIGMA, "line_sigma": common.LINE_SIGMA}
    c = {"seed": args.seed, "mutation": mutation,
         "map_elites": {"batch_size": common.BATCH, "initial_population": common.INITIAL}}
    if args.algorithm == "map-elites":
        c.update(algorithm="map-elites", archive={"bins": list(common.GRID), "measures": [0, 1]})
    else:
        # qdmeta's own k-means over the peers' sample count, from the cache the CLI's run filled
        # (peers.py's work folder, beside the centroids file); cvt.search is its default, auto.
        c.update(algorithm="cvt-map-elites",
                 cvt={"centroids": args.centroids, "samples": args.samples, "init": "random",
                      "init_samples": args.samples, "method": "lloyd", "iterations": args.kmeans_iterations,
                      "seed": 1, "cache_dir": str(Path(args.centroids_file).parent / "centroid-cache" / args.task.name)})
    return c


def make_centroids(args):
    """The CLI's centroids, loaded from its cache (peers.py makes them first); a marker file
    tells peers.py that this peer's CVT runs can go."""
    _, task = make_task(args.task)
    start = time.perf_counter()
    qdmeta.Algorithm(config(args), task=task).ask()
    wall = time.perf_counter() - start
    np.save(args.centroids_file, np.zeros(1))
    common.emit(library="qdmeta-py", version=qdmeta.__version__, algorithm="cvt-centroids", evals=0, wall_s=wall,
                note="the CLI's centroids, read from its cache")


def run(args):
    evaluate, task = make_task(args.task)
    algorithm = qdmeta.Algorithm(config(args), task=task)
    sizes = common.batches(args.evals)
    start = time.perf_counter()
    evals = 0
    task_s = 0.0  # the numpy task's share of the loop
    for _ in sizes:
        genotypes = algorithm.ask()
        task_start = time.perf_counter()
        evaluated = evaluate(genotypes)
        task_s += time.perf_counter() - task_start
        algorithm.tell(*evaluated)
        evals += len(genotypes)
    wall = time.perf_counter() - start
    objectives = algorithm.data()["objective"]
    common.emit(library="qdmeta-py", version=qdmeta.__version__, algorithm=args.algorithm, evals=evals, wall_s=wall,
                num_elites=len(objectives), qd_score=common.qd_score(objectives, args.task.qd_offset),
                obj_max=float(np.max(objectives)), task_s=task_s, note="Python ask/tell loop, numpy task")


if __name__ == "__main__":
    common.main(__doc__, "qdmeta-python", make_centroids, run, kmeans_iterations=True)

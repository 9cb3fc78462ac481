"""pyribs runner: MAP-Elites or CVT-MAP-Elites on a shared task (common.py) through pyribs's
public API (an archive, an emitter, a Scheduler). Prints one JSON line.

pyribs's GaussianEmitter perturbs every gene, so PaperEmitter below implements the Gaussian
operator of common.py through the documented EmitterBase interface: uniform parents from the
archive, each gene mutated with probability 0.10 by N(0, 0.05^2), clamped to [0, 1]. iso+line
is pyribs's own IsoLineEmitter (iso_sigma 0.01, line_sigma 0.2, its defaults), given the initial
random solutions as its `initial_solutions`.
"""
import time

import numpy as np
import ribs
from ribs.archives import CVTArchive, GridArchive, k_means_centroids
from ribs.emitters import EmitterBase, IsoLineEmitter
from ribs.schedulers import Scheduler

import common


class PaperEmitter(EmitterBase):
    """First ask: the initial random solutions; then batches of mutated uniform parents."""

    def __init__(self, archive, genes, sizes, seed):
        super().__init__(archive, solution_dim=genes, bounds=[(0.0, 1.0)] * genes, lower_bounds=None,
                         upper_bounds=None)
        self._genes = genes
        self._sizes = iter(sizes)
        self._rng = np.random.default_rng(seed)
        self._first = True

    def ask(self):
        n = next(self._sizes)
        if self._first:
            self._first = False
            return self._rng.random((n, self._genes))
        parents = self.archive.sample_elites(n)["solution"]
        return common.mutate(parents, self._rng)


def make_centroids(args):
    start = time.perf_counter()
    centroids, _ = k_means_centroids(centroids=args.centroids, ranges=[(0.0, 1.0)] * args.task.cvt_dimensions,
                                     samples=args.samples, seed=args.seed,
                                     k_means_kwargs={"max_iter": args.kmeans_iterations})
    wall = time.perf_counter() - start
    np.save(args.centroids_file, centroids)
    common.emit(library="pyribs", version=ribs.__version__, algorithm="cvt-centroids", evals=0, wall_s=wall,
                note=f"k_means_centroids: {args.samples} uniform samples, sklearn k_means "
                     f"(pyribs defaults: init=random, n_init=1, lloyd), max_iter={args.kmeans_iterations}")


def run(args):
    task = args.task
    sizes = common.batches(args.evals)
    if args.algorithm == "map-elites":
        archive = GridArchive(solution_dim=task.genes, dims=common.GRID, ranges=[(0.0, 1.0)] * 2,
                              qd_score_offset=task.qd_offset, seed=args.seed)
        measures_of = lambda evaluated: evaluated[1]  # noqa: E731
    else:
        archive = CVTArchive(solution_dim=task.genes, centroids=np.load(args.centroids_file),
                             ranges=[(0.0, 1.0)] * task.cvt_dimensions, qd_score_offset=task.qd_offset,
                             seed=args.seed)
        measures_of = lambda evaluated: evaluated[2]  # noqa: E731
    if args.operator == "gaussian":
        emitter = PaperEmitter(archive, task.genes, sizes, args.seed)
    else:
        initial = np.random.default_rng(args.seed).random((common.INITIAL, task.genes))
        emitter = IsoLineEmitter(archive, iso_sigma=common.ISO_SIGMA, line_sigma=common.LINE_SIGMA,
                                 initial_solutions=initial, bounds=[(0.0, 1.0)] * task.genes,
                                 batch_size=common.BATCH, seed=args.seed)
    scheduler = Scheduler(archive, [emitter])
    start = time.perf_counter()
    evals = 0
    task_s = 0.0  # the numpy task's share of the loop
    for _ in sizes:
        solutions = scheduler.ask()
        task_start = time.perf_counter()
        evaluated = task.evaluate(solutions)
        task_s += time.perf_counter() - task_start
        scheduler.tell(evaluated[0], measures_of(evaluated))
        evals += len(solutions)
    wall = time.perf_counter() - start
    objectives = archive.data("objective")
    note = "IsoLineEmitter" if args.operator == "iso-line" else ""
    if args.algorithm == "cvt":
        note = "; ".join(filter(None, [note, "CVTArchive nearest_neighbors=scipy_kd_tree (default)"]))
    common.emit(library="pyribs", version=ribs.__version__, algorithm=args.algorithm, evals=evals, wall_s=wall,
                num_elites=len(archive), qd_score=common.qd_score(objectives, task.qd_offset),
                obj_max=float(np.max(objectives)), task_s=task_s, note=note)


if __name__ == "__main__":
    common.main(__doc__, "pyribs", make_centroids, run, kmeans_iterations=True)

"""pyribs runner: MAP-Elites or CVT-MAP-Elites on the shared task through pyribs's public API
(an archive, a custom emitter, a Scheduler). Prints one JSON line.

pyribs's GaussianEmitter perturbs every gene, so PaperEmitter below implements the paper's
operator through the documented EmitterBase interface: uniform parents from the archive,
each gene mutated with probability 0.10 by N(0, 0.05^2), clamped to [0, 1].
"""
import time

import numpy as np
import ribs
from ribs.archives import CVTArchive, GridArchive, k_means_centroids
from ribs.emitters import EmitterBase
from ribs.schedulers import Scheduler

import common


class PaperEmitter(EmitterBase):
    """First ask: the initial random solutions; then batches of mutated uniform parents."""

    def __init__(self, archive, sizes, seed):
        super().__init__(archive, solution_dim=common.DIMENSIONS, bounds=[(0.0, 1.0)] * common.DIMENSIONS,
                         lower_bounds=None, upper_bounds=None)
        self._sizes = iter(sizes)
        self._rng = np.random.default_rng(seed)
        self._first = True

    def ask(self):
        n = next(self._sizes)
        if self._first:
            self._first = False
            return self._rng.random((n, common.DIMENSIONS))
        parents = self.archive.sample_elites(n)["solution"]
        return common.mutate(parents, self._rng)


def make_centroids(args):
    start = time.perf_counter()
    centroids, _ = k_means_centroids(centroids=args.centroids, ranges=[(0.0, 1.0)] * common.DIMENSIONS,
                                     samples=args.samples, seed=args.seed,
                                     k_means_kwargs={"max_iter": args.kmeans_iterations})
    wall = time.perf_counter() - start
    np.save(args.centroids_file, centroids)
    common.emit(library="pyribs", version=ribs.__version__, algorithm="cvt-centroids", evals=0, wall_s=wall,
                note=f"k_means_centroids: {args.samples} uniform samples, sklearn k_means "
                     f"(pyribs defaults: init=random, n_init=1, lloyd), max_iter={args.kmeans_iterations}")


def run(args):
    sizes = common.batches(args.evals)
    if args.algorithm == "map-elites":
        archive = GridArchive(solution_dim=common.DIMENSIONS, dims=common.GRID, ranges=[(0.0, 1.0)] * 2,
                              qd_score_offset=common.QD_OFFSET, seed=args.seed)
        measures_of = lambda g: g[:, :2]  # noqa: E731
    else:
        archive = CVTArchive(solution_dim=common.DIMENSIONS, centroids=np.load(args.centroids_file),
                             ranges=[(0.0, 1.0)] * common.DIMENSIONS, qd_score_offset=common.QD_OFFSET,
                             seed=args.seed)
        measures_of = lambda g: g  # noqa: E731
    scheduler = Scheduler(archive, [PaperEmitter(archive, sizes, args.seed)])
    start = time.perf_counter()
    evals = 0
    for _ in sizes:
        solutions = scheduler.ask()
        scheduler.tell(common.rastrigin(solutions), measures_of(solutions))
        evals += len(solutions)
    wall = time.perf_counter() - start
    objectives = archive.data("objective")
    common.emit(library="pyribs", version=ribs.__version__, algorithm=args.algorithm, evals=evals, wall_s=wall,
                num_elites=len(archive), qd_score=common.qd_score(objectives), obj_max=float(np.max(objectives)),
                note=f"CVTArchive nearest_neighbors=scipy_kd_tree (default)" if args.algorithm == "cvt" else "")


if __name__ == "__main__":
    common.main(__doc__, "pyribs", make_centroids, run, kmeans_iterations=True)

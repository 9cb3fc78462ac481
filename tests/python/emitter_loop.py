"""The task and loop the emitter tests share: pyribs's sphere with a linear projection (CMA-ME's
first benchmark): objective 100 * (1 - sphere / worst sphere), shifted optimum at 5.12 * 0.4 per
gene, measures the sums of the two halves of the genes clipped to [-5.12, 5.12]."""
import numpy as np

import qdmeta

DIM = 10
BOUND = 5.12
HALF = DIM // 2


def sphere_projection(solutions):
    x = np.asarray(solutions, dtype=np.float64)
    shift = BOUND * 0.4
    worst = (BOUND + shift) ** 2 * x.shape[1]
    objective = 100.0 * (1.0 - np.sum((x - shift) ** 2, axis=1) / worst)
    clipped = np.where(np.abs(x) <= BOUND, x, BOUND / x)
    measures = np.stack([clipped[:, :HALF].sum(axis=1), clipped[:, HALF:].sum(axis=1)], axis=1)
    return objective.astype(np.float32), measures.astype(np.float32)


def grid(learning_rate=None, threshold_min=-np.inf, dims=(20, 20)):
    r = BOUND * HALF
    return qdmeta.GridArchive(solution_dim=DIM, dims=list(dims), ranges=[(-r, r), (-r, r)],
                              learning_rate=learning_rate, threshold_min=threshold_min)


def cma_mae(seed, learning_rate=0.01, emitters=3, batch_size=12):
    archive = grid(learning_rate, 0.0)
    return qdmeta.Scheduler(archive, [
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, ranker="imp", selection_rule="mu",
                                        restart_rule="basic", batch_size=batch_size, seed=seed * 100 + i)
        for i in range(emitters)])


def cma_me(seed, emitters=3, batch_size=12):
    """pyribs's CMA-ME: learning_rate 1, threshold_min -inf, the default 2imp / filter / no_improvement."""
    archive = grid()
    return qdmeta.Scheduler(archive, [
        qdmeta.EvolutionStrategyEmitter(archive, x0=np.zeros(DIM), sigma0=0.5, batch_size=batch_size,
                                        seed=seed * 100 + i)
        for i in range(emitters)])


def gaussian_map_elites(seed, emitters=3, batch_size=12):
    archive = grid()
    return qdmeta.Scheduler(archive, [
        qdmeta.GaussianEmitter(archive, sigma=0.5, x0=np.zeros(DIM), batch_size=batch_size, seed=seed * 100 + i)
        for i in range(emitters)])


def run(scheduler, iterations, log=None):
    """`iterations` ask/tell rounds; `log` (a list) gets each round's (objective, measures)."""
    for _ in range(iterations):
        objective, measures = sphere_projection(scheduler.ask())
        scheduler.tell(objective, measures)
        if log is not None:
            log.append((objective, measures))
    return scheduler

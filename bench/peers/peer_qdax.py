"""QDax runner: MAP-Elites or CVT-MAP-Elites on the shared task through QDax's public API
(MAPElites with a MixingEmitter, centroids from compute_euclidean_centroids or
compute_cvt_centroids), on CPU jax. Prints one JSON line.

The paper's operator goes in through the emitter's mutation-function argument. QDax stores
every archive as centroids and places a descriptor by its nearest centroid, so its 100 x 100
grid is the grid's 10,000 cell centres (the same cells as a grid archive). The run is one
jit-compiled lax.scan over the batches; its wall time includes compilation, which a user
pays too (reported separately in the note).
"""
import functools
import time

import jax
import jax.numpy as jnp
import numpy as np
import qdax
from qdax.core.containers.mapelites_repertoire import compute_cvt_centroids, compute_euclidean_centroids
from qdax.core.emitters.standard_emitters import MixingEmitter
from qdax.core.map_elites import MAPElites

import common


def paper_mutation(genotypes, key):
    mask_key, noise_key = jax.random.split(key)
    mask = jax.random.bernoulli(mask_key, common.MUTATION_RATE, genotypes.shape)
    noise = common.MUTATION_SD * jax.random.normal(noise_key, genotypes.shape)
    return jnp.clip(genotypes + jnp.where(mask, noise, 0.0), 0.0, 1.0)


def scoring(genotypes, key, measures_dims):
    del key
    x = -5.12 + 10.24 * genotypes
    fitness = -(10.0 * x.shape[1] + jnp.sum(x * x - 10.0 * jnp.cos(2.0 * jnp.pi * x), axis=1))
    return fitness, genotypes[:, :measures_dims], {}


def metrics(repertoire):
    return {}


def rastrigin_only(args):
    if args.task.name != "rastrigin" or args.operator != "gaussian":
        raise SystemExit("the QDax runner has Rastrigin with the Gaussian operator only")


def make_centroids(args):
    rastrigin_only(args)
    start = time.perf_counter()
    centroids = compute_cvt_centroids(num_descriptors=common.DIMENSIONS, num_init_cvt_samples=args.samples,
                                      num_centroids=args.centroids, minval=0.0, maxval=1.0,
                                      key=jax.random.key(args.seed))
    centroids = np.asarray(centroids)
    wall = time.perf_counter() - start
    np.save(args.centroids_file, centroids)
    common.emit(library="qdax", version=qdax.__version__, algorithm="cvt-centroids", evals=0, wall_s=wall,
                note=f"compute_cvt_centroids: {args.samples} uniform samples, sklearn KMeans "
                     "(k-means++, n_init=1, its default max_iter=300; iterations cannot be set)")


def run(args):
    rastrigin_only(args)
    sizes = common.batches(args.evals)
    if args.algorithm == "map-elites":
        centroids = compute_euclidean_centroids(grid_shape=common.GRID, minval=0.0, maxval=1.0)
        measures_dims = 2
    else:
        centroids = jnp.asarray(np.load(args.centroids_file))
        measures_dims = common.DIMENSIONS
    if any(s != common.BATCH for s in sizes[1:]):
        raise SystemExit("QDax's scan needs whole batches: use --evals = 2000 + 400 k")
    emitter = MixingEmitter(mutation_fn=paper_mutation, variation_fn=None, variation_percentage=0.0,
                            batch_size=common.BATCH)
    algorithm = MAPElites(scoring_function=functools.partial(scoring, measures_dims=measures_dims),
                          emitter=emitter, metrics_function=metrics)
    key = jax.random.key(args.seed)
    key, init_key, run_key = jax.random.split(key, 3)
    start = time.perf_counter()
    initial = jax.random.uniform(init_key, (common.INITIAL, common.DIMENSIONS))
    repertoire, emitter_state, _ = algorithm.init(initial, centroids, run_key)
    scan = jax.jit(lambda carry: jax.lax.scan(algorithm.scan_update, carry, None, length=len(sizes) - 1))
    compiled = scan.lower((repertoire, emitter_state, key)).compile()
    compile_s = time.perf_counter() - start
    (repertoire, _, _), _ = compiled((repertoire, emitter_state, key))
    fitnesses = np.asarray(jax.block_until_ready(repertoire.fitnesses)).reshape(-1)
    wall = time.perf_counter() - start
    filled = fitnesses[np.isfinite(fitnesses)]
    common.emit(library="qdax", version=qdax.__version__, algorithm=args.algorithm, evals=sum(sizes), wall_s=wall,
                num_elites=int(filled.size), qd_score=common.qd_score(filled), obj_max=float(np.max(filled)),
                note=f"jax {jax.__version__} on {jax.devices()[0].platform}; {compile_s:.1f} s of the wall is "
                     "initialisation and jit compilation")


if __name__ == "__main__":
    common.main(__doc__, "qdax", make_centroids, run)

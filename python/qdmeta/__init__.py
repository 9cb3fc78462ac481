"""qdmeta: Quality-Diversity Meta-Evolution (QD-Meta), CVT-MAP-Elites, AURORA and MAP-Elites.

The C++ library behind the `qdmeta` command line, from Python:

- ``Task(function, genotype_size, base_feature_size, name)``: a task written in numpy;
  ``Task.builtin({"name": "rastrigin", ...})`` a built-in one.
- ``MetaObjective(function, name)``: QD-Meta's meta-fitness written in numpy.
- ``GridArchive``, ``CvtArchive`` (with ``cvt_centroids``), ``UnstructuredArchive``: iterated
  over, ``retrieve(measures)``, ``sample_elites(n)``, as pyribs's archives.
- ``EvolutionStrategyEmitter``, ``GaussianEmitter``, ``IsoLineEmitter``, ``Scheduler`` and
  ``BanditScheduler``: CMA-ME and CMA-MAE's ask/tell loop with pyribs's names, over an archive
  made with ``learning_rate`` and ``threshold_min``.
- ``Algorithm(config, task=..., meta_objective=..., variation=...)``: any registered algorithm,
  driven by ``ask()``/``tell()`` or ``step()``; ``archive`` and ``retrieve(measures)`` show its
  archive; ``variation`` gives MAP-Elites a variation operator written in numpy.

Archives, tasks, meta-objectives and algorithms (between steps) pickle and deep-copy.
- ``run(config, out_dir, ...)`` and ``resume(out_dir, ...)``: run directories as ``qdmeta run``
  writes them.
- ``ProximityArchive``, ``SlidingBoundariesArchive``: novelty search's archive and Fontaine et
  al.'s sliding-boundaries grid, as pyribs's.
- ``cqd_score(archive, ...)``: the CQD score of an archive, as pyribs's ``cqd_score``.
- ``qdmeta.visualize`` (imported on its own, as it needs matplotlib): heatmaps and parallel-axes
  plots of an archive.

Configs are dicts with the keys of the TOML configs (docs/config.md). docs/python.md is the
tutorial.
"""

from ._qdmeta import (  # noqa: F401  (the public names)
    Algorithm,
    ArchiveStats,
    BanditScheduler,
    CvtArchive,
    Error,
    EvolutionStrategyEmitter,
    GaussianEmitter,
    GridArchive,
    InputError,
    IsoLineEmitter,
    MetaObjective,
    ProximityArchive,
    SlidingBoundariesArchive,
    Scheduler,
    Task,
    UnstructuredArchive,
    __version__,
    algorithms,
    build_info,
    cvt_centroids,
    resume,
    run,
    tasks,
)

import numpy as _numpy

from ._cqd import CQDScoreResult, cqd_score  # noqa: F401

from . import _arguments, _numpy_check, _pyribs_names, _qdmeta

_numpy_check.check(_qdmeta, _numpy)
_pyribs_names.add_pyribs_names((GridArchive, CvtArchive, UnstructuredArchive), GridArchive)

for _archive in (GridArchive, CvtArchive, UnstructuredArchive):
    _arguments.shorten_argument_errors(_archive, "__init__", "add", "retrieve", "retrieve_single", "sample_elites")
_arguments.shorten_argument_errors(ProximityArchive, "__init__", "add", "compute_novelty", "index_of", "data")
_arguments.shorten_argument_errors(SlidingBoundariesArchive, "__init__", "add", "index_of", "data")
_arguments.shorten_argument_errors(GridArchive, "index_of")
_arguments.shorten_argument_errors(CvtArchive, "index_of")
_arguments.shorten_argument_errors(Algorithm, "__init__", "tell", "tell_jobs", "retrieve", "step", "run")
_arguments.shorten_argument_errors(Task, "__init__", "evaluate")
_arguments.shorten_argument_errors(EvolutionStrategyEmitter, "__init__")
_arguments.shorten_argument_errors(GaussianEmitter, "__init__")
_arguments.shorten_argument_errors(IsoLineEmitter, "__init__")
_arguments.shorten_argument_errors(Scheduler, "__init__", "tell")
_arguments.shorten_argument_errors(BanditScheduler, "__init__", "tell")
run = _arguments.check_paths(run, "run", out_dir=1)
resume = _arguments.check_paths(resume, "resume", out_dir=0)
cvt_centroids = _arguments.check_paths(cvt_centroids, "cvt_centroids", cache_dir=4)
Algorithm.run = _arguments.check_paths(Algorithm.run, "Algorithm.run", out_dir=2)  # self, budget, out_dir

__all__ = [
    "Algorithm",
    "ArchiveStats",
    "BanditScheduler",
    "CQDScoreResult",
    "CvtArchive",
    "Error",
    "EvolutionStrategyEmitter",
    "GaussianEmitter",
    "GridArchive",
    "InputError",
    "IsoLineEmitter",
    "MetaObjective",
    "ProximityArchive",
    "Scheduler",
    "SlidingBoundariesArchive",
    "Task",
    "UnstructuredArchive",
    "__version__",
    "algorithms",
    "build_info",
    "cqd_score",
    "cvt_centroids",
    "resume",
    "run",
    "tasks",
]

"""The CQD score of an archive, with pyribs's arguments and result (qdmeta.cqd_score)."""

from __future__ import annotations

import dataclasses
from typing import Any

import numpy as np

from . import _qdmeta


@dataclasses.dataclass
class CQDScoreResult:
    """What :func:`cqd_score` computed, and with what (pyribs's fields)."""

    iterations: int
    mean: float  # the mean score over the iterations: the number most users want
    scores: np.ndarray  # (iterations,) one score per set of target points
    target_points: np.ndarray  # (iterations, n, measure_dim), a copy of those given
    penalties: np.ndarray  # the penalties used, a copy
    obj_min: float
    obj_max: float
    dist_max: float
    dist_ord: Any


def _norm_order(dist_ord):
    """numpy.linalg.norm's ``ord`` for vectors, as the p of a p-norm (None: 2)."""
    if dist_ord is None:
        return 2.0
    if isinstance(dist_ord, str) or isinstance(dist_ord, bool):
        raise _qdmeta.InputError(
            f"cqd_score: dist_ord {dist_ord!r} is not a vector norm's order: use a number >= 1 or numpy.inf"
        )
    order = float(dist_ord)
    if not order >= 1.0:  # NaN too
        raise _qdmeta.InputError(f"cqd_score: dist_ord ({dist_ord}) must be a norm's order: >= 1, or numpy.inf")
    return order


def cqd_score(archive, *, iterations, target_points, penalties, obj_min, obj_max, dist_max, dist_ord=None):
    """The Continuous Quality-Diversity score of ``archive`` (Kent et al., GECCO 2022).

    For each of ``iterations`` sets of target points (``target_points``: (iterations, n,
    measure_dim)) and each penalty theta (``penalties``: a count, spread evenly over [0, 1], or
    the values), the score adds, per target, the best ``(f - obj_min) / (obj_max - obj_min) -
    theta * distance / dist_max`` over the archive's elites; ``dist_ord`` is the distance's norm
    order (None: Euclidean). As pyribs's ``cqd_score``, except that pyribs leaves ``obj_min``
    out of the normalisation (the two agree where obj_min = 0; docs/python.md).
    """
    target_points = np.array(target_points, dtype=np.float64)
    measure_dim = archive.measure_dim
    if target_points.ndim != 3 or target_points.shape[0] != iterations or target_points.shape[2] != measure_dim:
        raise _qdmeta.InputError(
            f"cqd_score: target_points must have shape ({iterations}, n, {measure_dim}) "
            f"(iterations, n, measure_dim), not {target_points.shape}"
        )
    if np.isscalar(penalties):
        if isinstance(penalties, (bool, np.bool_)) or int(penalties) != penalties or penalties < 1:
            raise _qdmeta.InputError(f"cqd_score: penalties ({penalties}) must be a count >= 1 or a 1-D array")
        penalties = np.array(_qdmeta._evenly_spaced_penalties(int(penalties)), dtype=np.float64)
    else:
        penalties = np.array(penalties, dtype=np.float64)
        if penalties.ndim != 1:
            raise _qdmeta.InputError(f"cqd_score: penalties must be a count or a 1-D array, not of shape {penalties.shape}")
    objectives = np.asarray(archive.data("objective"), dtype=np.float64)
    measures = np.asarray(archive.data("measures"), dtype=np.float64)
    scores, mean = _qdmeta._cqd_score(
        objectives,
        measures,
        measure_dim,
        target_points,
        int(iterations),
        penalties,
        float(obj_min),
        float(obj_max),
        float(dist_max),
        _norm_order(dist_ord),
    )
    return CQDScoreResult(
        iterations=int(iterations),
        mean=float(mean),
        scores=scores,
        target_points=target_points,
        penalties=penalties,
        obj_min=obj_min,
        obj_max=obj_max,
        dist_max=dist_max,
        dist_ord=dist_ord,
    )

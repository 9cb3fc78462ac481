"""Pictures of one archive: a grid heatmap, a CVT (Voronoi) heatmap and a parallel-axes plot.

numpy and matplotlib only, and no qdmeta object: `qdmeta report` draws its final archives with
these functions, and the Python module's qdmeta.visualize hands them an archive's arrays (the
module carries a copy of this file as qdmeta/_archive_plots.py).

Colours: every occupied cell is drawn in cmap(norm(objective)), norm linear over [vmin, vmax]
(default: the smallest and largest objective shown); an empty cell is left in the axes' colour.
"""
import numpy as np
from matplotlib import colors as mcolors
from matplotlib import tri as mtri
from matplotlib.cm import ScalarMappable
from matplotlib.collections import LineCollection, PolyCollection


class PlotError(ValueError):
    """An archive these plots cannot draw (wrong dimension, mismatched arrays)."""


def _bounds(value, dims, what):
    """A scalar or one value per measure, as a float array of length dims."""
    array = np.broadcast_to(np.asarray(value, dtype=float), (dims,)) if np.ndim(value) == 0 else np.asarray(value, float)
    if array.shape != (dims,) or not np.all(np.isfinite(array)):
        raise PlotError(f"{what} must be one finite number or {dims} of them, got {value!r}")
    return array


def _norm(objective, vmin, vmax):
    finite = np.asarray(objective, dtype=float)
    low = float(np.min(finite)) if vmin is None and finite.size else (0.0 if vmin is None else float(vmin))
    high = float(np.max(finite)) if vmax is None and finite.size else (1.0 if vmax is None else float(vmax))
    if high <= low:  # one value (or one elite): a non-empty range centred on it
        low, high = low - 0.5, high + 0.5
    return mcolors.Normalize(vmin=low, vmax=high)


def _checked(index, objective, what):
    index = np.asarray(index, dtype=np.int64).ravel()
    objective = np.asarray(objective, dtype=float).ravel()
    if index.shape != objective.shape:
        raise PlotError(f"{what}: {index.size} indices against {objective.size} objectives")
    return index, objective


def _scalar_mappable(cmap, norm):
    return ScalarMappable(norm=norm, cmap=cmap)


def _add_colorbar(ax, cmap, norm, label):
    bar = ax.figure.colorbar(_scalar_mappable(cmap, norm), ax=ax)
    bar.set_label(label)
    return bar


def grid_heatmap(ax, index, objective, dims, lower=0.0, upper=1.0, *, cmap="viridis", vmin=None, vmax=None,
                 colorbar=True, measure_names=("measure 0", "measure 1")):
    """A 1-D or 2-D grid archive: cell `index` (row-major over dims, as GridArchive.index_of
    numbers them) in the colour of its objective; measure 0 along x, measure 1 along y.
    Returns the AxesImage."""
    dims = [int(d) for d in np.atleast_1d(dims)]
    if len(dims) not in (1, 2) or min(dims) < 1:
        raise PlotError(f"a grid heatmap draws 1 or 2 measures, the archive has dims {dims}")
    index, objective = _checked(index, objective, "grid heatmap")
    cells = int(np.prod(dims))
    if index.size and (index.min() < 0 or index.max() >= cells):
        raise PlotError(f"grid heatmap: cell indices must lie in [0, {cells}), got {index.min()}..{index.max()}")
    low, high = _bounds(lower, len(dims), "lower"), _bounds(upper, len(dims), "upper")
    heat = np.full(cells, np.nan)
    heat[index] = objective
    if len(dims) == 1:
        image, extent = heat.reshape(1, dims[0]), (low[0], high[0], 0.0, 1.0)
    else:
        image, extent = heat.reshape(dims).T, (low[0], high[0], low[1], high[1])
    norm = _norm(objective, vmin, vmax)
    drawn = ax.imshow(np.ma.masked_invalid(image), origin="lower", extent=extent, aspect="auto", cmap=cmap, norm=norm,
                      interpolation="nearest")
    ax.set_xlabel(measure_names[0])
    if len(dims) == 2:
        ax.set_ylabel(measure_names[1])
    else:
        ax.set_yticks([])
    if colorbar:
        _add_colorbar(ax, cmap, norm, "objective")
    return drawn


def voronoi_cells(centroids, lower, upper):
    """The Voronoi cell of each 2-D centroid, clipped to the box [lower, upper]^2, as a list of
    (k, 2) vertex arrays in counter-clockwise order. Mirroring every centroid across the box's
    four sides makes the sides bisectors, so each original cell comes out closed and clipped."""
    points = np.asarray(centroids, dtype=float)
    if points.ndim != 2 or points.shape[1] != 2 or len(points) < 1:
        raise PlotError(f"a CVT heatmap draws 2-D centroids, got an array of shape {points.shape}")
    low, high = _bounds(lower, 2, "lower"), _bounds(upper, 2, "upper")
    if np.any(points < low) or np.any(points > high):
        raise PlotError(f"every centroid must lie inside the box {low.tolist()}..{high.tolist()}")
    n = len(points)
    mirrors = [points]
    for axis in (0, 1):
        for side in (low[axis], high[axis]):
            m = points.copy()
            m[:, axis] = 2 * side - m[:, axis]
            mirrors.append(m)
    every = np.concatenate(mirrors)
    if n == 1:
        return [np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]])]
    triangulation = mtri.Triangulation(every[:, 0], every[:, 1])
    triangles = triangulation.triangles
    a, b, c = every[triangles[:, 0]], every[triangles[:, 1]], every[triangles[:, 2]]
    d = 2 * (a[:, 0] * (b[:, 1] - c[:, 1]) + b[:, 0] * (c[:, 1] - a[:, 1]) + c[:, 0] * (a[:, 1] - b[:, 1]))
    sa, sb, sc = (a ** 2).sum(1), (b ** 2).sum(1), (c ** 2).sum(1)
    centres = np.stack([(sa * (b[:, 1] - c[:, 1]) + sb * (c[:, 1] - a[:, 1]) + sc * (a[:, 1] - b[:, 1])) / d,
                        (sa * (c[:, 0] - b[:, 0]) + sb * (a[:, 0] - c[:, 0]) + sc * (b[:, 0] - a[:, 0])) / d], axis=1)
    vertex = triangles.ravel()
    triangle = np.repeat(np.arange(len(triangles)), 3)
    keep = vertex < n
    vertex, triangle = vertex[keep], triangle[keep]
    offset = centres[triangle] - points[vertex]
    angle = np.arctan2(offset[:, 1], offset[:, 0])
    order = np.lexsort((angle, vertex))
    vertex, triangle = vertex[order], triangle[order]
    starts = np.searchsorted(vertex, np.arange(n + 1))
    cells = [np.clip(centres[triangle[starts[i]:starts[i + 1]]], low, high) for i in range(n)]
    return cells


def cvt_heatmap(ax, centroids, index, objective, lower=0.0, upper=1.0, *, cmap="viridis", vmin=None, vmax=None,
                colorbar=True, edge_width=0.2, measure_names=("measure 0", "measure 1")):
    """A 2-D CVT archive: each centroid's Voronoi cell (clipped to the box) in the colour of its
    elite's objective; empty cells drawn as outlines. Returns the PolyCollection."""
    centroids = np.asarray(centroids, dtype=float)
    index, objective = _checked(index, objective, "CVT heatmap")
    if index.size and (index.min() < 0 or index.max() >= len(centroids)):
        raise PlotError(f"CVT heatmap: cell indices must lie in [0, {len(centroids)}), got {index.min()}..{index.max()}")
    cells = voronoi_cells(centroids, lower, upper)
    norm = _norm(objective, vmin, vmax)
    faces = np.zeros((len(cells), 4))  # transparent: the axes' colour shows through an empty cell
    faces[index] = _scalar_mappable(cmap, norm).to_rgba(objective)
    drawn = PolyCollection(cells, facecolors=faces, edgecolors=(0, 0, 0, 0.5), linewidths=edge_width)
    ax.add_collection(drawn)
    low, high = _bounds(lower, 2, "lower"), _bounds(upper, 2, "upper")
    ax.set_xlim(low[0], high[0])
    ax.set_ylim(low[1], high[1])
    ax.set_xlabel(measure_names[0])
    ax.set_ylabel(measure_names[1])
    if colorbar:
        _add_colorbar(ax, cmap, norm, "objective")
    return drawn


def parallel_axes(ax, measures, objective, *, lower=None, upper=None, cmap="viridis", vmin=None, vmax=None,
                  colorbar=True, sort_by_objective=True, measure_names=None):
    """Any archive: one line per elite through its measures (measure j at x = j), in the colour of
    its objective, the best drawn last (on top). lower/upper (default: each measure's range)
    scale every axis to [0, 1]. Returns the LineCollection."""
    measures = np.asarray(measures, dtype=float)
    objective = np.asarray(objective, dtype=float).ravel()
    if measures.ndim != 2 or measures.shape[0] != objective.size:
        raise PlotError(f"parallel axes: measures of shape {measures.shape} against {objective.size} objectives")
    dims = measures.shape[1]
    # An empty archive has no range of its own: its axes are drawn over [0, 1], with no lines.
    empty = measures.shape[0] == 0
    low = (np.zeros(dims) if empty else measures.min(axis=0)) if lower is None else _bounds(lower, dims, "lower")
    high = (np.ones(dims) if empty else measures.max(axis=0)) if upper is None else _bounds(upper, dims, "upper")
    span = np.where(high > low, high - low, 1.0)
    scaled = (measures - low) / span
    order = np.argsort(objective, kind="stable") if sort_by_objective else np.arange(objective.size)
    xs = np.arange(dims, dtype=float)
    segments = np.stack([np.broadcast_to(xs, scaled.shape), scaled], axis=2)[order]
    norm = _norm(objective, vmin, vmax)
    drawn = LineCollection(segments, colors=_scalar_mappable(cmap, norm).to_rgba(objective[order]), linewidths=0.5)
    ax.add_collection(drawn)
    ax.set_xlim(-0.05 * max(dims - 1, 1), (dims - 1) + 0.05 * max(dims - 1, 1))
    ax.set_ylim(-0.02, 1.02)
    names = measure_names or [f"measure {j}" for j in range(dims)]
    ax.set_xticks(xs, names)
    ax.set_ylabel("measure (scaled to its range)")
    if colorbar:
        _add_colorbar(ax, cmap, norm, "objective")
    return drawn

"""Plots of an archive with matplotlib, as pyribs's ribs.visualize draws them.

- ``grid_archive_heatmap(archive)``: a GridArchive of 1 or 2 measures, each cell in the colour of
  its elite's objective.
- ``cvt_archive_heatmap(archive)``: a CvtArchive of 2 measures, each centroid's Voronoi cell
  (clipped to the measure box) in the colour of its elite's objective.
- ``parallel_axes_plot(archive)``: any archive, one line per elite through its measures.

Each takes an archive, or anything with an ``archive`` attribute holding one (an Algorithm), and
draws on ``ax`` (default: the current axes); keyword arguments ``cmap``, ``vmin``, ``vmax`` and
``colorbar`` as in matplotlib. ``qdmeta report`` draws its final archives with the same code.
"""
import numpy as np

from . import _archive_plots
from ._archive_plots import PlotError

__all__ = ["PlotError", "cvt_archive_heatmap", "grid_archive_heatmap", "parallel_axes_plot"]


def _archive_of(archive):
    inner = getattr(archive, "archive", None)
    return archive if inner is None else inner


def _axes(ax):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt
    return plt.gca()


def grid_archive_heatmap(archive, ax=None, *, cmap="viridis", vmin=None, vmax=None, colorbar=True):
    """Heatmap of a GridArchive with 1 or 2 measures (measure 0 along x). Returns the image."""
    archive = _archive_of(archive)
    if not hasattr(archive, "dims"):
        raise PlotError(f"grid_archive_heatmap draws a GridArchive, not a {type(archive).__name__}")
    elites = archive.data()
    return _archive_plots.grid_heatmap(_axes(ax), elites["index"], elites["objective"], archive.dims,
                                       archive.lower_bounds, archive.upper_bounds, cmap=cmap, vmin=vmin, vmax=vmax,
                                       colorbar=colorbar)


def cvt_archive_heatmap(archive, ax=None, *, lower=0.0, upper=1.0, cmap="viridis", vmin=None, vmax=None,
                        colorbar=True):
    """Voronoi heatmap of a CvtArchive with 2 measures over the box [lower, upper] (every
    centroid must lie in it; qdmeta's CVT centroids live in [0, 1]^2). Returns the cells."""
    archive = _archive_of(archive)
    if not hasattr(archive, "centroids"):
        raise PlotError(f"cvt_archive_heatmap draws a CvtArchive, not a {type(archive).__name__}")
    elites = archive.data()
    return _archive_plots.cvt_heatmap(_axes(ax), np.asarray(archive.centroids), elites["index"], elites["objective"],
                                      lower, upper, cmap=cmap, vmin=vmin, vmax=vmax, colorbar=colorbar)


def parallel_axes_plot(archive, ax=None, *, lower=None, upper=None, cmap="viridis", vmin=None, vmax=None,
                       colorbar=True, sort_by_objective=True):
    """One line per elite through its measures, each measure scaled to [lower, upper] (default:
    its range over the elites). Any archive; an empty one draws its axes with no lines, as
    pyribs does. Returns the lines."""
    elites = _archive_of(archive).data()
    return _archive_plots.parallel_axes(_axes(ax), elites["measures"], elites["objective"], lower=lower, upper=upper,
                                        cmap=cmap, vmin=vmin, vmax=vmax, colorbar=colorbar,
                                        sort_by_objective=sort_by_objective)

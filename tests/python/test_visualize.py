"""qdmeta.visualize on the module's archives: the picture of a known archive (a cell's colour where
its elite is known, empty cells left blank, the colour range the objectives span) and the errors
for an archive a plot cannot draw."""
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402

import qdmeta  # noqa: E402
from qdmeta import visualize  # noqa: E402

VIRIDIS = matplotlib.colormaps["viridis"]


def colour_at(fig, ax, x, y):
    fig.canvas.draw()
    pixels = np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(int)
    px, py = ax.transData.transform((x, y))
    return pixels[pixels.shape[0] - 1 - int(round(py)), int(round(px))]


def viridis_rgb(fraction):
    return np.round(np.asarray(VIRIDIS(fraction)[:3]) * 255).astype(int)


def close(pixel, rgb):
    # Up to the image resampler's rounding (1-2 per channel); other colours here differ by far more.
    return np.max(np.abs(pixel - rgb)) <= 2


def test_the_grid_heatmap_shows_each_elite_in_its_cell():
    archive = qdmeta.GridArchive(solution_dim=2, dims=[10, 8], lower=-1.0, upper=1.0)
    assert archive.dims == [10, 8] and archive.lower_bounds == [-1.0, -1.0] and archive.upper_bounds == [1.0, 1.0]
    measures = np.array([[-0.95, -0.95], [0.05, 0.3], [0.95, 0.95]], dtype=np.float32)
    archive.add(np.zeros((3, 2)), np.array([0.0, 5.0, 10.0]), measures)
    fig, ax = plt.subplots(figsize=(4, 4), dpi=100)
    image = visualize.grid_archive_heatmap(archive, ax=ax, colorbar=False)
    assert image.get_array().shape == (8, 10)  # measure 1 along the rows
    assert (image.norm.vmin, image.norm.vmax) == (0.0, 10.0)
    for (x, y), fraction in zip(measures, [0.0, 0.5, 1.0]):
        assert close(colour_at(fig, ax, x, y), viridis_rgb(fraction)), (x, y)
    assert close(colour_at(fig, ax, -0.9, 0.9), np.array([255, 255, 255]))  # an empty cell
    plt.close(fig)


def test_the_cvt_heatmap_colours_the_cell_of_each_elite():
    centroids = qdmeta.cvt_centroids(2, cells=50, samples=5000, seed=3, cache_dir="")
    archive = qdmeta.CvtArchive(solution_dim=1, centroids=centroids)
    archive.add(np.zeros((2, 1)), np.array([-2.0, 2.0]), centroids[[4, 17]])
    fig, ax = plt.subplots(figsize=(5, 5), dpi=100)
    cells = visualize.cvt_archive_heatmap(archive, ax=ax, colorbar=False)
    assert len(cells.get_paths()) == 50
    assert close(colour_at(fig, ax, *centroids[4]), viridis_rgb(0.0))
    assert close(colour_at(fig, ax, *centroids[17]), viridis_rgb(1.0))
    plt.close(fig)


def test_parallel_axes_draw_every_elite_of_any_archive():
    archive = qdmeta.GridArchive(solution_dim=1, dims=[3, 3, 3])
    archive.add(np.zeros((4, 1)), np.array([1.0, 2.0, 3.0, 4.0]),
                np.array([[0.1, 0.1, 0.1], [0.5, 0.9, 0.1], [0.9, 0.5, 0.5], [0.1, 0.9, 0.9]], dtype=np.float32))
    fig, ax = plt.subplots()
    lines = visualize.parallel_axes_plot(archive, ax=ax, lower=0.0, upper=1.0, colorbar=False)
    segments = lines.get_segments()
    assert len(segments) == 4
    assert np.allclose(segments[-1][:, 1], [0.1, 0.9, 0.9])  # the best elite drawn last
    plt.close(fig)


def test_a_plot_that_cannot_draw_the_archive_says_why():
    fig, ax = plt.subplots()
    with pytest.raises(visualize.PlotError, match="1 or 2 measures"):
        visualize.grid_archive_heatmap(qdmeta.GridArchive(solution_dim=1, dims=[2, 2, 2]), ax=ax)
    with pytest.raises(visualize.PlotError, match="draws a CvtArchive, not a GridArchive"):
        visualize.cvt_archive_heatmap(qdmeta.GridArchive(solution_dim=1, dims=[2, 2]), ax=ax)
    three_d = qdmeta.CvtArchive(solution_dim=1, centroids=np.random.default_rng(1).random((5, 3)))
    with pytest.raises(visualize.PlotError, match="2-D centroids"):
        visualize.cvt_archive_heatmap(three_d, ax=ax)
    assert issubclass(visualize.PlotError, ValueError)
    plt.close(fig)


def test_the_parallel_axes_of_an_empty_archive_are_drawn_with_no_lines():
    for archive in (qdmeta.GridArchive(solution_dim=2, dims=[4, 4, 4]),
                    qdmeta.UnstructuredArchive(solution_dim=2, measure_dim=3)):
        fig, ax = plt.subplots()
        lines = visualize.parallel_axes_plot(archive, ax=ax)
        assert len(lines.get_segments()) == 0 and len(ax.get_xticks()) == 3
        assert ax.get_ylim() == (-0.02, 1.02)
        plt.close(fig)

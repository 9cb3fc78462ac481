"""tools/archive_plots.py: the Voronoi cells against a brute-force nearest-centroid search, and
the pictures themselves (size, colour range, the colour of a cell whose elite is known)."""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from matplotlib.path import Path  # noqa: E402

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "tools"))
import archive_plots  # noqa: E402

VIRIDIS = matplotlib.colormaps["viridis"]


def rendered(fig):
    """The figure's pixels (rows from the top, RGB in 0..255) after drawing."""
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].astype(int)


def pixel_at(fig, ax, x, y):
    """The RGB of the pixel under data point (x, y)."""
    pixels = rendered(fig)
    px, py = ax.transData.transform((x, y))
    return pixels[pixels.shape[0] - 1 - int(round(py)), int(round(px))]


def expected_rgb(value, low, high):
    return np.round(np.asarray(VIRIDIS((value - low) / (high - low))[:3]) * 255).astype(int)


def same_colour(pixel, rgb):
    """Equal up to the image resampler's rounding (adjacent entries of viridis's 256-colour table
    differ by up to 3 per channel; the colours of other values in these tests differ by far more)."""
    return np.max(np.abs(np.asarray(pixel) - rgb)) <= 2


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_each_voronoi_cell_holds_exactly_the_points_nearest_its_centroid(seed):
    rng = np.random.default_rng(seed)
    centroids = rng.random((200, 2)) * [2.0, 1.0] + [-1.0, 0.0]
    cells = archive_plots.voronoi_cells(centroids, [-1.0, 0.0], [1.0, 1.0])
    probes = rng.random((4000, 2)) * [2.0, 1.0] + [-1.0, 0.0]
    nearest = np.argmin(((probes[:, None, :] - centroids[None, :, :]) ** 2).sum(2), axis=1)
    inside = np.stack([Path(cell).contains_points(probes) for cell in cells], axis=1)
    assert np.array_equal(inside.sum(1), np.ones(len(probes))), "every probe lies in exactly one cell"
    assert np.array_equal(np.argmax(inside, axis=1), nearest)
    # The cells tile the box: their areas sum to its area (shoelace formula).
    areas = [0.5 * abs(np.dot(c[:, 0], np.roll(c[:, 1], 1)) - np.dot(c[:, 1], np.roll(c[:, 0], 1))) for c in cells]
    assert sum(areas) == pytest.approx(2.0, rel=1e-9)


def test_one_centroid_owns_the_whole_box_and_a_centroid_outside_is_refused():
    (cell,) = archive_plots.voronoi_cells([[0.3, 0.6]], 0.0, 1.0)
    assert sorted(map(tuple, cell)) == [(0, 0), (0, 1), (1, 0), (1, 1)]
    with pytest.raises(archive_plots.PlotError, match="inside the box"):
        archive_plots.voronoi_cells([[0.3, 1.5], [0.2, 0.2]], 0.0, 1.0)
    with pytest.raises(archive_plots.PlotError, match="2-D centroids"):
        archive_plots.voronoi_cells(np.zeros((4, 3)), 0.0, 1.0)


def test_a_grid_heatmap_colours_each_cell_by_its_elite_and_leaves_empty_cells_blank():
    fig, ax = plt.subplots(figsize=(4, 4), dpi=100)
    dims = [4, 5]  # cell = i0 * 5 + i1, measure 0 along x
    index = np.array([0, 7, 19])  # (0, 0), (1, 2), (3, 4)
    objective = np.array([-10.0, -4.0, 2.0])
    image = archive_plots.grid_heatmap(ax, index, objective, dims, lower=[0, 10], upper=[4, 20], colorbar=False)
    assert image.get_array().shape == (5, 4)
    assert image.norm.vmin == -10.0 and image.norm.vmax == 2.0
    for (i0, i1), value in zip([(0, 0), (1, 2), (3, 4)], objective):
        x, y = i0 + 0.5, 10 + 2 * (i1 + 0.5)
        assert same_colour(pixel_at(fig, ax, x, y), expected_rgb(value, -10.0, 2.0))
    assert np.array_equal(pixel_at(fig, ax, 2.5, 11.0), [255, 255, 255]), "cell (2, 0) is empty: the axes' white"
    plt.close(fig)


def test_a_grid_heatmap_refuses_three_measures_and_cells_out_of_range():
    fig, ax = plt.subplots()
    with pytest.raises(archive_plots.PlotError, match="1 or 2 measures"):
        archive_plots.grid_heatmap(ax, [0], [1.0], [2, 2, 2])
    with pytest.raises(archive_plots.PlotError, match=r"\[0, 4\)"):
        archive_plots.grid_heatmap(ax, [4], [1.0], [2, 2])
    with pytest.raises(archive_plots.PlotError, match="2 indices against 1"):
        archive_plots.grid_heatmap(ax, [0, 1], [1.0], [2, 2])
    plt.close(fig)


def test_a_cvt_heatmap_colours_a_known_elites_cell_and_spans_the_colour_range():
    rng = np.random.default_rng(7)
    centroids = rng.random((60, 2))
    index = np.arange(0, 60, 2)
    objective = np.linspace(-5.0, 5.0, index.size)
    fig, ax = plt.subplots(figsize=(5, 5), dpi=100)
    cells = archive_plots.cvt_heatmap(ax, centroids, index, objective, colorbar=False, edge_width=0.0)
    faces = cells.get_facecolors()
    assert faces.shape == (60, 4)
    assert np.all(faces[1::2, 3] == 0), "empty cells are transparent"
    for i, value in [(0, -5.0), (58, 5.0), (30, objective[15])]:
        assert same_colour(pixel_at(fig, ax, *centroids[i]), expected_rgb(value, -5.0, 5.0))
    plt.close(fig)


def test_parallel_axes_draws_one_line_per_elite_best_on_top():
    measures = np.array([[0.0, 10.0, 5.0], [1.0, 20.0, 5.0], [0.5, 15.0, 5.0]])
    objective = np.array([3.0, 1.0, 2.0])
    fig, ax = plt.subplots()
    lines = archive_plots.parallel_axes(ax, measures, objective, colorbar=False)
    segments = lines.get_segments()
    assert len(segments) == 3
    # Drawn worst first: objective 1 (row 1), 2 (row 2), 3 (row 0); each measure scaled to its range.
    assert np.allclose(segments[0], [[0, 1], [1, 1], [2, 0]])
    assert np.allclose(segments[2], [[0, 0], [1, 0], [2, 0]])
    assert np.allclose(lines.get_colors()[2][:3], VIRIDIS(1.0)[:3])
    plt.close(fig)

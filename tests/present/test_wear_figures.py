"""The wear figures (hipsim.present.wear_figures): the grid's cell corners in the top view, tracks scaled to the cup,
the difference maps' colour range symmetric about zero; read back from figures made from small fakes of a run."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hipsim.present.wear_figures import _grid_mesh, plot_difference_maps, plot_force_track, plot_slide_tracks


def grid_maps(theta, phi, r=10.0):
    points = SimpleNamespace(theta=np.asarray(theta), phi=np.asarray(phi), shape=(len(theta), len(phi)), w=None)
    return SimpleNamespace(points=points, setup=SimpleNamespace(radius_mm=r), name="run")


def test_the_cells_corners_lie_half_a_step_around_each_point():
    X, Y = _grid_mesh(grid_maps([np.pi / 4, np.pi / 2], [0.0, np.pi / 2]), 2.0)
    assert X.shape == Y.shape == (3, 3)
    # corners at θ = π/8, 3π/8, 5π/8 and φ = −π/4, π/4, 3π/4: x = r·sin θ·cos φ
    theta = np.array([1, 3, 5]) * np.pi / 8
    phi = np.array([-1, 1, 3]) * np.pi / 4
    np.testing.assert_allclose(X, 2.0 * np.outer(np.sin(theta), np.cos(phi)), atol=1e-15)
    np.testing.assert_allclose(Y, 2.0 * np.outer(np.sin(theta), np.sin(phi)), atol=1e-15)
    X1, _ = _grid_mesh(grid_maps([0.3], [0.0, 1.0]), 1.0)  # one ring: a quarter turn either side of it
    np.testing.assert_allclose(X1[:, 0], np.sin([0.3 - np.pi / 4, 0.3 + np.pi / 4]) * np.cos(-0.5), atol=1e-15)


def test_tracks_are_drawn_at_the_cups_radius():
    tracks: Any = SimpleNamespace(
        slide=[np.array([[0.1, 0.2, 0.9], [0.3, 0.4, 0.8]])], force=np.array([[0.0, 0.5, 0.8]]), load=np.array([1e3])
    )
    ax = plot_slide_tracks(tracks, 10.0).axes[0]
    rim, slide, start, force = ax.get_lines()[:4]
    assert max(np.hypot(rim.get_xdata(), rim.get_ydata())) == pytest.approx(10.0)
    assert slide.get_xdata().tolist() == pytest.approx([1.0, 3.0]) and start.get_ydata().tolist() == [2.0]
    assert force.get_ydata().tolist() == [5.0] and ax.get_title() == "Slide tracks and force track"
    scatter = plot_force_track(tracks, 10.0, "f").axes[0].collections[0]
    assert scatter.get_offsets().tolist() == [[0.0, 5.0]] and scatter.get_array().tolist() == [1e3]


def test_the_difference_maps_are_symmetric_about_zero():
    maps = grid_maps([0.2, 0.4], [0.0, 1.0, 2.0])
    differences = {
        "sliding_mm": np.array([1.0, -3.0, 0.5, 0.0, 2.0, np.nan]),
        "work_N_per_mm": np.zeros(6),
        "cross_shear": np.full(6, np.nan),
    }
    fig = plot_difference_maps(maps, differences)
    meshes = [ax.collections[0] for ax in fig.axes if ax.collections]
    assert meshes[0].get_clim() == (-3.0, 3.0)  # the largest |B − A|, either side
    assert meshes[2].get_clim() == (-1.0, 1.0)  # nothing finite: a unit range
    assert fig.get_suptitle() == "B − A"

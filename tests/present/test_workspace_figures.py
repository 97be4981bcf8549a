"""The workspace figures (hipsim.present.workspace_figures): pixels centred on their grid values, panels per γ,
the offset sweep's series with the built machine marked and infeasible offsets shaded; read back from the artists
of figures made from small maps written here."""

from __future__ import annotations

from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from hipsim.design.workspace import SingularityMap
from hipsim.present.workspace_figures import _extent, _shade, plot_offset_sweep, plot_singularity_map


def test_each_pixel_is_centred_on_its_grid_value():
    assert _extent(np.array([0.0, 10.0, 20.0]), np.array([-4.0, 4.0])) == (-5.0, 25.0, -8.0, 8.0)
    assert _extent(np.array([3.0]), np.array([1.0, 2.0, 4.0])) == (2.5, 3.5, 0.5, 5.0)  # uneven: each end's own step


def test_the_shaded_spans_are_half_a_step_either_side():
    from matplotlib.figure import Figure

    ax = Figure().subplots()
    _shade(ax, np.array([0.0, 1.0, 2.0, 3.0]), np.array([False, True, False, True]))
    spans = [patch.get_x() for patch in ax.patches]  # type: ignore[attr-defined]  # axvspan: Rectangles
    widths = [patch.get_width() for patch in ax.patches]  # type: ignore[attr-defined]
    assert spans == pytest.approx([0.5, 2.5]) and widths == pytest.approx([1.0, 1.0])
    empty = Figure().subplots()
    _shade(empty, np.array([0.0, 1.0]), np.array([False, False]))
    assert not empty.patches


def test_one_panel_per_gamma_and_the_rest_hidden():
    cond = np.full((2, 2, 3), 0.4)
    cond[1, 0, 0] = np.nan  # out of reach: masked
    cond[0, 1, 2] = 0.6
    smap = SingularityMap(np.array([-10.0, 0.0, 10.0]), np.array([-5.0, 5.0]), np.array([-3.0, 3.0]), cond, 30.0, "p")
    fig = plot_singularity_map(smap)
    visible = [ax for ax in fig.axes if ax.get_visible() and ax.get_title()]
    assert [ax.get_title() for ax in visible] == [
        "γ = -3° (internal/external rotation)",
        "γ = 3° (internal/external rotation)",
    ]
    image = visible[1].get_images()[0]
    assert image.get_extent() == [-15.0, 15.0, -10.0, 10.0]
    assert np.ma.is_masked(image.get_array()[0, 0]) and image.get_clim() == (0.0, 0.6)
    assert fig.get_suptitle() == "Singularity map, platform offset δ = 30°"


def test_the_offset_sweep_marks_the_built_machine_and_shades_what_is_infeasible():
    sweep: Any = SimpleNamespace(
        deltas_deg=np.array([20.0, 25.0, 30.0, 35.0]),
        delta_built_deg=30.0,
        built_index=2,
        cond_inv_min=np.array([0.1, 0.2, 0.3, np.nan]),
        tau_peak_Nmm=np.array([900.0, 500.0, 400.0, np.nan]),
        stroke_max_mm=np.array([50.0, 45.0, 40.0, np.nan]),
        feasible=np.array([True, True, True, False]),
        trajectory="ISO",
    )
    fig = plot_offset_sweep(sweep)
    torque = fig.axes[1]
    series, built = torque.get_lines()[0], torque.get_lines()[2]
    assert series.get_ydata().tolist()[:3] == [900.0, 500.0, 400.0] and torque.get_yscale() == "log"
    assert built.get_xdata().tolist() == [30.0] and built.get_ydata().tolist() == [400.0]
    assert [t.get_text() for t in torque.texts] == [
        "400",
        "shaded: motion out of reach, singular, or passing through a singularity",
    ]
    assert all(len(ax.patches) == 1 and ax.patches[0].get_x() == pytest.approx(32.5) for ax in fig.axes)

"""workspace.json's records (hipsim.design.workspace_summary) from a map and a sweep built by hand."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hipsim.design.workspace import OffsetSweep, SingularityMap, TrajectoryMargin
from hipsim.design.workspace_summary import Grid, MarginSummary, workspace_summary


def _map(margin: TrajectoryMargin | None) -> SingularityMap:
    cond = np.full((2, 2, 3), 0.5)
    cond[1, 0, :2] = np.nan  # γ = 4: 2 of 6 orientations out of reach
    return SingularityMap(
        np.array([-10.0, 0.0, 10.0]), np.array([-5.0, 5.0]), np.array([-4.0, 4.0]), cond, 30.0, "p.toml", margin
    )


def _sweep() -> OffsetSweep:
    nan = math.nan
    return OffsetSweep(
        np.array([0.0, 30.0]),
        np.array([nan, 0.4]),
        np.array([nan, 120.0]),
        np.array([0, 2]),
        np.array([nan, 80.0]),
        np.array([5, 0]),
        np.array([0, 0]),
        np.array([1, 0]),
        "iso",
        30.0,
    )


def test_the_summary_of_a_hand_built_map_and_sweep():
    margin = TrajectoryMargin("iso", np.array([0.3, 0.2]), 0.2, 1, 0.5, np.array([1.0, 2.0, 3.0]), 0, 0, 0)
    summary = workspace_summary(_map(margin), _sweep())
    assert summary.grid.alpha_deg == (-10.0, 10.0, 3) and summary.grid.beta_deg == (-5.0, 5.0, 2)
    assert summary.reachable_fraction == {"-4": 1.0, "4": pytest.approx(4 / 6, abs=1e-6)}
    assert summary.trajectory_margin.q_deg == (1.0, 2.0, 3.0) and summary.trajectory_margin.t_s == 0.5
    document = summary.to_json()
    infeasible, built = document["offset_sweep"]
    assert infeasible["tau_peak_Nmm"] is None and infeasible["out_of_reach_samples"] == 5  # NaN prints as null
    assert built == {
        "delta_deg": 30.0,
        "cond_inv_min": 0.4,
        "tau_peak_Nmm": 120.0,
        "tau_peak_motor": 2,
        "stroke_max_mm": 80.0,
        "out_of_reach_samples": 0,
        "singular_samples": 0,
        "singularity_crossings": 0,
    }
    assert (document["parameters"], document["trajectory"], document["delta_deg"]) == ("p.toml", "iso", 30.0)


def test_a_trajectory_out_of_reach_prints_nulls_and_a_map_without_one_is_refused():
    lost = TrajectoryMargin("iso", np.array([np.nan]), math.nan, -1, math.nan, np.full(3, np.nan), 1, 0, 0)
    margin = workspace_summary(_map(lost), _sweep()).to_json()["trajectory_margin"]
    assert (
        margin["cond_inv_min"] is None and margin["q_deg"] == [None, None, None] and margin["out_of_reach_samples"] == 1
    )
    with pytest.raises(ValueError, match="^workspace_summary: the map was made without a trajectory"):
        workspace_summary(_map(None), _sweep())


def test_the_margin_each_count_in_its_place_and_the_fractions_to_six_places():
    """Counts chosen apart (out of reach 2, singular 3, crossings 4) so that a swap shows; γ = 4's 4/6 printed 0.666667."""
    margin = TrajectoryMargin("iso", np.array([0.3, 0.05]), 0.05, 1, 0.5, np.array([1.0, 2.0, 3.0]), 2, 3, 4)
    summary = workspace_summary(_map(margin), _sweep())
    assert summary.trajectory_margin == MarginSummary(0.05, 0.5, (1.0, 2.0, 3.0), 2, 3, 4)
    assert summary.reachable_fraction == {"-4": 1.0, "4": 0.666667}
    assert summary.grid == Grid((-10.0, 10.0, 3), (-5.0, 5.0, 2), (-4.0, 4.0))


def test_a_map_whose_panels_do_not_match_its_gamma_values_is_refused():
    smap = _map(TrajectoryMargin("iso", np.array([0.3]), 0.3, 0, 0.0, np.zeros(3), 0, 0, 0))
    lopsided = dataclasses.replace(smap, gamma_deg=np.array([-4.0, 0.0, 4.0]))  # 3 values, 2 panels
    with pytest.raises(ValueError, match="zip"):
        workspace_summary(lopsided, _sweep())

"""The sweep command's own logic (hipsim.cli.sweep): where to look next, a best variant on the edge of the swept
range and its nearest failing neighbour, from sweep tables built by hand; a key given twice; the ranges to sweep on.
The sweep itself: design/test_sweep.py."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.cli import sweep as sweep_cli
from hipsim.design.variants import key_ref
from hipsim.exceptions import HipsimError


def _table(keys: dict, objective, rating=None, margin=None):
    """A sweep table built by hand: the keys' columns, one objective, every row computed."""
    n = len(objective)
    columns: dict[str, list] = {key: list(map(float, values)) for key, values in keys.items()}
    columns |= {
        "status": ["ok"] * n,
        "reason": [""] * n,
        "rating": rating or ["unchecked"] * n,
        "margin": margin or [math.nan] * n,
        "binding": [""] * n,
    }
    return columns | {"tau_peak_max_Nmm": list(map(float, objective))}


def test_an_optimum_on_the_edge_of_a_grid_is_reported_with_a_range_beyond_it():
    x = np.arange(320.0, 341.0, 5.0)  # 320 … 340, step 5
    on_edge = sweep_cli._summary(
        _table({"lever.length_mm": x}, (x - 400.0) ** 2), ["lever.length_mm"], {"tau_peak_max_Nmm": False}, None
    )
    (edge,) = on_edge["best"]["tau_peak_max_Nmm"]["edges"]
    assert (edge["key"], edge["side"], edge["value"], edge["step"]) == ("lever.length_mm", "upper", 340.0, 5.0)
    low, high = edge["suggestion"]
    assert low == 320.0 and high > 340.0 and (high - 340.0) % 5.0 == 0.0
    text = "\n".join(sweep_cli._onward_lines(on_edge))
    assert "upper edge of lever.length_mm" in text and f"lever.length_mm=320:{high:g}:5" in text
    inside = sweep_cli._summary(
        _table({"lever.length_mm": x}, (x - 331.0) ** 2), ["lever.length_mm"], {"tau_peak_max_Nmm": False}, None
    )
    assert inside["best"]["tau_peak_max_Nmm"]["edges"] == [] and "edge" not in "\n".join(
        sweep_cli._onward_lines(inside)
    )


def test_a_flat_objective_points_to_no_edge_and_a_sample_has_edges_too():
    x = np.arange(1.0, 6.0)
    flat = sweep_cli._summary(
        _table({"lever.mass_kg": x}, np.ones(5)), ["lever.mass_kg"], {"tau_peak_max_Nmm": False}, None
    )
    assert flat["best"]["tau_peak_max_Nmm"]["edges"] == []  # the first row ties with every other
    from hipsim.design.sweep_edges import edges_of

    rng = np.random.default_rng(3)
    sample = (np.arange(20) + rng.random(20))[
        rng.permutation(20)
    ] / 20 * 4 + 1  # one value in each of 20 strata of 1 … 5
    values = np.column_stack([sample, sample[::-1]])
    low_row = int(np.argmin(sample))
    assert ("a", "lower") in [(e.key, e.side) for e in edges_of(values, ["a", "b"], low_row)]
    middle = int(np.argsort(sample)[10])
    assert [e for e in edges_of(values, ["a", "b"], middle) if e.key == "a"] == []
    assert all(e.step is None for e in edges_of(values, ["a", "b"], low_row))


def test_the_best_variant_names_its_nearest_failing_neighbour():
    x = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    y = np.array([10.0, 10.0, 10.0, 10.0, 10.0])
    rating = ["fail", "pass", "pass", "fail", "fail"]
    margin = [-0.2, 0.1, 0.3, -0.05, -0.4]
    columns = _table({"a.x": x, "a.y": y}, -np.array(margin), rating, margin)
    summary = sweep_cli._summary(columns, ["a.x", "a.y"], {"tau_peak_max_Nmm": False}, None)
    best = summary["best"]["margin"]
    assert best["variant"] == {"a.x": 3.0, "a.y": 10.0} and best["margin"] == 0.3
    assert (
        best["nearest_failing"]["variant"] == {"a.x": 4.0, "a.y": 10.0} and best["nearest_failing"]["margin"] == -0.05
    )
    assert "nearest failing neighbour at a.x 4, a.y 10 (FAIL, margin -5.0 %); its own margin +30.0 %" in "\n".join(
        sweep_cli._onward_lines(summary)
    )


def test_a_key_given_twice_is_refused():
    key = key_ref("lever.length_mm")
    seen = {key}
    with pytest.raises(HipsimError, match="--grid lever.length_mm is given twice"):
        sweep_cli._unique(key_ref("lever.length_mm"), seen, "--grid")
    assert sweep_cli._unique(key_ref("screw.lead_mm"), seen, "--grid").name == "screw.lead_mm"


def test_the_ranges_to_sweep_on_as_the_options_take_them():
    edges = [
        {"key": "lever.length_mm", "suggestion": (320.0, 360.0), "step": 5.0},
        {"key": "screw.lead_mm", "suggestion": (4.5, 12.25), "step": None},  # a sample: no step
    ]
    assert sweep_cli._extend(edges) == "sweep on, e.g. lever.length_mm=320:360:5 screw.lead_mm=4.5:12.25"

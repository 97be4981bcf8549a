"""A sweep's summary over its table (hipsim.design.sweep_summary): counts, the best variant and where to look next,
the Pareto points, the verdict; tables built by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.cli import sweep as sweep_cli
from hipsim.design.sweep_summary import Best, Neighbour, pareto_points, sweep_result, sweep_verdict
from hipsim.records import Level, Verdict, exit_status


def _table(keys: dict, objective, rating=None, margin=None, status=None):
    """A sweep table built by hand: the keys' columns, one objective, every row computed unless ``status`` says."""
    n = len(objective)
    columns: dict[str, list] = {key: list(map(float, values)) for key, values in keys.items()}
    columns |= {
        "status": status or ["ok"] * n,
        "reason": [""] * n,
        "rating": rating or ["unchecked"] * n,
        "margin": margin or [math.nan] * n,
        "binding": [""] * n,
    }
    return columns | {"tau_peak_max_Nmm": list(map(float, objective))}


def test_an_optimum_on_the_edge_of_a_grid_is_reported_with_a_range_beyond_it():
    x = np.arange(320.0, 341.0, 5.0)  # 320 … 340, step 5
    on_edge = sweep_result(
        _table({"lever.length_mm": x}, (x - 400.0) ** 2), ["lever.length_mm"], {"tau_peak_max_Nmm": False}
    )
    (edge,) = on_edge.best["tau_peak_max_Nmm"].edges
    assert (edge.key, edge.side, edge.value, edge.step) == ("lever.length_mm", "upper", 340.0, 5.0)
    low, high = edge.suggestion
    assert low == 320.0 and high > 340.0 and (high - 340.0) % 5.0 == 0.0
    text = "\n".join(sweep_cli._onward_lines(on_edge))
    assert "upper edge of lever.length_mm" in text and f"lever.length_mm=320:{high:g}:5" in text
    inside = sweep_result(
        _table({"lever.length_mm": x}, (x - 331.0) ** 2), ["lever.length_mm"], {"tau_peak_max_Nmm": False}
    )
    assert inside.best["tau_peak_max_Nmm"].edges == () and "edge" not in "\n".join(sweep_cli._onward_lines(inside))


def test_a_flat_objective_points_to_no_edge_and_a_sample_has_edges_too():
    x = np.arange(1.0, 6.0)
    flat = sweep_result(_table({"lever.mass_kg": x}, np.ones(5)), ["lever.mass_kg"], {"tau_peak_max_Nmm": False})
    assert flat.best["tau_peak_max_Nmm"].edges == ()  # the first row ties with every other
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
    result = sweep_result(columns, ["a.x", "a.y"], {"tau_peak_max_Nmm": False})
    best = result.best["margin"]
    assert best.variant == {"a.x": 3.0, "a.y": 10.0} and best.margin == 0.3 and best.goal == "max"
    neighbour = best.nearest_failing
    assert neighbour is not None and neighbour.variant == {"a.x": 4.0, "a.y": 10.0} and neighbour.margin == -0.05
    assert "nearest failing neighbour at a.x 4, a.y 10 (FAIL, margin -5.0 %); its own margin +30.0 %" in "\n".join(
        sweep_cli._onward_lines(result)
    )
    # Counts by hand: 2 pass, 3 fail, rated; passing is the rating's; the JSON key of the passed count is "pass".
    assert (result.rows, result.ok, result.passed, result.fail, result.unchecked, result.passing) == (5, 5, 2, 3, 0, 2)
    assert result.rated and result.to_json()["pass"] == 2 and result.verdict.level is Level.FEASIBLE


def test_the_counts_by_status_and_the_verdict_without_a_rating():
    x = np.array([1.0, 2.0, 3.0])
    status = ["ok", "cannot_assemble", "out_of_workspace"]
    result = sweep_result(
        _table({"a.x": x}, [1.0, math.nan, math.nan], status=status), ["a.x"], {"tau_peak_max_Nmm": False}
    )
    assert (result.ok, result.cannot_assemble, result.out_of_workspace, result.passing) == (1, 1, 1, 1)
    assert not result.rated and result.verdict.level is Level.FEASIBLE and "no drive given" in result.verdict.not_judged


def test_the_sweep_verdict_at_its_boundary():
    """One passing row is FEASIBLE; none is NOT FEASIBLE (exit 1), rated or not."""
    assert sweep_verdict(4, 4, True, 1).level is Level.FEASIBLE
    assert sweep_verdict(4, 4, True, 0).level is Level.NOT_FEASIBLE
    assert sweep_verdict(4, 0, False, 0).level is Level.NOT_FEASIBLE
    assert exit_status([sweep_verdict(4, 4, True, 0)]) == 1 and exit_status([sweep_verdict(4, 4, True, 1)]) == 0
    assert sweep_verdict(4, 3, True, 1).numbers == {"rows": 4.0, "ok": 3.0, "passing": 1.0}


def test_pareto_points_by_hand():
    """Minimise both: (1, 3) and (2, 1) are on the front, (3, 3) is dominated; the front's ends lie on the key's edges."""
    columns = _table({"a.x": [1.0, 2.0, 3.0]}, [1.0, 2.0, 3.0]) | {"y": [3.0, 1.0, 3.0]}
    front, points, edged = pareto_points(columns, ["a.x"], [("tau_peak_max_Nmm", False), ("y", False)])
    assert front.tolist() == [True, True, False]
    assert [p.to_json() for p in points] == [
        {"a.x": 1.0, "tau_peak_max_Nmm": 1.0, "y": 3.0},
        {"a.x": 2.0, "tau_peak_max_Nmm": 2.0, "y": 1.0},
    ]
    assert [(p.variant, [e.side for e in p.edges]) for p in edged] == [({"a.x": 1.0}, ["lower"])]


def test_the_sweep_verdicts_words_whole():
    assert sweep_verdict(4, 3, True, 1) == Verdict(
        Level.FEASIBLE, "1 of 4 variants pass the drive's rating", "", {"rows": 4.0, "ok": 3.0, "passing": 1.0}
    )
    assert sweep_verdict(4, 3, False, 3) == Verdict(
        Level.FEASIBLE,
        "3 of 4 variants run the motion (they assemble and stay in the workspace)",
        "the drive's rating: no drive given",
        {"rows": 4.0, "ok": 3.0, "passing": 3.0},
    )


def _mixed():
    """Four rows by hand: x = 1 … 4; row 1 cannot assemble (its reason), row 2 fails the rating (its binding check),
    rows 0 and 3 pass; the torque of row 1 a Parquet null (None)."""
    columns = _table(
        {"a.x": [1.0, 2.0, 3.0, 4.0]},
        [1.0, 0.0, 3.0, 4.0],
        ["pass", "unchecked", "fail", "pass"],
        [0.2, math.nan, -0.1, 0.3],
        ["ok", "cannot_assemble", "ok", "ok"],
    )
    columns["tau_peak_max_Nmm"][1] = None
    columns["reason"][1] = "lever too short"
    columns["binding"][2] = "max_speed"
    return columns


def test_the_best_variants_and_their_nearest_failing_rows_whole():
    """The least torque is row 0's (row 1's null is no value): its nearest failing row is row 1 (cannot assemble, no
    margin, its reason); the largest margin is row 3's (0.3): its nearest failing row is row 2 (FAIL, its binding)."""
    result = sweep_result(_mixed(), ["a.x"], {"tau_peak_max_Nmm": False})
    torque = result.best["tau_peak_max_Nmm"]
    assert torque == Best(
        "min",
        1.0,
        0,
        {"a.x": 1.0},
        "pass",
        torque.edges,
        0.2,
        Neighbour(1, {"a.x": 2.0}, "cannot_assemble", "unchecked", None, None, "lever too short"),
    )
    assert [(e.key, e.side, e.value) for e in torque.edges] == [("a.x", "lower", 1.0)]
    margin = result.best["margin"]
    assert margin == Best(
        "max",
        0.3,
        3,
        {"a.x": 4.0},
        "pass",
        margin.edges,
        0.3,
        Neighbour(2, {"a.x": 3.0}, "ok", "fail", -0.1, "max_speed", None),
    )
    assert [(e.key, e.side, e.value) for e in margin.edges] == [("a.x", "upper", 4.0)]
    assert (result.rows, result.ok, result.cannot_assemble, result.out_of_workspace) == (4, 3, 1, 0)
    assert (result.rated, result.passed, result.fail, result.unchecked, result.passing) == (True, 2, 1, 1, 2)
    assert result.verdict.judged == "2 of 4 variants pass the drive's rating"


def test_one_rating_word_alone_makes_a_table_rated():
    x = {"a.x": [1.0, 2.0, 3.0]}
    failing = sweep_result(_table(x, [1.0, 2.0, 3.0], ["fail", "unchecked", "unchecked"]), ["a.x"], {})
    assert failing.rated and (failing.fail, failing.unchecked, failing.passing) == (1, 2, 0)
    assert failing.verdict.level is Level.NOT_FEASIBLE  # 3 rows run the motion, none passes the rating
    passing = sweep_result(
        _table(x, [1.0, 2.0, 3.0], ["pass", "unchecked", "unchecked"], [0.5, math.nan, math.nan]), ["a.x"], {}
    )
    assert passing.rated and passing.passing == 1 and "margin" in passing.best
    unrated = sweep_result(_table(x, [1.0, 2.0, 3.0]), ["a.x"], {"tau_peak_max_Nmm": False})
    assert not unrated.rated and "margin" not in unrated.best and unrated.best["tau_peak_max_Nmm"].margin is None
    assert unrated.best["tau_peak_max_Nmm"].nearest_failing is None  # every row runs, none is rated


def test_an_objective_without_values_is_skipped_and_the_next_still_found():
    columns = _table({"a.x": [1.0, 2.0, 3.0]}, [3.0, 1.0, 2.0]) | {"empty": [math.nan] * 3, "y": [5.0, 9.0, 7.0]}
    result = sweep_result(columns, ["a.x"], {"empty": False, "tau_peak_max_Nmm": False}, [("y", True)])
    assert list(result.best) == ["tau_peak_max_Nmm", "y"]
    assert (result.best["tau_peak_max_Nmm"].row, result.best["tau_peak_max_Nmm"].value) == (1, 1.0)
    assert (result.best["y"].goal, result.best["y"].row, result.best["y"].value) == ("max", 1, 9.0)


@pytest.mark.parametrize(
    ("objective", "edges"),
    [
        # best 1000 on the upper edge; row 0 is 1e-7 (1e-10 of it) away, within 1e-9: a tie on the lower edge
        ([1000.0 + 1e-7, 2000.0, 1000.0], []),
        # best 0: the tolerance is 1e-9 of 1e-300, so a row at 1e-12 does not tie
        ([1e-12, 5.0, 0.0], ["upper"]),
        # a row exactly at that tolerance ties
        ([1e-9 * 1e-300, 5.0, 0.0], []),
    ],
)
def test_rows_tie_with_the_best_to_1e_9_of_it(objective, edges):
    result = sweep_result(_table({"a.x": [1.0, 2.0, 3.0]}, objective), ["a.x"], {"tau_peak_max_Nmm": False})
    best = result.best["tau_peak_max_Nmm"]
    assert best.row == 2 and [e.side for e in best.edges] == edges


def test_pareto_points_with_one_objective_maximised_and_a_null():
    """Minimise x's torque, maximise y: (1, 3) and (3, 4) are on the front; (2, 1) is dominated; a null is never on it."""
    columns = _table({"a.x": [1.0, 2.0, 3.0, 4.0]}, [1.0, 2.0, 3.0, 0.0]) | {"y": [3.0, 1.0, 4.0, 9.0]}
    columns["tau_peak_max_Nmm"][3] = None
    front, points, edged = pareto_points(columns, ["a.x"], [("tau_peak_max_Nmm", False), ("y", True)])
    assert front.tolist() == [True, False, True, False]
    assert [p.values for p in points] == [
        {"a.x": 1.0, "tau_peak_max_Nmm": 1.0, "y": 3.0},
        {"a.x": 3.0, "tau_peak_max_Nmm": 3.0, "y": 4.0},
    ]
    assert [(p.variant, [e.side for e in p.edges]) for p in edged] == [({"a.x": 1.0}, ["lower"])]

"""hipsim.design.sweep_edges by hand: a value within one stratum (range / m) of an end is on that edge, the range to
sweep next, and the nearest failing row with each key scaled by its swept range."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.design.sweep_edges import edges_of, nearest_failing


def column(*values):
    return np.array(values, dtype=float)[:, None]


def test_a_grids_end_values_only_are_on_its_edges():
    grid = column(1, 2, 3, 4, 5)  # m = 5, stratum 4/5 = 0.8: the second value is a step (1) in
    (lower,) = edges_of(grid, ["m"], 0)
    assert (lower.key, lower.side, lower.value, lower.low, lower.high, lower.step) == ("m", "lower", 1.0, 1.0, 5.0, 1.0)
    # Half the span (2) past the low end would cross zero from a positive value: halved towards zero instead.
    assert lower.suggestion == (0.5, 5.0)
    assert edges_of(grid, ["m"], 1) == []
    (upper,) = edges_of(grid, ["m"], 4)
    assert upper.side == "upper" and upper.suggestion == (1.0, 7.0)


def test_one_stratum_from_the_end_is_not_on_the_edge():
    sample = column(0.0, 0.25, 0.9, 1.0)  # m = 4, stratum exactly 0.25
    assert edges_of(sample, ["k"], 1) == []
    (edge,) = edges_of(column(0.0, 0.2499, 0.9, 1.0), ["k"], 1)
    assert edge.side == "lower" and edge.step is None  # uneven: a sample, no step
    assert edge.suggestion == (-0.5, 1.0)  # the low end at zero may go below it


def test_a_grid_extends_by_whole_steps_and_a_negative_end_goes_on():
    (upper,) = edges_of(column(0, 1, 2, 3), ["x"], 3)
    assert upper.suggestion == (0.0, 5.0)  # half the span, 1.5, rounds to 2 steps
    (lower,) = edges_of(column(-2, -1, 0), ["x"], 0)
    assert lower.suggestion == (-3.0, 0.0)


def test_keys_swept_over_one_value_and_missing_values_give_no_edge():
    values = np.array([[1.0, 7.0], [2.0, 7.0], [math.nan, 7.0]])
    assert [e.key for e in edges_of(values, ["a", "b"], 0)] == ["a"]
    assert edges_of(values, ["a", "b"], 2) == []  # its own value unknown
    assert edges_of(values, ["a", "b"], 1)[0].to_json() == {
        "key": "a",
        "side": "upper",
        "value": 2.0,
        "low": 1.0,
        "high": 2.0,
        "step": 1.0,
        "suggestion": [1.0, 3.0],  # half the span is half a step: a grid goes on by one step at least
    }


def test_the_nearest_failing_row_is_measured_in_swept_ranges():
    values = np.array([[0.0, 0.0], [3.0, 0.0], [0.0, 2.0], [10.0, 2.0]])  # spans 10 and 2
    # Scaled: row 1 is 0.3 away, row 2 is 1.0 away (unscaled it would be 3 against 2).
    assert nearest_failing(values, np.array([False, True, True, False]), 0) == 1
    assert nearest_failing(values, np.array([True, True, True, False]), 0) == 1  # the row itself does not count
    assert nearest_failing(values, np.array([True, False, False, False]), 0) is None
    assert nearest_failing(values, np.zeros(4, dtype=bool), 0) is None


@pytest.mark.parametrize("row", [0, 1])
def test_a_key_of_one_value_does_not_divide_by_zero(row):
    values = np.array([[0.0, 5.0], [1.0, 5.0], [0.4, 5.0]])
    assert nearest_failing(values, np.array([True, True, True]), row) == 2

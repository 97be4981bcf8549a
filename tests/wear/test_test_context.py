"""hipsim.wear.test_context by hand: a station's angle errors (RMS and largest |error| per angle), the monitor's last
snapshot with an estimate (the station's own column when it has one there, else the stations' mean; cells that are
not numbers skipped), its words and its document. (The error against ISO by gait phase: tests/wear/test_gravimetric.py.)"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest

from hipsim.wear.test_context import FrictionState, friction_state, motion_error

NAN = float("nan")


def test_rms_and_largest_error_per_angle():
    error = motion_error(np.array([[1.0, -2.0, 0.0], [-1.0, 2.0, 3.0], [1.0, 2.0, 0.0], [-1.0, -2.0, 0.0]]), "log")
    assert error.rms_deg == pytest.approx((1.0, 2.0, 1.5))  # √(9/4) for γ
    assert error.max_deg == (1.0, 2.0, 3.0)
    assert error.to_json() == {"source": "log", "rms_deg": [1.0, 2.0, 1.5], "max_deg": [1.0, 2.0, 3.0]}
    assert motion_error(np.array([[0.0, -5.0, 0.0]]), "one").max_deg == (0.0, 5.0, 0.0)  # by magnitude


TABLE: dict[str, list] = {
    "cycle": ["0", "250000", "500000", "750000"],
    "hip_mu_change": [0.0, 0.002, 0.003, "n/a"],  # the last snapshot has no estimate: the one before is taken
    "hip_mu_change_std": [0.0005, 0.0005, 0.0007, NAN],
    "hip_mu_change_2": [0.0, 0.001, 0.005, NAN],
    "hip_mu_change_2_std": [0.001, 0.001, 0.002],
    "flag": ["", "", "NOTICE", "ALARM"],
}


def test_the_last_snapshot_with_an_estimate_and_the_stations_own_column():
    own = friction_state(TABLE, 2, "monitor.csv")
    assert own == FrictionState("monitor.csv", 4, 500_000, 0.005, 0.002, True, "NOTICE")
    mean = friction_state(TABLE, 1, "monitor.csv")  # no column of station 1: the mean
    assert mean == FrictionState("monitor.csv", 4, 500_000, 0.003, 0.0007, False, "NOTICE")
    assert friction_state(TABLE, None, "monitor.csv") == mean


def test_a_table_without_estimates_or_flags():
    table: dict[str, list[Any]] = {"cycle": [0, 10], "hip_mu_change": [NAN, None]}
    state = friction_state(table, 1, "m.csv")
    assert state is not None and state.last_cycle == 10 and state.snapshots == 2  # the last row
    assert math.isnan(state.hip_mu_change) and math.isnan(state.hip_mu_change_std) and state.flag == ""
    # No column of estimates nor of flags (once an IndexError): the last row, its numbers unknown.
    bare = friction_state({"cycle": [5]}, None, "m.csv")
    assert bare is not None and bare.last_cycle == 5 and math.isnan(bare.hip_mu_change)
    assert friction_state({}, 1, "m.csv") is None and friction_state({"cycle": []}, 1, "m.csv") is None


def test_a_friction_states_words():
    own = FrictionState("m.csv", 4, 500_000, 0.005, 0.002, True, "NOTICE")
    assert (
        own.describe()
        == "hip μ change +0.0050 ± 0.0020 (this station's) at cycle 500000 over 4 snapshots; monitor: NOTICE"
    )
    mean = FrictionState("m.csv", 4, 500_000, -0.003, 0.0007, False, "")
    assert mean.describe() == (
        "hip μ change -0.0030 ± 0.0007 (the two stations' mean) at cycle 500000 over 4 snapshots; monitor: no flag"
    )


def test_an_estimate_only_at_the_first_snapshot_is_the_last_one():
    table: dict[str, list[Any]] = {
        "cycle": [0, 10, 20],
        "hip_mu_change": [0.002, NAN, "x"],
        "hip_mu_change_std": [0.001, 0.0, 0.0],
    }
    state = friction_state(table, None, "m.csv")
    assert state is not None and (state.last_cycle, state.hip_mu_change, state.hip_mu_change_std) == (0, 0.002, 0.001)

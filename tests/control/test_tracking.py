"""A plant-and-model run's summary (hipsim.control.tracking): the errors per platform and angle by hand, each
station's ISO 14242-1 verdict on its own platform's motion, the record's JSON."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.control.tracking import MachineRun
from hipsim.motion.trajectories import iso14242
from hipsim.records import Level, exit_status


def _run(offset_deg: tuple[float, float], cycles: float = 2) -> MachineRun:
    """Both platforms on the ISO cycle at 100 Hz, each off it by a constant α offset in [deg]; motor 1 at ±2 N·m."""
    desired = iso14242(rate=100.0, cycles=cycles)
    n = len(desired.t)
    attitudes = np.repeat(desired.q[:, None, :], 2, axis=1).copy()
    for j, off in enumerate(offset_deg):
        attitudes[:, j, 0] -= math.radians(off)
    tau = np.zeros((n, 3))
    tau[:, 0] = np.where(np.arange(n) % 2 == 0, 2.0, -2.0)
    zeros = np.zeros((n, 3))
    return MachineRun(
        desired.t,
        desired,
        zeros,
        attitudes,
        np.zeros((n, 2, 3)),
        desired.q,
        tau,
        tau,
        np.zeros(n, bool),
        zeros,
        "analytic",
        "pd",
        "encoders",
        2,
        1e-4,
    )


def test_the_errors_and_motors_by_hand():
    """A constant α error of 1° on m_1: RMS and |peak| 1°, signed +1 (desired − true); motor 1's ±2 N·m: RMS 2000 N·mm."""
    s = _run((1.0, 0.0)).summary()
    assert s.error(1, "alpha").rms_deg == pytest.approx(1.0) and s.error(1, "alpha").peak_deg == pytest.approx(1.0)
    assert s.error(2, "alpha").rms_deg == 0.0 and not s.error(1, "alpha").controlled and s.error(2, "beta").controlled
    assert s.motors[0].torque_rms_Nmm == pytest.approx(2000.0) and s.motors[1].torque_peak_Nmm == 0.0
    assert s.stations is None and "stations" not in s.to_json()
    assert [e["platform"] for e in s.to_json()["errors"]] == [1, 1, 1, 2, 2, 2]


def test_each_station_is_judged_on_its_own_platform():
    """m_1 4° off in α (beyond ±3°) fails, m_2 on the waveform passes; swapped, the verdicts swap: exit 1 either way."""
    first = _run((4.0, 0.0)).summary(periodic=True, iso=True)
    assert first.stations is not None
    assert [s.verdict for s in first.stations] == [Level.FAIL, Level.PASS] and exit_status(first.stations) == 1
    assert first.stations[0].failing == ("alpha",) and first.stations[0].worst_deg is not None
    assert first.stations[0].worst_deg["alpha"] == pytest.approx(
        4.0, abs=0.05
    )  # 100 Hz against the waveform: a few hundredths
    second = _run((0.0, 4.0)).summary(periodic=True, iso=True)
    assert second.stations is not None and [s.verdict for s in second.stations] == [Level.PASS, Level.FAIL]
    edge = _run((2.9, 0.0)).summary(periodic=True, iso=True)  # within ±3°
    assert edge.stations is not None and [s.verdict for s in edge.stations] == [Level.PASS, Level.PASS]


def test_a_run_shorter_than_a_cycle_is_not_judged():
    s = _run((4.0, 4.0), cycles=0.3).summary(iso=True)
    assert s.stations is not None and [x.verdict for x in s.stations] == [Level.NOT_MADE, Level.NOT_MADE]
    assert exit_status(s.stations) == 0 and s.to_json()["stations"][0]["verdict"] == "NOT MADE"

"""The ISO 14242-1 verdict on a station judges the motion it went through, apart from the motion it was asked for
(issue 44 point 5; hipsim/motion/iso_verdict.py)."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.motion.iso_compliance import DEFAULT_TOLERANCES, CycleDeviation, IsoCheck
from hipsim.motion.iso_verdict import ANGLES, Tracking, station_iso, station_iso_verdict
from hipsim.motion.trajectories import iso14242
from hipsim.records import Level, exit_status

ISO = iso14242(rate=200.0, cycles=2)  # two whole cycles, periodic


def _offset(alpha_deg=0.0, beta_deg=0.0, gamma_deg=0.0) -> np.ndarray:
    return np.radians([alpha_deg, beta_deg, gamma_deg]) * np.ones((len(ISO.t), 1))


def _verdict(q, q_d):
    return station_iso("m_2", ISO.t, q, q_d, ISO.Fe, periodic=True)


def test_a_perfectly_tracked_non_iso_motion_is_a_passing_station_with_a_non_iso_input():
    q_d = ISO.q + _offset(alpha_deg=6.7)  # the desired motion itself is 6.7° off the waveform
    verdict = _verdict(q_d, q_d)
    assert verdict.verdict == Level.PASS and exit_status([verdict]) == 0
    # the station's motion, reported as it is (the check aligns the cycles by the load: 0.02° of the waveform's own)
    assert verdict.worst_deg["alpha"] == pytest.approx(6.7, abs=0.03)
    assert verdict.failing == ("alpha",)
    assert verdict.desired is not None and not verdict.desired.iso and verdict.desired.failing == ("alpha",)
    assert verdict.tracking is not None and verdict.tracking.peak_abs_deg == {"alpha": 0.0, "beta": 0.0, "gamma": 0.0}
    assert verdict.desired_line == (
        "the desired motion is not the ISO 14242-1 waveform: worst 6.71° off; tracking of it: RMS alpha 0°, beta 0°, gamma 0°"
    )
    assert "share" in verdict.judged and "PASS" not in verdict.judged


def test_a_badly_tracked_iso_motion_is_a_failing_station():
    e = 4.0 * np.sin(2 * np.pi * ISO.t)  # beta tracked with a 4° error, the tolerance 3°
    q = ISO.q + np.radians(np.column_stack([0 * e, e, 0 * e]))
    verdict = _verdict(q, ISO.q)
    assert verdict.verdict == Level.FAIL and exit_status([verdict]) == 1
    assert verdict.failing == ("beta",) and verdict.cycles == 2
    assert verdict.worst_deg["beta"] == pytest.approx(4.0, abs=0.03)
    assert verdict.desired is not None and verdict.desired.iso and verdict.desired_line is None
    assert verdict.tracking is not None
    assert verdict.tracking.rms_deg["beta"] == pytest.approx(4.0 / np.sqrt(2), rel=1e-9)  # RMS of a whole sine
    assert verdict.tracking.peak_abs_deg["beta"] == pytest.approx(4.0 * np.sin(2 * np.pi * 50 / 200), rel=1e-12)


def test_a_well_tracked_iso_motion_passes_with_no_desired_line():
    verdict = _verdict(ISO.q + _offset(gamma_deg=-2.9), ISO.q)
    assert verdict.verdict == Level.PASS and verdict.desired_line is None
    assert verdict.worst_deg["gamma"] == pytest.approx(2.9, abs=0.03)  # the worst by its magnitude, not its sign


@pytest.mark.parametrize(("error_deg", "level"), [(2.9, Level.PASS), (3.1, Level.FAIL)])
def test_a_non_iso_motion_tracked_badly_fails(error_deg, level):
    q_d = ISO.q + _offset(alpha_deg=6.7)
    assert _verdict(q_d + _offset(gamma_deg=-error_deg), q_d).verdict == level


def _cycle(alpha=0.0, beta=0.0, gamma=0.0) -> CycleDeviation:
    return CycleDeviation(0.0, 1.0, alpha, beta, gamma, 0.0)


@pytest.mark.parametrize(("peak_deg", "level"), [(3.0, Level.PASS), (np.nextafter(3.0, 4.0), Level.FAIL)])
def test_the_tracking_share_is_judged_at_the_tolerance_inclusive(peak_deg, level):
    """A non-ISO desired motion: the station fails exactly when its tracking error leaves ±3° (boundary of <=)."""
    achieved = IsoCheck((_cycle(alpha=6.7),), DEFAULT_TOLERANCES, "run")
    desired = IsoCheck((_cycle(alpha=6.7),), DEFAULT_TOLERANCES, "run")
    for angle in ("alpha", "beta", "gamma"):  # each angle's comparison on its own
        peaks = {"alpha": 0.0, "beta": 0.0, "gamma": 0.0} | {angle: peak_deg}
        tracking = Tracking(dict.fromkeys(peaks, 0.0), peaks)
        assert station_iso_verdict("m_1", achieved, desired, tracking).verdict == level


@pytest.mark.parametrize(("worst_deg", "level"), [(3.0, Level.PASS), (np.nextafter(3.0, 4.0), Level.FAIL)])
def test_an_iso_desired_motion_judges_the_station_motion_at_the_tolerance_inclusive(worst_deg, level):
    desired = IsoCheck((_cycle(),), DEFAULT_TOLERANCES, "run")
    for angle in ("alpha", "beta", "gamma"):
        achieved = IsoCheck((_cycle(**{angle: worst_deg}),), DEFAULT_TOLERANCES, "run")
        tracking = Tracking(dict.fromkeys(ANGLES, 0.0), dict.fromkeys(ANGLES, 0.0))  # a tracking that would pass
        assert station_iso_verdict("m_1", achieved, desired, tracking).verdict == level


def test_the_station_motion_passing_needs_no_tracking_share():
    """The desired motion off by 3.5°, the station pulling it back within tolerance: its motion passes."""
    q_d = ISO.q + _offset(beta_deg=3.5)
    verdict = _verdict(ISO.q + _offset(beta_deg=1.0), q_d)
    assert verdict.verdict == Level.PASS and verdict.desired is not None and not verdict.desired.iso
    assert "within tolerance" in verdict.judged


def test_no_whole_cycle_is_not_made_and_exits_0():
    short = slice(0, 60)
    verdict = station_iso("m_1", ISO.t[short], ISO.q[short], ISO.q[short], ISO.Fe[short])
    assert verdict.verdict == Level.NOT_MADE and verdict.reason and exit_status([verdict]) == 0

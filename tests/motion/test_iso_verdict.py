"""The ISO 14242-1 verdict on a station judges the motion it went through, apart from the motion it was asked for
(issue 44 point 5; hipsim/motion/iso_verdict.py)."""

from __future__ import annotations

import numpy as np
import pytest

from hipsim.motion.iso_compliance import DEFAULT_TOLERANCES, CycleDeviation, IsoCheck
from hipsim.motion.iso_verdict import ANGLES, TOLERANCES_ASSUMED, Tracking, station_iso, station_iso_verdict
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


def _check(*cycles, source="run"):
    return IsoCheck(tuple(cycles), DEFAULT_TOLERANCES, source)


def test_each_judged_sentence_whole():
    """Worst deviations chosen by hand (2 cycles): the sentences name every angle's worst and the failing ones."""
    good = _check(CycleDeviation(0.0, 1.0, 1.0, 0.5, 0.25, 10.0), CycleDeviation(1.0, 1.0, 2.5, 0.5, 0.125, 20.0))
    tracking = Tracking({"alpha": 0.5, "beta": 0.0, "gamma": 0.0}, {"alpha": 1.0, "beta": 3.5, "gamma": 0.0})
    passed = station_iso_verdict("m_2", good, None, None)
    assert (
        passed.judged
        == "m_2's motion against the ISO 14242-1 waveform: worst alpha 2.5°, beta 0.5°, gamma 0.25°, within tolerance"
    )
    assert (passed.verdict, passed.cycles, passed.failing, passed.desired, passed.tracking) == (
        Level.PASS,
        2,
        (),
        None,
        None,
    )
    assert passed.worst_deg == {"alpha": 2.5, "beta": 0.5, "gamma": 0.25}
    bad = _check(CycleDeviation(0.0, 1.0, 4.0, 0.5, 3.5, 10.0))
    failed = station_iso_verdict("m_1", bad, good, tracking)
    assert (
        failed.judged
        == "m_1's motion against the ISO 14242-1 waveform: worst alpha 4°, beta 0.5°, gamma 3.5°; fails alpha, gamma"
    )
    assert (failed.verdict, failed.failing, failed.tracking) == (Level.FAIL, ("alpha", "gamma"), tracking)
    assert failed.desired is not None and failed.desired.iso and failed.desired.worst_deg["alpha"] == 2.5
    # The desired motion not the waveform: the station is judged on its tracking's peaks against the tolerances.
    share = station_iso_verdict("m_1", bad, bad, tracking)
    assert share.judged == (
        "m_1's share of its deviation from the ISO 14242-1 waveform (worst alpha 4°, beta 0.5°, gamma 3.5°), the desired "
        "motion not being the waveform: its tracking error peaks at alpha 1° (±3°), beta 3.5° (±3°), gamma 0° (±3°)"
    )
    assert share.verdict == Level.FAIL and share.desired is not None and share.desired.failing == ("alpha", "gamma")
    assert share.desired_line == (
        "the desired motion is not the ISO 14242-1 waveform: worst 4° off; tracking of it: RMS alpha 0.5°, beta 0°, gamma 0°"
    )
    # Not known whether the desired motion is the waveform, or no tracking: judged as ISO.
    for desired, known in ((None, tracking), (bad, None)):
        alone = station_iso_verdict("m_1", bad, desired, known)
        assert alone.verdict == Level.FAIL and alone.judged.endswith("; fails alpha, gamma")
    assert station_iso_verdict("m_1", bad, None, tracking).desired is None
    no_tracking = station_iso_verdict("m_1", bad, bad, None)
    assert no_tracking.desired_line == "the desired motion is not the ISO 14242-1 waveform: worst 4° off"
    doc = passed.to_json()
    assert "desired" not in doc and "reason" not in doc and doc["verdict"] == "PASS"


def test_station_iso_hands_its_names_limits_and_period_to_both_checks(monkeypatch):
    import hipsim.motion.iso_verdict as module
    from hipsim.motion.iso_compliance import Tolerances

    calls = []

    def stand_in(t, q, load, tolerances, source, periodic):
        calls.append((q, tolerances, source, periodic))
        return _check(CycleDeviation(0.0, 1.0, 5.0 if len(calls) == 1 else 0.0, 0.0, 0.0, 0.0))

    monkeypatch.setattr(module, "iso_check", stand_in)
    tight = Tolerances(alpha=1.0)
    t = np.arange(3) / 100.0
    q, q_d = np.radians([[1.0, 2.0, 3.0]] * 3), np.zeros((3, 3))
    verdict = station_iso("station 2", t, q, q_d, np.ones(3), tight, "log.csv", True)
    assert [(c[1], c[2], c[3]) for c in calls] == [(tight, "log.csv", True)] * 2
    assert calls[0][0] is q and calls[1][0] is q_d
    assert verdict.judged.startswith("station 2's motion against") and verdict.verdict == Level.FAIL
    assert verdict.tracking is not None
    assert verdict.tracking.rms_deg == pytest.approx({"alpha": 1.0, "beta": 2.0, "gamma": 3.0}, rel=1e-12)
    assert verdict.tracking.peak_abs_deg == pytest.approx({"alpha": 1.0, "beta": 2.0, "gamma": 3.0}, rel=1e-12)
    calls.clear()
    station_iso("m_1", t, q, q_d, np.ones(3))
    assert [(c[1], c[2], c[3]) for c in calls] == [(DEFAULT_TOLERANCES, "run", False)] * 2


def test_the_tracking_by_hand_on_integers():
    """Whole numbers of radians (integer arrays): the RMS over every sample and the peak magnitude, in degrees."""
    q = np.array([[1, 0, 0], [-2, 0, 0], [2, 0, 1], [1, 0, 0]])
    verdict = station_iso("m_1", np.arange(4) / 10.0, q, np.zeros((4, 3), dtype=int), np.ones(4))
    assert verdict.verdict == Level.NOT_MADE and verdict.judged == "m_1's motion: no ISO 14242-1 check"
    assert verdict.tracking is not None
    assert verdict.tracking.rms_deg["alpha"] == pytest.approx(np.degrees(np.sqrt(10 / 4)), rel=1e-12)
    assert verdict.tracking.peak_abs_deg == pytest.approx(
        {"alpha": np.degrees(2.0), "beta": 0.0, "gamma": np.degrees(1.0)}
    )
    assert verdict.reason and verdict.reason != "None" and not verdict.reason.startswith("t = ")
    assert verdict.to_json()["reason"] == verdict.reason


def test_the_iso_check_summary_by_hand():
    from hipsim.motion.iso_verdict import iso_check_summary

    check = _check(
        CycleDeviation(0.5, 1.05, 1.0, 3.5, 0.0, 10.0),
        CycleDeviation(1.5, 0.85, 2.0, 0.5, 4.0, 100.0),
        source="log.csv",
    )
    s = iso_check_summary(check)
    assert (s.source, s.passed, s.failing, s.cycles, s.level) == (
        "log.csv",
        False,
        ("beta", "gamma", "load", "frequency"),
        2,
        Level.FAIL,
    )
    assert s.tolerances_assumed == "defaults are assumed values: confirm them against your copy of ISO 14242-1"
    assert list(s.quantities) == ["alpha", "beta", "gamma", "load", "frequency"]
    a, b, load, f = (s.quantities[k] for k in ("alpha", "beta", "load", "frequency"))
    assert (a.unit, a.worst, a.tolerance, a.cycles_failed, a.passed) == ("deg", 2.0, 3.0, 0, True)
    assert (b.unit, b.worst, b.cycles_failed, b.passed) == ("deg", 3.5, 1, False)
    assert (load.unit, load.worst, load.tolerance, load.cycles_failed) == ("N", 100.0, DEFAULT_TOLERANCES.load, 1)
    assert (f.unit, f.worst, f.tolerance, f.cycles_failed) == ("Hz", pytest.approx(0.15), 0.1, 1)
    first, second = s.per_cycle
    assert (first.cycle, first.start_s, first.frequency_Hz, first.alpha, first.beta, first.gamma, first.load) == (
        1, 0.5, 1.05, 1.0, 3.5, 0.0, 10.0
    )  # fmt: skip
    assert first.frequency == pytest.approx(0.05) and first.passed is False
    assert (second.cycle, second.start_s, second.gamma, second.load, second.passed) == (2, 1.5, 4.0, 100.0, False)
    ok = iso_check_summary(_check(CycleDeviation(0.0, 1.0, 1.0, 1.0, 1.0, 1.0)))
    assert ok.passed and ok.level == Level.PASS and ok.per_cycle[0].passed is True and ok.failing == ()
    assert ok.per_cycle[0].frequency == 0.0 and ok.quantities["gamma"].unit == "deg"
    assert s.to_json()["quantities"]["load"]["cycles_failed"] == 1


def _quantities(**checks):
    """Per quantity (unit, worst, tolerance, cycles failed, passed), the others well within their tolerance."""
    from hipsim.motion.iso_verdict import QuantityCheck

    base = {
        "alpha": ("deg", 0.0, 3.0, 0, True),
        "beta": ("deg", 0.0, 3.0, 0, True),
        "gamma": ("deg", 0.0, 3.0, 0, True),
        "load": ("N", 0.0, 90.0, 0, True),
        "frequency": ("Hz", 0.0, 0.1, 0, True),
    }
    return {name: QuantityCheck(*checks.get(name, row)) for name, row in base.items()}


def test_the_run_verdict_passes_and_names_the_quantity_closest_to_its_tolerance():
    from hipsim.motion.iso_verdict import binding_quantity, iso_check_verdict

    q = _quantities(beta=("deg", 2.7, 3.0, 0, True), load=("N", 81.0, 90.0, 0, True))  # 0.9 of each: a tie
    assert binding_quantity(q) == "beta"  # the first of a tie, in the order given
    q = _quantities(beta=("deg", 2.7, 3.0, 0, True), load=("N", 81.09, 90.0, 0, True))  # 0.901 of the load's
    assert binding_quantity(q) == "load"
    verdict = iso_check_verdict(q, 2)
    assert verdict.level == Level.PASS and exit_status([verdict]) == 0
    assert verdict.judged == (
        "every one of 2 whole cycle(s) kept every angle, the load and the frequency within tolerance; "
        "closest: load, worst deviation 81.1 N against ±90 N"
    )
    assert verdict.not_judged.startswith("the tolerances themselves: the defaults are assumed values")
    assert verdict.numbers["cycles"] == 2.0 and verdict.numbers["beta_worst_deg"] == 2.7
    assert verdict.numbers["load_tolerance_N"] == 90.0 and verdict.numbers["frequency_tolerance_Hz"] == 0.1
    assert len(verdict.numbers) == 11


def test_the_run_verdict_fails_on_the_first_quantity_that_left_its_tolerance():
    from hipsim.motion.iso_verdict import binding_quantity, iso_check_verdict

    q = _quantities(beta=("deg", 3.5, 3.0, 1, False), gamma=("deg", 9.0, 3.0, 3, False))
    assert binding_quantity(q) == "beta"  # the first failing, not the one furthest out
    verdict = iso_check_verdict(q, 3)
    assert verdict.level == Level.FAIL and exit_status([verdict]) == 1
    assert verdict.judged == (
        "beta, gamma left the tolerance in 3 whole cycle(s) checked; worst beta: 3.5 deg against ±3 deg "
        "(1 cycle(s) outside)"
    )
    assert verdict.not_judged == TOLERANCES_ASSUMED
    assert verdict.numbers == {
        "cycles": 3.0,
        "alpha_worst_deg": 0.0,
        "alpha_tolerance_deg": 3.0,
        "beta_worst_deg": 3.5,
        "beta_tolerance_deg": 3.0,
        "gamma_worst_deg": 9.0,
        "gamma_tolerance_deg": 3.0,
        "load_worst_N": 0.0,
        "load_tolerance_N": 90.0,
        "frequency_worst_Hz": 0.0,
        "frequency_tolerance_Hz": 0.1,
    }


@pytest.mark.parametrize(("alpha_deg", "level"), [(3.0, Level.PASS), (3.0 + 1e-9, Level.FAIL)])
def test_the_run_verdict_at_the_tolerance_itself(alpha_deg, level):
    """A deviation equal to the tolerance is within it (<=); the summary's verdict is made from its quantities."""
    from hipsim.motion.iso_verdict import iso_check_summary

    s = iso_check_summary(_check(CycleDeviation(0.0, 1.0, alpha_deg, 0.0, 0.0, 0.0)))
    assert s.verdict.level == level and s.level == level and s.passed is (level == Level.PASS)
    assert s.to_json()["verdict"]["level"] == level.value and "passed" not in s.to_json()

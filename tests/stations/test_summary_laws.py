"""hipsim/stations/summary.py's laws by hand: the run's columns in the file's units, the RMS over the right count, the
duration, which platform the carriages serve, the verdict's level, words and numbers at each of its branches, and how
far apart the two platforms turn (``stations --sliders``). Every record here is written by hand, no kinematics run."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hipsim.motion.iso_verdict import DesiredIso, StationIso
from hipsim.motion.trajectories import iso14242
from hipsim.records import Level
from hipsim.stations.commands import StationMotion
from hipsim.stations.summary import (
    AngleError,
    PlatformSummary,
    StationSummary,
    attitude_columns,
    error_columns,
    sliders_summary,
    station_columns,
    station_summary,
    stations_verdict,
)

NAMES = ["alpha_1_deg", "beta_1_deg", "gamma_1_deg", "alpha_2_deg", "beta_2_deg", "gamma_2_deg"]


def _motion(desired_deg, attitudes_deg, t=(0.0, 0.5), control="2", weights=(1.0, 1.0)) -> StationMotion:
    desired, attitudes = np.radians(np.asarray(desired_deg, float)), np.radians(np.asarray(attitudes_deg, float))
    carriages = np.arange(3 * len(t), dtype=float).reshape(len(t), 3) * 0.001 + 0.1
    return StationMotion(np.asarray(t, float), desired, carriages, attitudes, control, weights)


def test_the_columns_are_named_platform_by_platform():
    assert attitude_columns() == NAMES
    assert error_columns() == [f"err_{n}" for n in NAMES]


def test_the_runs_columns_in_mm_and_degrees_and_the_load_only_when_given():
    desired = [[1.0, 2.0, 3.0], [4.0, 5.0, 6.0]]
    attitudes = [[[1.5, 2.0, 3.0], [1.0, 2.0, 2.0]], [[4.0, 5.25, 6.0], [4.0, 5.0, 7.0]]]
    motion = _motion(desired, attitudes)
    columns = station_columns(motion)
    assert list(columns) == ["t_s", "L_11_mm", "L_12_mm", "L_13_mm", *NAMES, *(f"err_{n}" for n in NAMES)]
    assert columns["t_s"] == pytest.approx([0.0, 0.5])
    assert columns["L_11_mm"] == pytest.approx([100.0, 103.0]) and columns["L_13_mm"] == pytest.approx([102.0, 105.0])
    assert columns["alpha_1_deg"] == pytest.approx([1.5, 4.0]) and columns["gamma_2_deg"] == pytest.approx([2.0, 7.0])
    assert columns["beta_1_deg"] == pytest.approx([2.0, 5.25])
    assert columns["err_alpha_1_deg"] == pytest.approx([0.5, 0.0]) and columns["err_beta_1_deg"] == pytest.approx(
        [0.0, 0.25]
    )
    assert columns["err_gamma_2_deg"] == pytest.approx([-1.0, 1.0]) and columns["err_alpha_2_deg"] == pytest.approx(
        [0.0, 0.0], abs=1e-12
    )
    loaded = station_columns(motion, np.array([300, 3000]))
    assert list(loaded)[-1] == "Fe_N" and loaded["Fe_N"].dtype == float
    assert loaded["Fe_N"] == pytest.approx([300.0, 3000.0])


def test_the_rms_is_over_every_sample_platform_and_angle_and_the_duration_from_first_to_last():
    """Three samples from t = 2 s; m_2's beta off by 3°, then 0, then −4°: Σe² = 25 over 18 values."""
    desired = np.zeros((3, 3))
    attitudes = np.zeros((3, 2, 3))
    attitudes[:, 1, 1] = [3.0, 0.0, -4.0]
    summary = station_summary(_motion(desired, attitudes, t=(2.0, 2.5, 3.25), control="1", weights=(2, 0.5)))
    assert summary.samples == 3 and summary.duration_s == pytest.approx(1.25)
    assert summary.sum_squared_error_deg2 == pytest.approx(25.0)
    assert summary.rms_error_deg == pytest.approx(math.sqrt(25.0 / 18.0))
    assert summary.weights == (2.0, 0.5) and isinstance(summary.weights[0], float)
    m1, m2 = summary.platforms
    assert (m1.controlled, m2.controlled) == (True, False)  # --control 1
    beta = m2.angles["beta"]
    assert (beta.rms_deg, beta.peak_deg, beta.peak_at_s) == pytest.approx((math.sqrt(25.0 / 3.0), -4.0, 3.25))
    assert m2.iso is None and summary.verdicts == ()
    both = station_summary(_motion(desired, attitudes, t=(2.0, 2.5, 3.25), control="both"))
    assert [p.controlled for p in both.platforms] == [True, True]


def test_one_sample_lasts_zero_seconds():
    summary = station_summary(_motion([[0.0, 0.0, 0.0]], [[[2.0, 0.0, 0.0], [0.0, 0.0, 0.0]]], t=(4.0,)))
    assert summary.duration_s == 0.0 and summary.samples == 1
    assert summary.rms_error_deg == pytest.approx(math.sqrt(4.0 / 6.0))


def test_the_worst_is_the_first_largest_magnitude():
    angles = {a: AngleError(0.0, 0.0, 0.0) for a in ("alpha", "beta", "gamma")}
    p1 = PlatformSummary(1, angles | {"gamma": AngleError(1.0, -2.0, 0.3)}, True)
    p2 = PlatformSummary(2, angles | {"alpha": AngleError(1.0, 2.0, 0.1), "beta": AngleError(1.0, 1.5, 0.2)}, False)
    summary = StationSummary("1", (1.0, 1.0), 3, 1.0, 0.0, 0.0, (p2, p1))
    platform, angle, worst = summary.worst
    assert (platform, angle, worst.peak_at_s) == (2, "alpha", 0.1)  # −2 and +2 tie: the first in order
    assert StationSummary("1", (1.0, 1.0), 3, 1.0, 0.0, 0.0, (p1, p2)).worst[:2] == (1, "gamma")


def _iso(level: Level, worst: dict[str, float] | None) -> StationIso:
    return StationIso(level, f"{level.value} by hand", worst_deg=worst)


def _summary(iso1: StationIso | None, iso2: StationIso | None) -> StationSummary:
    zero = AngleError(0.0, 0.0, 0.0)
    p1 = PlatformSummary(1, {"alpha": zero, "beta": AngleError(0.5, -0.75, 1.5), "gamma": zero}, False, iso1)
    p2 = PlatformSummary(2, {"alpha": AngleError(0.1, 0.25, 0.5), "beta": zero, "gamma": zero}, True, iso2)
    return StationSummary("2", (1.0, 1.0), 4, 2.0, 1.0, 0.125, (p1, p2))


NOT_JUDGED = "the attitude errors against an acceptance limit (none is set)"


def test_no_station_checked_is_not_made_with_the_errors_numbers():
    for summary in (_summary(None, None), _summary(_iso(Level.NOT_MADE, None), _iso(Level.NOT_MADE, None))):
        verdict = stations_verdict(summary)
        assert verdict.level == Level.NOT_MADE
        assert verdict.judged == "no whole ISO 14242-1 cycle with a load to check"
        assert verdict.not_judged == NOT_JUDGED
        assert verdict.numbers == {"worst_peak_deg": 0.75, "worst_peak_at_s": 1.5, "rms_error_deg": 0.125}


def test_a_failing_station_fails_and_only_the_checked_stations_are_named():
    summary = _summary(_iso(Level.NOT_MADE, None), _iso(Level.FAIL, {"alpha": 1.0, "beta": 4.0, "gamma": 0.5}))
    verdict = stations_verdict(summary)
    assert verdict.level == Level.FAIL and verdict.not_judged == NOT_JUDGED
    assert verdict.judged == "ISO 14242-1 (tolerances assumed): station 2 FAIL"
    assert verdict.numbers == {
        "worst_peak_deg": 0.75,
        "worst_peak_at_s": 1.5,
        "rms_error_deg": 0.125,
        "worst_alpha_2_deg": 1.0,
        "worst_beta_2_deg": 4.0,
        "worst_gamma_2_deg": 0.5,
    }


@pytest.mark.parametrize(
    ("first", "second", "level"),
    [(Level.PASS, Level.PASS, Level.PASS), (Level.FAIL, Level.PASS, Level.FAIL), (Level.PASS, Level.FAIL, Level.FAIL)],
)
def test_any_failing_station_fails_the_run(first, second, level):
    verdict = stations_verdict(_summary(_iso(first, {"alpha": 1.0}), _iso(second, None)))
    assert verdict.level == level
    assert verdict.judged == f"ISO 14242-1 (tolerances assumed): station 1 {first.value}, station 2 {second.value}"
    assert verdict.numbers["worst_alpha_1_deg"] == 1.0 and "worst_alpha_2_deg" not in verdict.numbers


def test_a_desired_motion_off_the_waveform_is_said_in_the_headline():
    """Both stations track a motion 12.5° off the waveform (β the worst of the two): PASS each, on their tracking."""
    off = [
        DesiredIso(False, ("alpha",), {"alpha": 6.0, "beta": 12.5, "gamma": 3.0}),
        DesiredIso(True, (), {"alpha": 0.1}),
    ]
    isos = [dataclasses.replace(_iso(Level.PASS, {"alpha": 1.0}), desired=d) for d in off]
    verdict = stations_verdict(_summary(*isos))
    assert verdict.level == Level.PASS
    assert verdict.judged == (
        "ISO 14242-1 (tolerances assumed): station 1 PASS, station 2 PASS; the desired motion is not the ISO 14242-1 "
        "waveform (worst 12.5° off): each station is judged on its tracking of it"
    )


def test_how_far_apart_the_platforms_turn_per_angle():
    """m_1 − m_2 in alpha: 1°, −3°, 2° (RMS √(14/3), peak 3); beta 0.5° throughout; gamma none."""
    attitudes = np.zeros((3, 2, 3))
    attitudes[:, 0, 0] = np.radians([1.0, -1.0, 2.0])
    attitudes[:, 1, 0] = np.radians([0.0, 2.0, 0.0])
    attitudes[:, 0, 1] = np.radians(0.5)
    summary = sliders_summary("log.csv", attitudes)
    assert summary.log == "log.csv" and summary.samples == 3
    assert summary.platform_difference_rms_deg == pytest.approx((math.sqrt(14 / 3), 0.5, 0.0))
    assert summary.platform_difference_peak_deg == pytest.approx((3.0, 0.5, 0.0))
    assert all(isinstance(v, float) for v in summary.platform_difference_peak_deg)


def test_too_short_a_loaded_run_is_named_by_station_and_not_made():
    attitudes = np.zeros((4, 2, 3))
    motion = _motion(np.zeros((4, 3)), attitudes, t=(0.0, 0.1, 0.2, 0.3))
    named = station_summary(motion, np.full(4, 300.0), source="gait.csv")
    for source, summary in (("trajectory", station_summary(motion, np.full(4, 300.0))), ("gait.csv", named)):
        for j, platform in enumerate(summary.platforms, start=1):
            iso = platform.iso
            assert iso is not None and iso.verdict == Level.NOT_MADE
            assert iso.judged == f"m_{j}'s motion: no ISO 14242-1 check"
            assert iso.reason is not None and f"{source}, station {j}" in iso.reason
        assert stations_verdict(summary).level == Level.NOT_MADE and len(summary.verdicts) == 2


def test_one_iso_cycle_is_whole_only_when_the_run_is_periodic():
    """One ISO 14242-1 cycle at 50 Hz tracked exactly: wrapped around (periodic) it is a whole cycle and passes; read
    as it is, one heel strike makes no whole cycle."""
    iso = iso14242(rate=50.0, cycles=1)
    motion = StationMotion(iso.t, iso.q, np.zeros((len(iso.t), 3)), np.stack([iso.q, iso.q], axis=1), "2")
    wrapped = station_summary(motion, iso.Fe, periodic=True).platforms[0].iso
    assert wrapped is not None and wrapped.verdict == Level.PASS and wrapped.cycles == 1
    once = station_summary(motion, iso.Fe).platforms[1].iso
    assert once is not None and once.verdict == Level.NOT_MADE and once.reason is not None
    assert "trajectory, station 2: found no whole gait cycle" in once.reason


def test_two_samples_last_from_the_first_to_the_second():
    summary = station_summary(_motion(np.zeros((2, 3)), np.zeros((2, 2, 3)), t=(1.0, 1.75)))
    assert summary.duration_s == 0.75 and summary.rms_error_deg == 0.0

"""hipsim/stations/excitation.py's laws by hand: the Fourier series and its derivatives, the file of whole periods, the
limits at their edges, the peaks against the platforms' own motion, and the condition number of one column and of two
that one motion cannot tell apart. (The design itself: tests/stations/test_calibration.py.)"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from hipsim.analytic.stations import platform_jacobian, platform_motion
from hipsim.machine.parameters import load_parameters
from hipsim.motion.trajectories import iso14242
from hipsim.physics.orientation import inverse_condition_number
from hipsim.rig.identification.excitation import Limits
from hipsim.rig.identification.excitation_summary import ExcitationPeaks, limits_verdict
from hipsim.stations import deviations as dv
from hipsim.stations import excitation as excitation_module
from hipsim.stations.excitation import CalibrationExcitation, _peaks, _series, calibration_condition
from hipsim.stations.sensitivity import Structure, attitude_jacobian

LIMITS = Limits(max_angle=math.radians(20.0), max_speed=0.2, max_acceleration=1.5, min_cond_inv=0.3)
EDGE = ExcitationPeaks(angle_deg=20.0, speed_mm_s=200.0, acceleration_mm_s2=1500.0, cond_inv_min=0.3)
PEAKS = ExcitationPeaks(0.0, 0.0, 0.0, 1.0)

#: α = 0.1·sin(ωt) + 0.2·cos(2ωt); β = 0.3·cos(ωt); γ = −0.1·sin(2ωt), ω = 2π·0.5 rad/s.
COEFFICIENTS = np.array([[0.1, 0.0, 0.0, 0.2], [0.0, 0.3, 0.0, 0.0], [0.0, 0.0, -0.1, 0.0]])


def test_the_series_and_its_derivatives_by_hand():
    t = np.array([0.0, 0.25, 0.7])
    w = math.pi
    q, qd, qdd = CalibrationExcitation(0.5, COEFFICIENTS, 1.0, 2.0, PEAKS, LIMITS).angles(t)
    s1, c1, s2, c2 = np.sin(w * t), np.cos(w * t), np.sin(2 * w * t), np.cos(2 * w * t)
    np.testing.assert_allclose(q, np.stack([0.1 * s1 + 0.2 * c2, 0.3 * c1, -0.1 * s2], axis=1), atol=1e-15)
    np.testing.assert_allclose(
        qd, np.stack([0.1 * w * c1 - 0.4 * w * s2, -0.3 * w * s1, -0.2 * w * c2], axis=1), atol=1e-14
    )
    np.testing.assert_allclose(
        qdd, np.stack([-0.1 * w**2 * s1 - 0.8 * w**2 * c2, -0.3 * w**2 * c1, 0.4 * w**2 * s2], axis=1), atol=1e-13
    )


@pytest.mark.parametrize(("duration", "rows"), [(3.0, 41), (2.0, 21), (2.0000001, 41), (0.0, 21)])
def test_the_file_holds_whole_periods_the_last_row_the_first(tmp_path, duration, rows):
    """0.5 Hz at 10 Hz: a period is 2 s, 20 samples; 3 s need two periods, 2 s one (not two by round-off)."""
    design = CalibrationExcitation(0.5, COEFFICIENTS, 1.0, 2.0, PEAKS, LIMITS)
    path = design.write_csv(tmp_path / "motion.csv", rate=10.0, duration=duration)
    table = np.genfromtxt(path, delimiter=",", names=True)
    assert table.dtype.names == ("t_s", "alpha_deg", "beta_deg", "gamma_deg", "Fe_N")
    assert (
        len(table) == rows
        and table["t_s"][1] == pytest.approx(0.1)
        and table["t_s"][-1] == pytest.approx((rows - 1) / 10)
    )
    assert table["alpha_deg"][0] == pytest.approx(math.degrees(0.2)) and table["beta_deg"][0] == pytest.approx(
        math.degrees(0.3)
    )
    assert table["gamma_deg"][2] == pytest.approx(math.degrees(-0.1 * math.sin(0.4 * math.pi)), abs=1e-9)
    assert table["alpha_deg"][-1] == pytest.approx(table["alpha_deg"][0], abs=1e-9)
    assert np.all(table["Fe_N"] == 300.0)


def test_the_limits_hold_on_their_edges():
    assert not limits_verdict(EDGE, LIMITS).failed
    for key, past in (
        ("angle_deg", 20.001),
        ("speed_mm_s", 200.001),
        ("acceleration_mm_s2", 1500.01),
        ("cond_inv_min", 0.2999),
    ):
        assert limits_verdict(dataclasses.replace(EDGE, **{key: past}), LIMITS).failed, key


@pytest.mark.parametrize("seat", [False, True])
def test_the_peaks_are_the_platforms_own(seat):
    """Speed and acceleration the larger of the two platforms' (a seat's lift left out), the singularity measure the
    smaller, the angle the largest of all three."""
    params = load_parameters()
    if seat:
        delta = np.zeros(dv.COUNT)
        delta[dv.names().index("spline_x_1")] = 2e-3
        params = dv.machine(params, delta)
    t = np.arange(40) / 20.0
    peaks = _peaks(params, COEFFICIENTS * 0.5, 0.5, t)
    q, qd, qdd = _series(COEFFICIENTS * 0.5, 0.5, t)
    drawing = load_parameters()
    motion = [platform_motion(drawing, q, qd, qdd, j) for j in (1, 2)]
    assert peaks.angle_deg == pytest.approx(math.degrees(0.15))
    assert peaks.speed_mm_s == pytest.approx(1e3 * max(np.abs(m[1]).max() for m in motion), rel=1e-9)
    assert peaks.acceleration_mm_s2 == pytest.approx(1e3 * max(np.abs(m[2]).max() for m in motion), rel=1e-9)
    cond = min(inverse_condition_number(platform_jacobian(params, q, j)).min() for j in (1, 2))
    assert peaks.cond_inv_min == pytest.approx(cond, rel=1e-12)
    assert 0 < peaks.cond_inv_min < 1 and peaks.speed_mm_s > 10.0


def test_the_condition_of_one_column_and_of_columns_one_motion_cannot_tell_apart():
    params = load_parameters()
    names = dv.names()
    t = np.arange(30) / 30.0
    q = _series(COEFFICIENTS, 1.0, t)[0]
    lever = names.index("lever_11")
    one = Structure(1, np.array([lever]), np.array([], dtype=int), np.zeros((1, 0)), False)
    assert calibration_condition(params, q, seen=one) == pytest.approx(1.0)
    # A translation of platform 1's centre with its U-joints changes no reading: its columns are dependent.
    shift = [names.index(n) for n in ("centre_x_1", "ujoint_x_11", "ujoint_x_12", "ujoint_x_13")]
    dependent = Structure(4, np.array(shift), np.array([], dtype=int), np.zeros((4, 0)), False)
    assert calibration_condition(params, q, seen=dependent) > 1e8
    # Two columns, each made unit norm: the condition of [[1, c], [c, 1]]'s square root, c their cosine.
    two = [lever, names.index("lever_12")]
    pair = Structure(2, np.array(two), np.array([], dtype=int), np.zeros((2, 0)), False)
    Y = attitude_jacobian(params, np.stack([q, q], axis=1), np.array(two)).reshape(-1, 2)
    # With offsets, each column's mean over the samples is no evidence: the columns are centred first.
    for offsets, columns in ((False, Y), (True, Y.reshape(30, 6, 2) - Y.reshape(30, 6, 2).mean(axis=0))):
        unit = columns.reshape(-1, 2) / np.linalg.norm(columns.reshape(-1, 2), axis=0)
        c = abs(float(unit[:, 0] @ unit[:, 1]))
        expected = math.sqrt((1 + c) / (1 - c))
        assert calibration_condition(params, q, offsets, pair) == pytest.approx(expected, rel=1e-9)


def test_the_design_keeps_the_best_of_its_seeds(monkeypatch):
    """Three candidates of two harmonics, amplitudes falling as 1/l, each scaled to the 20° limit and shrunk by 0.9
    until every limit holds (:func:`_within`, pinned above): the one with the smallest condition number is kept."""
    params = load_parameters()
    names = dv.names()
    columns = np.array([names.index("lever_11"), names.index("lever_12")])
    pair = Structure(2, columns, np.array([], dtype=int), np.zeros((2, 0)), False)
    asked: list[bool] = []

    def structure(params: object, offsets: bool) -> Structure:
        asked.append(offsets)
        return pair

    monkeypatch.setattr(excitation_module, "structure", structure)
    limits = Limits(max_angle=math.radians(20.0), max_speed=0.25, max_acceleration=1e3, min_cond_inv=0.01)
    design = excitation_module.calibration_excitation(params, 0.5, 2, limits, seeds=3, offsets=True, seed=7)
    assert asked == [True] and design.frequency == 0.5 and design.coefficients.shape == (3, 4)
    t = np.arange(240) / (240 * 0.5)
    candidates = []
    for k in range(3):
        c = np.random.default_rng([7, k]).normal(size=(3, 4)) / np.array([1.0, 1.0, 2.0, 2.0])
        c *= math.radians(20.0) / np.abs(_series(c, 0.5, t)[0]).max()
        while limits_verdict(_peaks(params, c, 0.5, t), limits).failed:
            c = c * 0.9
        candidates.append((calibration_condition(params, _series(c, 0.5, t)[0], True, pair), c))
    conditions = [condition for condition, _ in candidates]
    assert max(conditions) > 1.01 * min(conditions)  # the choice matters
    condition, best = min(candidates, key=lambda item: item[0])
    np.testing.assert_allclose(design.coefficients, best, rtol=1e-12)
    assert design.condition_number == pytest.approx(condition, rel=1e-12)
    iso = iso14242(rate=240).q
    assert design.iso_condition_number == pytest.approx(calibration_condition(params, iso, True, pair), rel=1e-12)
    assert design.peaks == _peaks(params, best, 0.5, t)

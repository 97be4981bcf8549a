"""Tests of hipsim.motion.trajectories: the built-in ISO 14242-1 cycle (spec §7.2) and the Trajectory type.

Expected values come from the spec's formulas and ranges, written out here;
derivatives are checked against finite differences and against the exact
derivatives of the ISO curves.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim import TrajectoryError
from hipsim.motion.trajectories import Trajectory, iso14242, iso14242_angles, iso14242_load

DEG = math.pi / 180.0
KNOTS = [(0.0, 300.0), (0.12, 3000.0), (0.32, 1500.0), (0.50, 3000.0), (0.62, 300.0), (1.0, 300.0)]


# --------------------------------------------------------------------------- the built-in cycle


def test_iso_defaults():
    traj = iso14242()
    assert isinstance(traj, Trajectory)
    assert len(traj) == 1000
    np.testing.assert_array_equal(traj.t, np.arange(1000) / 1000.0)
    assert traj.t[-1] < 1.0  # the end of the cycle is left out so cycles tile
    assert traj.periodic is True
    assert traj.q.shape == traj.qd.shape == traj.qdd.shape == (1000, 3)
    assert traj.Fe.shape == (1000,)


def test_iso_values_match_spec_formulas():
    # α(s) = 3.5° + 21.5°·cos(2πs); β(s) = 1.5° + 5.5°·cos(2πs − 40°); γ(s) = −4° + 6°·cos(2πs − π).
    traj = iso14242(rate=250)
    s = traj.t
    expected = (
        np.stack(
            [
                3.5 + 21.5 * np.cos(2 * np.pi * s),
                1.5 + 5.5 * np.cos(2 * np.pi * s - 40 * DEG),
                -4.0 + 6.0 * np.cos(2 * np.pi * s - np.pi),
            ],
            axis=1,
        )
        * DEG
    )
    np.testing.assert_allclose(traj.q, expected, rtol=0, atol=1e-14)


def _angle_extremes(n=200_001):
    s = np.linspace(0.0, 1.0, n)
    q, _, _ = iso14242_angles(s)
    return s, np.degrees(q)


def test_iso_angle_ranges_match_standard():
    s, q = _angle_extremes()
    alpha, beta, gamma = q.T
    # Flexion +25° at heel strike s = 0, extension −18° at s = 0.5.
    assert alpha.max() == pytest.approx(25.0, abs=1e-9)
    assert alpha.min() == pytest.approx(-18.0, abs=1e-9)
    assert s[np.argmax(alpha)] in (0.0, 1.0)
    assert s[np.argmin(alpha)] == pytest.approx(0.5, abs=1e-5)
    # Abduction/adduction +7°/−4°, internal/external rotation +2°/−10°.
    assert beta.max() == pytest.approx(7.0, abs=1e-8)
    assert beta.min() == pytest.approx(-4.0, abs=1e-8)
    assert gamma.max() == pytest.approx(2.0, abs=1e-8)
    assert gamma.min() == pytest.approx(-10.0, abs=1e-8)
    # β lags by 40° of the cycle: its maximum at s = 40/360.
    assert s[np.argmax(beta)] == pytest.approx(40.0 / 360.0, abs=1e-5)
    # γ is at its minimum at heel strike and its maximum at s = 0.5.
    assert gamma[0] == pytest.approx(-10.0, abs=1e-12)
    assert s[np.argmax(gamma)] == pytest.approx(0.5, abs=1e-5)


def test_iso_angle_rates_never_vanish_together():
    s = np.linspace(0.0, 1.0, 100_001)
    _, qd, _ = iso14242_angles(s)
    assert np.linalg.norm(qd, axis=1).min() > 0.05


@pytest.mark.parametrize(("s", "load"), KNOTS)
def test_iso_load_at_knots(s, load):
    assert iso14242_load(np.array([s]))[0] == pytest.approx(load, abs=1e-9)


def test_iso_load_is_300N_through_swing():
    s = np.linspace(0.62, 1.0, 3801)
    np.testing.assert_allclose(iso14242_load(s), 300.0, rtol=0, atol=1e-9)


def test_iso_load_no_overshoot_between_knots():
    s = np.linspace(0.0, 1.0, 100_001)
    load = iso14242_load(s)
    assert load.min() >= 300.0 - 1e-9
    assert load.max() <= 3000.0 + 1e-9
    # Monotone between consecutive knots (PCHIP).
    for (s0, f0), (s1, f1) in zip(KNOTS[:-1], KNOTS[1:]):
        segment = load[(s >= s0) & (s <= s1)]
        steps = np.diff(segment) * np.sign(f1 - f0) if f1 != f0 else np.abs(np.diff(segment))
        assert steps.min() >= -1e-9, (s0, s1)


def test_iso_load_is_the_pchip_of_the_knots():
    # Every knot is a local extremum or borders a flat segment, so Fritsch–Carlson PCHIP
    # gives it zero slope and each piece is the cubic Hermite step f0 + (f1 − f0)(3u² − 2u³).
    s = np.linspace(0.0, 1.0, 20_001)
    expected = np.empty_like(s)
    for (s0, f0), (s1, f1) in zip(KNOTS[:-1], KNOTS[1:]):
        inside = (s >= s0) & (s <= s1)
        u = (s[inside] - s0) / (s1 - s0)
        expected[inside] = f0 + (f1 - f0) * (3 * u**2 - 2 * u**3)
    np.testing.assert_allclose(iso14242_load(s), expected, rtol=0, atol=1e-8)


def test_iso_load_continuous_across_period_boundary():
    h = 1e-6
    left = iso14242_load(np.array([1.0 - 2 * h, 1.0 - h]))
    right = iso14242_load(np.array([1.0, 1.0 + h, 1.0 + 2 * h]))
    at_zero = iso14242_load(np.array([0.0, h, 2 * h]))
    np.testing.assert_allclose(right, at_zero, rtol=0, atol=1e-9)  # periodic
    # Value: both one-sided limits are 300 N.
    assert left[-1] == pytest.approx(300.0, abs=1e-6)
    assert right[1] == pytest.approx(300.0, abs=1e-6)
    # Slope from both sides (one-sided second-order differences) agree.
    slope_left = (3 * right[0] - 4 * left[1] + left[0]) / (2 * h)
    slope_right = (-3 * right[0] + 4 * right[1] - right[2]) / (2 * h)
    assert abs(slope_left - slope_right) < 1e-3  # N per cycle; the load spans 2700 N
    # And the curve reaches 3000 N at 0.12 from 300 N, so a kink would be visible:
    # compare with the slope a tenth of the way up.
    assert abs(iso14242_load(np.array([0.012 + h]))[0] - iso14242_load(np.array([0.012]))[0]) / h > 1000.0


def test_iso_load_continuous_at_time_boundary_of_a_2hz_cycle():
    t = np.array([0.5 - 1e-7, 0.5, 0.5 + 1e-7])
    load = iso14242_load(t, frequency=2.0)
    np.testing.assert_allclose(load, 300.0, rtol=0, atol=1e-6)


@pytest.mark.parametrize("frequency", [1.0, 2.0, 0.7])
def test_iso_exact_derivatives_vs_finite_differences(frequency):
    t = np.linspace(0.0, 1.0 / frequency, 997)
    q, qd, qdd = iso14242_angles(t, frequency)
    # Central differences: truncation (ωh)²/6 relative, roundoff eps·|q|/(h·|q̇|); h = 1e-5 s
    # puts both below 1e-9 of the peak.
    h = 1e-5
    qp, qdp, _ = iso14242_angles(t + h, frequency)
    qm, qdm, _ = iso14242_angles(t - h, frequency)
    fd1 = (qp - qm) / (2 * h)
    fd2 = (qdp - qdm) / (2 * h)
    assert np.abs(fd1 - qd).max() <= 1e-6 * np.abs(qd).max()
    assert np.abs(fd2 - qdd).max() <= 1e-6 * np.abs(qdd).max()
    # The second difference of q itself (h larger: roundoff goes as eps/h²).
    h2 = 1e-4
    qp2, _, _ = iso14242_angles(t + h2, frequency)
    qm2, _, _ = iso14242_angles(t - h2, frequency)
    fd2q = (qp2 - 2 * q + qm2) / h2**2
    assert np.abs(fd2q - qdd).max() <= 1e-6 * np.abs(qdd).max()
    # The peaks themselves: flexion rate 21.5°·2πf, acceleration 21.5°·(2πf)².
    w = 2 * np.pi * frequency
    assert np.abs(qd[:, 0]).max() == pytest.approx(21.5 * DEG * w, rel=1e-4)
    assert np.abs(qdd[:, 0]).max() == pytest.approx(21.5 * DEG * w**2, rel=1e-4)


def test_iso_trajectory_derivatives_are_exact():
    traj = iso14242(rate=500)
    q, qd, qdd = iso14242_angles(traj.t)
    np.testing.assert_array_equal(traj.q, q)
    np.testing.assert_array_equal(traj.qd, qd)
    np.testing.assert_array_equal(traj.qdd, qdd)
    np.testing.assert_array_equal(traj.Fe, iso14242_load(traj.t))


def test_iso_frequency_halves_the_period():
    slow = iso14242(rate=1000, frequency=1.0)
    fast = iso14242(rate=1000, frequency=2.0)
    assert len(fast) == 500
    assert fast.periodic
    np.testing.assert_array_equal(fast.t, np.arange(500) / 1000.0)
    # q_2Hz(t) = q_1Hz(2t); its rates double and accelerations quadruple.
    np.testing.assert_allclose(fast.q, slow.q[::2], rtol=0, atol=1e-13)
    np.testing.assert_allclose(fast.qd, 2 * slow.qd[::2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(fast.qdd, 4 * slow.qdd[::2], rtol=0, atol=1e-11)
    np.testing.assert_allclose(fast.Fe, slow.Fe[::2], rtol=0, atol=1e-9)
    # Extension −18° at t = 0.25 s.
    assert np.degrees(fast.q[250, 0]) == pytest.approx(-18.0, abs=1e-12)


@pytest.mark.parametrize(
    ("rate", "cycles", "frequency", "n", "periodic"),
    [
        (200, 1, 1.0, 200, True),
        (1000, 3, 1.0, 3000, True),
        (1000, 0.3, 1.0, 300, False),
        (100, 2.5, 1.0, 250, False),
        (500, 2, 2.0, 500, True),
        (1000, 1, 0.5, 2000, True),
    ],
)
def test_iso_rate_cycles_frequency(rate, cycles, frequency, n, periodic):
    traj = iso14242(rate=rate, cycles=cycles, frequency=frequency)
    assert len(traj) == n
    assert traj.periodic is periodic
    np.testing.assert_allclose(traj.t, np.arange(n) / rate, rtol=0, atol=1e-15)
    if periodic:  # the next sample after the last would be the first again
        q_next, _, _ = iso14242_angles(np.array([n / rate]), frequency)
        np.testing.assert_allclose(q_next[0], traj.q[0], rtol=0, atol=1e-13)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"rate": 0},
        {"rate": -1000},
        {"rate": math.nan},
        {"rate": math.inf},
        {"rate": "1000"},
        {"cycles": 0},
        {"cycles": -1},
        {"cycles": math.nan},
        {"cycles": 1e-4},  # fewer than 2 samples
        {"frequency": 0},
        {"frequency": -1.0},
        {"frequency": None},
    ],
)
def test_iso_bad_arguments(kwargs):
    with pytest.raises(TrajectoryError) as info:
        iso14242(**kwargs)
    name = next(iter(kwargs))
    assert "ISO 14242-1" in str(info.value)
    if name != "cycles" or kwargs[name] != 1e-4:
        assert name in str(info.value)


def test_trajectory_is_read_only():
    traj = iso14242(rate=100)
    with pytest.raises(ValueError, match="read-only"):
        traj.q[0, 0] = 1.0
    with pytest.raises(ValueError, match="read-only"):
        traj.t[0] = 1.0


# --------------------------------------------------------------------------- the Trajectory object


def test_trajectory_rejects_bad_shapes_and_non_finite():
    t = np.arange(5) / 10.0
    good = np.zeros((5, 3))
    with pytest.raises(TrajectoryError):
        Trajectory(t, np.zeros((5, 2)), good, good, np.zeros(5))
    with pytest.raises(TrajectoryError):
        Trajectory(t, good, good, good, np.zeros(4))
    bad = good.copy()
    bad[3, 1] = np.nan
    with pytest.raises(TrajectoryError) as info:
        Trajectory(t, good, bad, good, np.zeros(5), name="mine")
    assert "mine" in str(info.value) and "qd" in str(info.value) and "0.3" in str(info.value)


def test_trajectory_slice():
    traj = iso14242(rate=100)
    part = traj.slice(slice(10, 20))
    assert len(part) == 10 and part.periodic is False
    np.testing.assert_array_equal(part.q, traj.q[10:20])
    np.testing.assert_array_equal(part.Fe, traj.Fe[10:20])

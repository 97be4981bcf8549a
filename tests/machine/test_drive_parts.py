"""A linear module's drive-train parts (hipsim.machine.drive_parts): torque–speed curves, top speed, names, checks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.machine.drive_parts import DIRECT, END_FIXINGS, Drive, Gearbox, LeadScrew, Motor, TorqueSpeedCurve


def test_a_curve_is_linear_between_points_and_zero_beyond():
    curve = TorqueSpeedCurve(np.array([100.0, 200.0]), np.array([2.0, 1.0]))
    np.testing.assert_allclose(curve.at([0.0, -150.0, 200.0, 250.0]), [2.0, 1.5, 1.0, 0.0])
    assert curve.at(200.0 + 1e-9) == 0.0  # just past the end: the motor cannot go faster
    assert not curve.flat and curve.end_speed == 200.0


def test_a_single_point_is_flat_at_every_speed():
    flat = TorqueSpeedCurve(np.array(3.0), np.array(0.5))  # scalars become one point
    assert flat.flat and flat.end_speed == math.inf
    assert flat.at([0.0, -1e6, 1e9]).tolist() == [0.5, 0.5, 0.5]
    assert flat.speed.shape == (1,) and not flat.speed.flags.writeable


@pytest.mark.parametrize(
    ("speed", "torque", "message"),
    [
        ([0.0, 100.0], [1.0], "must be equal non-empty"),
        ([], [], "must be equal non-empty"),
        ([0.0, 100.0, 100.0], [1.0, 1.0, 1.0], "rise strictly"),  # equal speeds: not rising
        ([-1.0, 100.0], [1.0, 1.0], "from ≥ 0"),
        ([0.0, 100.0], [1.0, -1e-12], "not be negative"),
    ],
)
def test_a_bad_curve_says_what_is_wrong(speed, torque, message):
    with pytest.raises(ValueError, match=message):
        TorqueSpeedCurve(np.array(speed), np.array(torque))


def test_edges_that_are_accepted():
    curve = TorqueSpeedCurve(np.array([0.0, 1e-9]), np.array([0.0, 0.0]))  # speed 0 and torque 0 allowed
    assert curve.at(0.0) == 0.0


def test_the_top_speed_is_the_max_speed_then_the_peak_then_the_s1_curve():
    peak = TorqueSpeedCurve(np.array([0.0, 300.0]), np.array([2.0, 0.0]))
    s1 = TorqueSpeedCurve(np.array([0.0, 250.0]), np.array([1.0, 0.5]))
    flat = TorqueSpeedCurve(np.array([0.0]), np.array([1.0]))
    assert Motor("m", s1, peak, max_speed=100.0).top_speed == 100.0
    assert Motor("m", s1, peak).top_speed == 300.0
    assert Motor("m", s1, flat).top_speed == 250.0  # a flat peak curve says nothing of speed
    assert Motor("m", flat, flat).top_speed is None
    assert Motor("m").top_speed is None


def test_a_drives_name_leaves_out_a_direct_coupling():
    motor = Motor("M")
    assert Drive(motor).name == "M"
    assert Drive(motor, gearbox=DIRECT, screw=LeadScrew("S")).name == "M + S"
    assert Drive(motor, gearbox=Gearbox("G", 2.0), screw=LeadScrew("S")).name == "M + G + S"


def test_an_unknown_end_fixing_is_refused_naming_the_known_ones():
    with pytest.raises(
        ValueError, match="fixed-free, supported-supported, fixed-supported, fixed-fixed, got 'clamped'"
    ):
        LeadScrew("s", end_fixing="clamped")
    assert LeadScrew("s", end_fixing="fixed-fixed").end_fixing == "fixed-fixed"


def test_the_end_fixings_are_the_beam_roots_and_the_effective_lengths():
    # λ·l: the first roots of cos·cosh = −1 (fixed-free), sin = 0 (supported), tan = tanh, cos·cosh = 1 (fixed-fixed)
    free, supported, fixed_supported, fixed = (END_FIXINGS[k][0] for k in END_FIXINGS)
    assert math.cos(free) * math.cosh(free) == pytest.approx(-1.0, abs=1e-3)
    assert math.sin(supported) == pytest.approx(0.0, abs=1e-15)
    assert math.tan(fixed_supported) == pytest.approx(math.tanh(fixed_supported), abs=1e-3)
    assert math.cos(fixed) * math.cosh(fixed) == pytest.approx(1.0, abs=1e-2)
    # Euler factors 1/K² for K = 2, 1, 0.699, 0.5
    assert [END_FIXINGS[k][1] for k in END_FIXINGS] == pytest.approx([0.25, 1.0, 1 / 0.699**2, 4.0], rel=1e-3)

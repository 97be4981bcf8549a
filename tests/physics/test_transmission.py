"""hipsim.physics.transmission by hand: θ = 2π·L/p, its ratio 2π/p and inverse p/2π, a lead from a ratio."""

from __future__ import annotations

import math

import numpy as np
from numpy.testing import assert_allclose

from hipsim.physics.transmission import (
    TWO_PI,
    angle_from_travel,
    lead_from_ratio,
    radians_per_travel,
    travel_per_radian,
)


def test_one_lead_of_travel_is_one_motor_turn():
    assert angle_from_travel(0.005, 0.005) == 2 * math.pi
    assert_allclose(angle_from_travel(np.array([0.0, 0.0025, -0.01]), 0.005), [0.0, math.pi, -4 * math.pi], rtol=1e-15)
    assert TWO_PI == 2 * math.pi


def test_the_ratio_and_its_inverse():
    assert_allclose(radians_per_travel(0.01), 628.3185307179587, rtol=1e-15)  # 2π/0.01 rad/m
    assert_allclose(travel_per_radian(0.01), 0.0015915494309189533, rtol=1e-15)  # 0.01/2π m/rad
    assert_allclose(radians_per_travel(0.004) * travel_per_radian(0.004), 1.0, rtol=1e-15)


def test_a_slider_force_as_a_motor_torque():
    # τ = F·p/2π: 1000 N on a 5 mm lead is 0.7958 N·m at the motor (no losses here).
    assert_allclose(1000.0 * travel_per_radian(0.005), 0.7957747154594768, rtol=1e-15)


def test_a_lead_from_a_mujoco_gear():
    assert_allclose(lead_from_ratio(1000 * math.pi), 0.002, rtol=1e-15)  # gear 1000π rad/m: 2 mm a turn
    assert_allclose(lead_from_ratio(radians_per_travel(0.005)), 0.005, rtol=1e-15)

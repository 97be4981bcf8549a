"""Tests of hipsim.motion.hip_angles: the ISB hip chain ↔ the platform angles.

Expected values come from rotation matrices written out here (elementary
rotations, products, the closed-form Z–X–Y and Z–Y–X angles), not from SciPy.
"""

from __future__ import annotations

import numpy as np
import pytest
from support import Rx, Ry, Rz, machine_R, zxy_angles, zyx_angles

from hipsim.exceptions import ArgumentError
from hipsim.motion.hip_angles import (
    PELVIS_AXES,
    hip_angles_of,
    hip_rotation,
    hip_to_machine,
    machine_rotation,
    machine_to_hip,
)

RNG = np.random.default_rng(11)
SAMPLES = RNG.uniform(np.radians([-40, -30, -40]), np.radians([60, 30, 40]), (200, 3))


def test_pelvis_axes_map_the_body_onto_the_machine():
    # Pelvis x (anterior) is machine +Y, y (superior) is +Z, z (the subject's right) is +X.
    np.testing.assert_array_equal(PELVIS_AXES @ [1, 0, 0], [0, 1, 0])
    np.testing.assert_array_equal(PELVIS_AXES @ [0, 1, 0], [0, 0, 1])
    np.testing.assert_array_equal(PELVIS_AXES @ [0, 0, 1], [1, 0, 0])


def test_compositions_of_many_rows_at_once():
    stacked = hip_rotation(SAMPLES[:5])
    assert stacked.shape == (5, 3, 3) and hip_rotation(SAMPLES[:1]).shape == (1, 3, 3)
    for R, hip in zip(stacked, SAMPLES[:5]):
        np.testing.assert_allclose(R, Rz(hip[0]) @ Rx(hip[1]) @ Ry(hip[2]), rtol=0, atol=1e-15)
    assert machine_rotation(SAMPLES[:4]).shape == (4, 3, 3)
    assert hip_angles_of(machine_rotation(SAMPLES[:4])).shape == (4, 3)


def test_compositions_are_the_written_out_products():
    for hip, q in zip(SAMPLES[:20], SAMPLES[20:40]):
        np.testing.assert_allclose(hip_rotation(hip), Rz(hip[0]) @ Rx(hip[1]) @ Ry(hip[2]), rtol=0, atol=1e-15)
        np.testing.assert_allclose(machine_rotation(q), machine_R(*q), rtol=0, atol=1e-15)


def test_hip_to_machine_matches_the_closed_form_route():
    C = PELVIS_AXES
    q = hip_to_machine(SAMPLES)
    for hip, (alpha, beta, gamma) in zip(SAMPLES, q):
        R = C @ Rz(hip[0]) @ Rx(hip[1]) @ Ry(hip[2]) @ C.T
        np.testing.assert_allclose([alpha, beta, gamma], zyx_angles(R), rtol=0, atol=1e-13)


def test_machine_to_hip_matches_the_closed_form_route():
    C = PELVIS_AXES
    hip = machine_to_hip(SAMPLES)
    for q, angles in zip(SAMPLES, hip):
        np.testing.assert_allclose(angles, zxy_angles(C.T @ machine_R(*q) @ C), rtol=0, atol=1e-13)


def test_round_trips_both_ways():
    np.testing.assert_allclose(machine_to_hip(hip_to_machine(SAMPLES)), SAMPLES, rtol=0, atol=1e-12)
    np.testing.assert_allclose(hip_to_machine(machine_to_hip(SAMPLES)), SAMPLES, rtol=0, atol=1e-12)
    np.testing.assert_allclose(hip_angles_of(machine_rotation(SAMPLES)), machine_to_hip(SAMPLES), rtol=0, atol=1e-15)


@pytest.mark.parametrize("axis", [0, 1, 2])
def test_one_angle_at_a_time_the_two_sets_agree(axis):
    """Flexion alone is α, adduction alone β, internal rotation alone γ (machine axes: X right, Y anterior, Z up)."""
    angles = np.zeros((7, 3))
    angles[:, axis] = np.radians([-30, -10, -1, 0, 2, 15, 40])
    np.testing.assert_allclose(hip_to_machine(angles), angles, rtol=0, atol=1e-15)


def test_combined_they_differ_as_the_chains_order_says():
    # Flexion 30° then adduction 10° about the flexed femur's anterior axis: for the machine,
    # which turns about the vertical first and flexes last, that is not β = 10° alone.
    q = np.degrees(hip_to_machine(np.radians([30.0, 10.0, 0.0])))
    assert np.abs(q - [30.0, 10.0, 0.0]).max() > 0.5, q


def test_shapes_follow_the_input():
    assert hip_to_machine(np.zeros(3)).shape == (3,)
    assert machine_to_hip(np.zeros((4, 3))).shape == (4, 3)
    assert hip_rotation(np.zeros(3)).shape == (3, 3)
    assert hip_angles_of(np.eye(3)).shape == (3,)
    with pytest.raises(ValueError, match="shape"):
        hip_to_machine(np.zeros(4))


def test_a_wrong_shape_is_named_with_the_shape_given():
    for call in (hip_to_machine, machine_to_hip, hip_rotation, machine_rotation):
        # A HipsimError (one line at the command line), still a ValueError for code that catches that.
        with pytest.raises(ArgumentError) as refused:
            call(np.zeros((2, 4)))
        assert isinstance(refused.value, ValueError)
        assert str(refused.value) == "angles: expected shape (3,) or (N, 3), got shape (2, 4)"

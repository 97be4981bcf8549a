"""hipsim/stations/sensitivity.py against central differences of the inverse kinematics and against moving one value:
∂f_j/∂q under flipped angle signs, ∂q_j/∂δ for each platform (m_1's seat with m_2's attitude), the closed-form 3x3
inverse, the random poses, and the structure's order of preference and definitions written by hand."""

from __future__ import annotations

import math

import numpy as np
import pytest

from hipsim.analytic.stations import carriages_for_platform
from hipsim.machine.parameters import load_parameters
from hipsim.stations import deviations as dv
from hipsim.stations.commands import attitudes
from hipsim.stations.sensitivity import (
    POSE_RANGE,
    Structure,
    _preference,
    attitude_jacobian,
    inverse3,
    platform_attitude_jacobian,
    random_poses,
    reading_rate,
    structure,
)

Q = np.radians(np.array([[10.0, 4.0, -6.0], [-8.0, -3.0, 12.0]]))
H = 1e-6


@pytest.fixture(scope="module")
def flipped():
    """The drawing with β and γ's signs flipped: the rate must carry the signs on both sides."""
    params = load_parameters()
    return params.replace(angle_signs=np.array([1.0, -1.0, -1.0]))


@pytest.mark.parametrize("j", [1, 2])
def test_the_reading_rate_is_the_slope_of_the_inverse_kinematics(flipped, j):
    rate = reading_rate(flipped, Q, j)
    for k in range(3):
        dq = np.zeros(3)
        dq[k] = H
        slope = (carriages_for_platform(flipped, Q + dq, j) - carriages_for_platform(flipped, Q - dq, j)) / (2 * H)
        np.testing.assert_allclose(rate[:, :, k], slope, rtol=1e-6, atol=1e-9)


def test_the_inverse_of_3x3_matrices_and_inf_where_singular():
    P = np.array(
        [[[2.0, 0.0, 0.0], [0.0, 4.0, 0.0], [0.0, 0.0, 0.5]], [[1.0, 2.0, 0.0], [0.0, 1.0, 3.0], [0.0, 0.0, 1.0]]]
    )
    expected = np.array(
        [[[0.5, 0, 0], [0, 0.25, 0], [0, 0, 2.0]], [[1.0, -2.0, 6.0], [0.0, 1.0, -3.0], [0.0, 0.0, 1.0]]]
    )
    np.testing.assert_allclose(inverse3(P), expected, atol=1e-15)
    singular = inverse3(np.ones((1, 3, 3)))
    assert not np.all(np.isfinite(singular))


def _moved(params, name: str, step: float):
    delta = dv.deviation(params)
    delta[dv.names().index(name)] += step
    return dv.machine(params, delta)


@pytest.mark.parametrize(("name", "j"), [("lever_22", 2), ("joint_y_13", 1), ("slider_21", 2), ("spline_x_1", 1)])
def test_the_attitude_moves_as_the_jacobian_says(name, j):
    """The carriages that put platform j at Q held, one value moved by ±1 µm: the attitude's change by central
    difference (m_1 rides on m_2's tilt through the seat: m_2 at Q, so its rotation is the same for both)."""
    params = dv.machine(load_parameters(), np.zeros(dv.COUNT))
    L = carriages_for_platform(params, Q, 2)  # both platforms at Q on the drawing
    column = list(dv.platform_columns(j)).index(dv.names().index(name))
    J = platform_attitude_jacobian(params, Q, j, Q)[:, :, column]
    plus = attitudes(_moved(params, name, 1e-6), L, np.stack([Q, Q], axis=1))[:, j - 1]
    minus = attitudes(_moved(params, name, -1e-6), L, np.stack([Q, Q], axis=1))[:, j - 1]
    np.testing.assert_allclose(J, (plus - minus) / 2e-6, rtol=1e-4, atol=1e-6)
    assert np.abs(J).max() > 1.0  # [rad/m]: a value that moves the attitude
    both = attitude_jacobian(params, np.stack([Q, Q], axis=1))
    k = dv.names().index(name)
    np.testing.assert_allclose(both[:, j - 1, :, k], J, rtol=1e-12, atol=1e-15)
    assert np.all(both[:, 2 - j, :, k] == 0.0)  # the other platform does not move
    np.testing.assert_array_equal(
        attitude_jacobian(params, np.stack([Q, Q], axis=1), np.array([k, 0])), both[..., [k, 0]]
    )


def test_random_poses_within_twenty_degrees():
    q = random_poses(500, seed=3)
    assert q.shape == (500, 3) and math.degrees(POSE_RANGE) == pytest.approx(20.0)
    assert np.abs(q).max() <= POSE_RANGE and np.abs(q).max() > 0.95 * POSE_RANGE
    assert np.array_equal(q, random_poses(500, seed=3)) and not np.array_equal(q, random_poses(500, seed=4))
    assert random_poses().shape == (240, 3)


def test_the_order_of_preference():
    names = dv.names()
    order = [names[k] for k in _preference()]
    assert order[:6] == ["lever_11", "lever_12", "lever_13", "lever_21", "lever_22", "lever_23"]
    assert order[6] == "slider_11" and order[12] == "ujoint_x_11" and order[18] == "ujoint_y_11"
    assert order[24:27] == ["joint_x_11", "joint_x_12", "joint_x_13"]
    assert order[-9:] == [
        "centre_x_1",
        "centre_x_2",
        "centre_y_1",
        "centre_y_2",
        "centre_z_1",
        "centre_z_2",
        "spline_x_1",
        "spline_y_1",
        "spline_z_1",
    ]
    assert sorted(_preference()) == list(range(dv.COUNT))


def test_definitions_name_what_each_estimated_value_absorbs():
    names = dv.names()
    k = [names.index(n) for n in ("slider_11", "lever_12", "centre_z_1", "centre_x_2")]
    seen = Structure(2, np.array(k[:2]), np.array(k[2:]), np.array([[1.0, -2.5e-7], [0.0, 0.0]]), False)
    assert seen.definitions() == ["slider_11 + 1·centre_z_1"]  # a coefficient under 1e-6 is left out
    seen = Structure(2, np.array(k[:2]), np.array(k[2:]), np.array([[-1.0, 0.5], [2e-6, -1.23456789]]), True)
    assert seen.definitions() == [
        "slider_11 − 1·centre_z_1 + 0.5·centre_x_2",
        "lever_12 + 2e-06·centre_z_1 − 1.23457·centre_x_2",
    ]
    assert seen.definitions(tol=0.6) == ["slider_11 − 1·centre_z_1", "lever_12 − 1.23457·centre_x_2"]


def test_m_1s_seat_column_follows_m_2s_own_attitude():
    """The platforms at different attitudes on a machine with a seat: m_1's seat column is taken at m_2's attitude."""
    delta = np.zeros(dv.COUNT)
    delta[dv.names().index("spline_x_1")] = 2e-3
    params = dv.machine(load_parameters(), delta)
    q = np.stack([Q, Q[::-1]], axis=1)  # m_2 elsewhere
    both = attitude_jacobian(params, q)
    np.testing.assert_allclose(
        both[:, 0][..., dv.platform_columns(1)], platform_attitude_jacobian(params, Q, 1, Q[::-1])
    )
    seat = dv.names().index("spline_x_1")
    assert np.abs(both[:, 0, :, seat] - attitude_jacobian(params, np.stack([Q, Q], axis=1))[:, 0, :, seat]).max() > 1e-3


def test_what_folds_into_what_and_what_the_offsets_take():
    """Without offsets each platform's U-joints fold its centre's x and y (a translation) and its sliders its
    centre's z (a lift): 18 coefficients, each −1, the rest exactly 0. With an offset per sensor angle, the six
    centre values stay unseen and fewer combinations are seen."""
    drawing = load_parameters()
    seen = structure(drawing, offsets=False)
    assert np.count_nonzero(seen.coefficients) == 18 and seen.offsets is False
    np.testing.assert_allclose(seen.coefficients[seen.coefficients != 0], -1.0, atol=1e-6)
    assert seen.definitions()[:2] == ["ujoint_x_11 − 1·centre_x_1", "ujoint_y_11 − 1·centre_y_1"]
    assert seen.definitions()[12] == "slider_11 − 1·centre_z_1" and len(seen.definitions()) == 18
    offsets = structure(drawing, offsets=True)
    assert offsets.offsets is True and offsets.rank < seen.rank
    centres = {f"centre_{a}_{j}" for a in "xyz" for j in (1, 2)}
    assert centres <= {dv.names()[k] for k in offsets.dependent}

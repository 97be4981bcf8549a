"""Forward kinematics: slider heights back to the orientation, against the inverse kinematics."""

import numpy as np
import pytest
from support import SmoothMotion

import hipsim
from hipsim.analytic.forward_kinematics import forward_kinematics, solve_pose
from hipsim.analytic.inverse_kinematics import (
    angular_velocity_map,
    inverse_condition_number,
    slider_heights,
    slider_jacobian,
)
from hipsim.exceptions import PoseError

PARAMS = hipsim.load_parameters()


def heights(params, q):
    """Platform 1's slider heights of gait angles q (the inverse kinematics)."""
    return slider_heights(params, q * params.angle_signs)[:, 0]


def in_mode(params, q, margin=0.1):
    """Poses in the published machine's assembly mode (det J of home's sign), with a singularity measure above ``margin``."""
    J = slider_jacobian(params, q * params.angle_signs)
    home = np.sign(np.linalg.det(slider_jacobian(params, np.zeros((1, 3)))[0]))
    return (
        np.isfinite(J).all(axis=(1, 2)) & (np.sign(np.linalg.det(J)) == home) & (inverse_condition_number(J) > margin)
    )


def test_round_trip_along_the_iso_cycle():
    trajectory = hipsim.iso14242(rate=1000, cycles=2)
    q = forward_kinematics(PARAMS, heights(PARAMS, trajectory.q), trajectory.t)
    assert np.abs(q - trajectory.q).max() < 1e-9


def test_round_trip_at_random_poses():
    rng = np.random.default_rng(7)
    q = np.radians(rng.uniform(-30, 30, (3000, 3)))
    q = q[in_mode(PARAMS, q)]
    assert len(q) > 1000
    L = heights(PARAMS, q)
    near = q + np.radians(rng.uniform(-4, 4, q.shape))  # each from a guess a few degrees off
    assert np.abs(solve_pose(PARAMS, L, near) - q).max() < 1e-9
    small = np.abs(q).max(axis=1) < np.radians(15)
    assert np.abs(solve_pose(PARAMS, L[small]) - q[small]).max() < 1e-9  # from home


def test_round_trip_along_a_smooth_random_motion_with_flipped_signs():
    params = PARAMS.replace(angle_signs=np.array([1.0, -1.0, -1.0]))
    trajectory = SmoothMotion(seed=4, amplitude_deg=20)(np.arange(0, 3, 1e-3))
    q = forward_kinematics(params, heights(params, trajectory.q), trajectory.t)
    assert np.abs(q - trajectory.q).max() < 1e-9


def test_far_from_home_the_log_is_continued_from_the_start_pose():
    # A ramp to 32° flexion: from home, a far sample may converge elsewhere; continuation along the log does not.
    q = np.radians(np.column_stack([np.linspace(0, 32, 400), np.linspace(0, -8, 400), np.linspace(0, 12, 400)]))
    assert in_mode(PARAMS, q).all()
    assert np.abs(forward_kinematics(PARAMS, heights(PARAMS, q)) - q).max() < 1e-9


def test_newton_uses_the_true_jacobian():
    """∂L/∂q = J·T, the step the solver takes, against central differences of the slider heights."""
    q = np.radians([[10.0, -4.0, 6.0]])
    h = 1e-6
    numeric = np.stack(
        [(heights(PARAMS, q + h * e) - heights(PARAMS, q - h * e))[0] / (2 * h) for e in np.eye(3)], axis=1
    )
    analytic = slider_jacobian(PARAMS, q)[0] @ angular_velocity_map(q)[0]
    np.testing.assert_allclose(analytic, numeric, rtol=0, atol=1e-8)


def test_unreachable_heights_are_refused_by_sample():
    L = heights(PARAMS, hipsim.iso14242(rate=100).q).copy()
    L[40, 1] += 0.5  # half a metre: no pose reaches it
    with pytest.raises(PoseError, match=r"t = 0\.4 s.*no platform orientation gives the slider heights") as error:
        forward_kinematics(PARAMS, L, np.arange(len(L)) / 100, source="log.csv")
    assert error.value.index == 40
    assert "log.csv" in str(error.value)


def test_another_assembly_mode_is_refused():
    rng = np.random.default_rng(3)
    q = np.radians(rng.uniform(-30, 30, (5000, 3)))
    J = slider_jacobian(PARAMS, q)
    other = q[
        np.isfinite(J).all(axis=(1, 2))
        & (np.linalg.det(J) * np.linalg.det(slider_jacobian(PARAMS, np.zeros((1, 3)))[0]) < 0)
        & (inverse_condition_number(J) > 1e-3)
    ]
    assert len(other), "the sample should hold poses of the other mode"
    with pytest.raises(PoseError, match="another assembly mode"):
        solve_pose(PARAMS, heights(PARAMS, other[:1]), other[:1])

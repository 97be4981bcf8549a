"""Analytic kinematics (spec §3): every derivative against finite differences of the level below."""

import numpy as np
import pytest
from support import SmoothMotion, central_difference, iso_at, relative_error

import hipsim
from hipsim.analytic.inverse_kinematics import (
    angular_velocity_map,
    inverse_condition_number,
    kinematics,
    lever_frames,
    lever_jacobians,
    lever_rotation,
    rotation_matrix,
    slider_heights,
)
from hipsim.exceptions import PoseError
from hipsim.motion.trajectories import Trajectory, iso14242

H = 1e-5  # finite-difference step in [s]
TOL = 1e-6


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


@pytest.fixture(scope="module", params=["iso", "smooth"])
def motion(request):
    return iso_at if request.param == "iso" else SmoothMotion(seed=3)


T_SAMPLES = np.linspace(0.0, 1.0, 97, endpoint=False)


def kin_at(params, motion, t):
    return kinematics(params, motion(t))


def test_rotation_matrix_is_zyx():
    a, b, g = 0.3, -0.2, 0.7
    Rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    Ry = np.array([[np.cos(b), 0, np.sin(b)], [0, 1, 0], [-np.sin(b), 0, np.cos(b)]])
    Rz = np.array([[np.cos(g), -np.sin(g), 0], [np.sin(g), np.cos(g), 0], [0, 0, 1]])
    np.testing.assert_allclose(rotation_matrix(np.array([[a, b, g]]))[0], Rz @ Ry @ Rx, atol=1e-15)


def test_angular_velocity_against_rotation_difference(params, motion):
    kin = kin_at(params, motion, T_SAMPLES)
    Rdot = central_difference(lambda t: rotation_matrix(motion(t).q), T_SAMPLES, H)
    W = Rdot @ np.swapaxes(kin.R, 1, 2)  # [ω]×
    omega_fd = np.stack([W[:, 2, 1], W[:, 0, 2], W[:, 1, 0]], axis=1)
    assert relative_error(kin.omega, omega_fd) < TOL
    np.testing.assert_allclose(kin.omega, np.einsum("nab,nb->na", angular_velocity_map(kin.q), kin.qd))
    omega_dot_fd = central_difference(lambda t: kin_at(params, motion, t).omega, T_SAMPLES, H)
    assert relative_error(kin.omega_dot, omega_dot_fd) < TOL


def test_slider_derivatives(params, motion):
    kin = kin_at(params, motion, T_SAMPLES)
    Ld_fd = central_difference(lambda t: kin_at(params, motion, t).L, T_SAMPLES, H)
    Ldd_fd = central_difference(lambda t: kin_at(params, motion, t).Ld, T_SAMPLES, H)
    assert relative_error(kin.Ld, Ld_fd) < TOL
    assert relative_error(kin.Ldd, Ldd_fd) < TOL


def test_jacobian_maps_angular_velocity_to_slider_speeds(params):
    """J from the finite-difference derivative of L(q): dL/dq = J·T(q)."""
    q0 = np.radians([[10.0, -3.0, 5.0]])
    dq = 1e-6
    dLdq = np.stack(
        [
            (slider_heights(params, q0 + dq * np.eye(3)[k]) - slider_heights(params, q0 - dq * np.eye(3)[k]))[0, 0]
            / (2 * dq)
            for k in range(3)
        ],
        axis=1,
    )
    kin = kinematics(params, Trajectory(np.array([0.0]), q0, np.zeros((1, 3)), np.zeros((1, 3)), np.array([0.0])))
    np.testing.assert_allclose(kin.J[0] @ angular_velocity_map(q0)[0], dLdq, rtol=1e-7, atol=1e-9)


def test_lever_motion(params, motion):
    kin = kin_at(params, motion, T_SAMPLES)
    e_dot = central_difference(lambda t: kin_at(params, motion, t).e, T_SAMPLES, H)
    # A lever without spin turns at ω_l = e × ė.
    omega_l_fd = np.cross(kin.e, e_dot)
    assert relative_error(kin.omega_l, omega_l_fd) < TOL
    np.testing.assert_allclose(np.einsum("nik,nik->ni", kin.omega_l, kin.e), 0.0, atol=1e-12)
    omega_l_dot_fd = central_difference(lambda t: kin_at(params, motion, t).omega_l, T_SAMPLES, H)
    assert relative_error(kin.omega_l_dot, omega_l_dot_fd) < TOL
    centre = lambda t: (lambda k: 0.5 * (k.a + k.b))(kin_at(params, motion, t))
    assert relative_error(kin.v_l, central_difference(centre, T_SAMPLES, H)) < TOL
    v_l = lambda t: kin_at(params, motion, t).v_l
    assert relative_error(kin.a_l, central_difference(v_l, T_SAMPLES, H)) < TOL


def test_lever_jacobians(params, motion):
    kin = kin_at(params, motion, T_SAMPLES)
    J_v, J_omega = lever_jacobians(kin)
    np.testing.assert_allclose(np.einsum("niab,nb->nia", J_v, kin.omega), kin.v_l[:, 0], atol=1e-13)
    np.testing.assert_allclose(np.einsum("niab,nb->nia", J_omega, kin.omega), kin.omega_l, atol=1e-13)


def test_universal_joint_spin(params, motion):
    """With spin, ω_l lies in span{u1, u2} (what a universal joint allows) and ω̇_l is its derivative."""
    kin = kin_at(params, motion, T_SAMPLES)
    omega_l, omega_l_dot = lever_rotation(params, kin, spin=True)
    frames = lever_frames(params, kin)
    u1 = params.ujoint_axes[None]
    u2 = frames[..., 0]
    np.testing.assert_allclose(np.einsum("nik,nik->ni", omega_l, np.cross(u1, u2)), 0.0, atol=1e-12)
    # The part of ω_l across the lever is the spin-free one.
    across = omega_l - np.einsum("nik,nik->ni", omega_l, kin.e)[..., None] * kin.e
    np.testing.assert_allclose(across, kin.omega_l, atol=1e-12)
    spin_fd = central_difference(lambda t: lever_rotation(params, kin_at(params, motion, t), True)[0], T_SAMPLES, H)
    assert relative_error(omega_l_dot, spin_fd) < TOL
    # The lever frame's own rotation rate, from finite differences of the frames, is this ω_l.
    Rdot = central_difference(lambda t: lever_frames(params, kin_at(params, motion, t)), T_SAMPLES, H)
    W = Rdot @ np.swapaxes(frames, -1, -2)
    frame_rate = np.stack([W[..., 2, 1], W[..., 0, 2], W[..., 1, 0]], axis=-1)
    assert relative_error(omega_l, frame_rate) < TOL


def test_closure_and_slider_offset(params):
    kin = kinematics(params, iso14242())
    lengths = np.linalg.norm(kin.a - kin.b, axis=-1)
    assert np.max(np.abs(lengths - params.lever_length)) < 1e-12  # 1e-9 mm
    np.testing.assert_allclose(kin.L[:, 0] - kin.L[:, 1], params.heights[0] - params.heights[1], atol=1e-13)
    # b_ji on its screw: horizontal position is c_i.
    np.testing.assert_allclose(
        kin.b[..., :2], np.broadcast_to(params.screw_points[:, :2], kin.b[..., :2].shape), atol=1e-15
    )
    assert np.all(kin.e[..., 2] > 0)  # the lever below its platform joint


def test_iso_slider_maxima_near_published(params):
    """Spec §7.2: the m1 slider maxima come out within a few per cent of 665.58 / 660.47 / 624.42 mm."""
    kin = kinematics(params, iso14242())
    L_max = kin.L[:, 0].max(axis=0) * 1e3
    np.testing.assert_allclose(L_max, [665.58, 660.47, 624.42], rtol=0.04)


def test_inverse_condition_number_matches_svd():
    rng = np.random.default_rng(1)
    J = rng.normal(size=(500, 3, 3))
    s = np.linalg.svd(J, compute_uv=False)
    np.testing.assert_allclose(inverse_condition_number(J), s[:, 2] / s[:, 0], atol=1e-10)
    np.testing.assert_allclose(inverse_condition_number(np.diag([1.0, 2.0, 4.0])[None]), [0.25])
    assert inverse_condition_number(np.eye(3)[None])[0] == 1.0


def test_condition_along_iso_cycle(params):
    kin = kinematics(params, iso14242())
    s = np.linalg.svd(kin.J, compute_uv=False)
    np.testing.assert_allclose(kin.cond_inv, s[:, 2] / s[:, 0], atol=1e-10)
    assert 0.1 < kin.cond_inv.min() <= kin.cond_inv.max() < 1.0


def _still(q_deg, t=0.0):
    return Trajectory(np.array([t]), np.radians([q_deg]), np.zeros((1, 3)), np.zeros((1, 3)), np.array([0.0]))


def test_out_of_reach_raises_with_time(params):
    far = Trajectory(
        np.array([0.0, 0.5, 1.0]),
        np.radians([[0, 0, 0], [0, 0, 0], [0, 0, 180]]),
        np.zeros((3, 3)),
        np.zeros((3, 3)),
        np.zeros(3),
    )
    with pytest.raises(PoseError, match=r"t = 1 s: pose out of reach") as error:
        kinematics(params, far)
    assert error.value.index == 2
    flagged = kinematics(params, far, on_error="flag")
    assert flagged.flagged.tolist() == [False, False, True]
    assert np.all(np.isnan(flagged.L[2])) and np.all(np.isfinite(flagged.L[:2]))


def test_singular_pose_raises(params):
    """δ = 0 lines the platform joints up with the screws: at home the lever
    projections pass through the centre and J_b loses rank (spec §3)."""
    aligned = params.replace(home_offset=0.0)
    with pytest.raises(PoseError, match="singular pose"):
        kinematics(aligned, _still([0, 0, 0], t=0.25))
    assert kinematics(aligned, _still([0, 0, 0]), on_error="flag").flagged[0]
    assert not kinematics(params, _still([0, 0, 0])).flagged[0]


def test_crossing_a_singularity_between_samples_is_caught(params):
    """With δ = 5° the platform at α = β = 0 is singular at γ = −5°; coarse samples step over it."""
    machine = params.replace(home_offset=np.radians(5.0))
    gamma = np.radians([-9.7, -7.3, -4.1, -1.9])
    q = np.column_stack([np.zeros(4), np.zeros(4), gamma])
    coarse = Trajectory(np.arange(4) * 0.1, q, np.zeros((4, 3)), np.zeros((4, 3)), np.zeros(4))
    flagged = kinematics(machine, coarse, on_error="flag")
    assert flagged.cond_inv.min() > 0.01  # no sample comes close
    assert flagged.flagged.tolist() == [False, False, True, False]
    with pytest.raises(PoseError, match=r"t = 0.2 s: the motion passes through a singular pose") as error:
        kinematics(machine, coarse)
    assert error.value.index == 2
    assert not kinematics(params, coarse).flagged.any()  # the built machine (δ = 30°) is clear

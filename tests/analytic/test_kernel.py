"""The compiled single-state kernels against the vectorised model they transcribe."""

import math

import numpy as np
import pytest
from support import ALL_FRICTION, SmoothMotion, relative_error

import hipsim
import hipsim.analytic.kernel as kernel
from hipsim.analytic.inverse_kinematics import kinematics, slider_jacobian
from hipsim.analytic.virtual_work import inverse_dynamics, mass_and_bias
from hipsim.control.simulation import _rk4


@pytest.fixture(scope="module")
def params():
    return hipsim.load_parameters()


def machines(params):
    """The published machine, one with every friction, one with flipped angle signs and a skewed platform inertia,
    and one whose thrust bearing resists only rotation about its own axis."""
    inertia = params.platform_inertia + np.array([[0.0, 2e-4, -1e-4], [2e-4, 0.0, 3e-4], [-1e-4, 3e-4, 0.0]])
    signs = params.replace(angle_signs=np.array([-1.0, 1.0, -1.0]), platform_inertia=inertia, **ALL_FRICTION)
    return {
        "published": params,
        "all friction": params.replace(**ALL_FRICTION),
        "signs": signs,
        "axial bearing": signs.replace(thrust_bearing_axial_only=True),
    }


def random_states(seed=0, n=40):
    """A random smooth motion sampled coarsely: states far apart, all within reach."""
    return SmoothMotion(seed=seed, amplitude_deg=15.0)(np.linspace(0.0, 4.0, n))


@pytest.mark.parametrize("machine", ["published", "all friction", "signs", "axial bearing"])
@pytest.mark.parametrize("lever_spin", [True, False])
def test_torques_match_the_vectorised_inverse_dynamics(params, machine, lever_spin):
    params = machines(params)[machine]
    motion = random_states()
    expected = inverse_dynamics(params, kinematics(params, motion), motion.Fe, lever_spin).total
    P = kernel.kernel_parameters(params, lever_spin)
    actual = np.array(
        [kernel.torques(P, motion.q[k], motion.qd[k], motion.qdd[k], motion.Fe[k]) for k in range(len(motion))]
    )
    assert relative_error(actual, expected) < 1e-12  # round-off: the kernel sums in another order


@pytest.mark.parametrize("machine", ["published", "signs", "axial bearing"])
@pytest.mark.parametrize("lever_spin", [True, False])
def test_mass_and_bias_match_the_vectorised_model(params, machine, lever_spin):
    params = machines(params)[machine]
    motion = random_states(seed=1)
    M, h = mass_and_bias(params, motion, lever_spin)
    P = kernel.kernel_parameters(params, lever_spin)
    for k in range(len(motion)):
        M_k, h_k = kernel.mass_and_bias(P, motion.q[k], motion.qd[k], motion.Fe[k])
        assert relative_error(M_k, M[k]) < 1e-12
        assert relative_error(h_k, h[k]) < 1e-12


def test_derivative_inverts_the_inverse_dynamics(params):
    """The acceleration the forward dynamics gives, fed to the inverse dynamics, returns the applied torques."""
    params = machines(params)["signs"]
    P = kernel.kernel_parameters(params)
    motion = random_states(seed=2, n=10)
    rng = np.random.default_rng(2)
    for k in range(len(motion)):
        x, tau = np.concatenate([motion.q[k], motion.qd[k]]), rng.normal(size=3)
        dx = kernel.derivative(P, x, tau, motion.Fe[k])
        np.testing.assert_array_equal(dx[:3], motion.qd[k])
        np.testing.assert_allclose(
            kernel.torques(P, motion.q[k], motion.qd[k], dx[3:], motion.Fe[k]), tau, rtol=0, atol=1e-12
        )


class _DerivativeOnly:
    """The compiled derivative without ``advance``, for simulate's own RK4 loop."""

    def __init__(self, P):
        self.P = P

    def derivative(self, t, x, tau, Fe):
        return kernel.derivative(self.P, x, tau, Fe)


def test_advance_is_classic_rk4_with_the_loads_at_the_half_steps(params):
    P = kernel.kernel_parameters(params)
    x = np.concatenate(np.radians([[8.0, -3.0, 5.0], [20.0, -15.0, 30.0]]))
    tau, loads, h = np.array([0.2, -0.1, 0.15]), np.array([300.0, 900.0, 1500.0, 2100.0, 2700.0]), 2.5e-4
    expected = _rk4(_DerivativeOnly(P), 0.0, x, tau, loads, h, 2)  # type: ignore[arg-type]  # only derivative(), what _rk4 calls
    np.testing.assert_allclose(kernel.advance(P, x, tau, loads, h, 2), expected, rtol=1e-14, atol=1e-15)
    # The loads matter: the same step under the first load throughout differs.
    assert not np.allclose(kernel.advance(P, x, tau, np.full(5, loads[0]), h, 2), expected, rtol=1e-12, atol=0)


def test_jacobian_matches_the_vectorised_one(params):
    params = machines(params)["signs"]
    P = kernel.kernel_parameters(params)
    motion = random_states(seed=3)
    expected = slider_jacobian(params, motion.q * params.angle_signs)
    actual = np.array([kernel.jacobian(P, q) for q in motion.q])
    assert relative_error(actual, expected) < 1e-14


def test_out_of_reach_gives_nan_not_a_number_that_looks_right(params):
    P = kernel.kernel_parameters(params)
    far = np.radians([0.0, 0.0, 120.0])
    assert np.isnan(slider_jacobian(params, far[None])).any()  # truly out of reach
    assert np.isnan(kernel.jacobian(P, far)).any()
    assert np.isnan(kernel.derivative(P, np.concatenate([far, np.zeros(3)]), np.zeros(3), 0.0)[3:]).all()


def test_workspace_pd_is_the_jacobian_transpose_law(params):
    params = machines(params)["signs"]
    P = kernel.kernel_parameters(params)
    kp, kd = np.array([100.0, 200.0, 300.0]), np.array([1.0, 2.0, 3.0])
    q, qd = np.radians([5.0, 1.0, -2.0]), np.array([0.1, 0.0, -0.2])
    q_des, qd_des = np.radians([6.0, 0.0, -1.0]), np.array([0.0, 0.3, 0.1])
    tau = kernel.workspace_pd(P, q, qd, q_des, qd_des, kp, kd)
    J = slider_jacobian(params, (params.angle_signs * q)[None])[0]
    moment = params.angle_signs * (kp * (q_des - q) + kd * (qd_des - qd))
    np.testing.assert_allclose(tau, params.lead / (2 * math.pi) * np.linalg.solve(J.T, moment), rtol=1e-13)


@pytest.mark.parametrize(
    ("value", "shape", "message"),
    [
        ([1.0, 2.0], (3,), r"x: expected shape \(3,\), got shape \(2,\)"),
        ("a", (3,), "x: expected numbers"),
        ([[1, 2, 3]], (3,), r"got shape \(1, 3\)"),
    ],
)
def test_kernel_arguments_of_the_wrong_shape_are_refused_by_name(value, shape, message):
    # The compiled kernels do not check bounds: a short array would be read past its end.
    with pytest.raises(hipsim.HipsimError, match=message):
        kernel.floats(value, shape, "x")


def test_parameters_as_plain_tuples_come_back_whole(params):
    """What the Pinocchio servo loop hands its compiled call once a period (plain tuples) is the machine again inside."""
    P = kernel.kernel_parameters(params)
    plain = kernel.plain_parameters(P)
    assert type(plain) is tuple and type(plain[-1]) is tuple
    back = kernel.named_parameters(plain)
    assert back == P and type(back) is kernel.KernelParameters and type(back.friction) is type(P.friction)

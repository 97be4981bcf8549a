"""Analytic inverse dynamics with joint friction (spec §4), vectorised over samples.

The motor torques follow from the principle of virtual power: the power of the
motors plus that of every applied and inertial (D'Alembert) wrench is zero for
any platform angular velocity ω. All body velocities are linear in ω, so each
wrench maps to a generalised moment in ω-space, and the motor torques are

    τ = τ_L + τ_f − (p/2π)·Σ_j [ J⁻ᵀ·Q_j + F_L,j − F_Lf,j ]      (spec §4.2)

with Q_j the generalised moment of platform j, its three levers and the
friction moments. Instead of forming the lever Jacobians J_v, J_ω of spec
§4.2, a lever wrench (force F at its centre, moment M) is mapped through
their transposes in closed form:

    J_vᵀF + J_ωᵀM = r × f_a + Jᵀ·f_b,z,   f_a = F/2 + (M × e)/l,  f_b = F/2 − (M × e)/l,

that is, the lever wrench is replaced by two forces at its ends: f_a acts on
the platform at a (moment r × f_a about the fixed centre) and the vertical part
of f_b acts on the slider. ``tests/test_virtual_work.py`` checks this against the
explicit Jacobians of :func:`hipsim.analytic.inverse_kinematics.lever_jacobians`.

Both platforms have the same orientation and their legs the same lever
directions, so every platform, lever and slider term is the same for j = 1
and j = 2 and is computed once and counted twice.

As in :mod:`hipsim.analytic.inverse_kinematics`, the computations run
components-first (a vector per sample (3, N), per leg (3, 3, N) = (xyz, leg,
sample), a scalar per leg (3, N)) on the ``.T`` views of the
:class:`~hipsim.analytic.inverse_kinematics.Kinematics` arrays, and the
results are turned back with ``.T``. The friction laws, J⁻ᵀ and the lever's
spin and frame are those of :mod:`hipsim.physics.laws`, which the compiled
kernel and the Pinocchio model call too. The assembly below is transcribed
once more, for one state on plain floats, in :mod:`hipsim.analytic.kernel`,
because whole-array NumPy code costs ~700 calls of Python overhead per state
there; ``tests/test_analytic_kernel.py`` ties the two to round-off.
"""

from __future__ import annotations

import numpy as np

from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics import laws
from ..physics.friction import central_chain_friction_components
from ..physics.transmission import angle_from_travel, travel_per_radian
from ..physics.vectors import cross_array, dot, per_leg, stack
from ..results import Torques
from .inverse_kinematics import Kinematics, kinematics

__all__ = [
    "inverse_dynamics",
    "mass_and_bias",
    "mechanical_energy",
    "screw_friction_torque",
]


def screw_friction_torque(params: Parameters, motor_speed: np.ndarray) -> np.ndarray:
    """The lead screw's own friction torque on the motor shaft in [N·m]: Coulomb (smooth sign) plus viscous.

    Args:
        params: the machine.
        motor_speed: θ̇ in [rad/s], any shape.
    """
    return laws.screw_friction(params.friction, np.asarray(motor_speed, dtype=float))


def _body_components(axes, w: np.ndarray) -> np.ndarray:
    """Rᵀ·w: the components of w (3, ...) along a body's axes, the columns of R given as three vectors."""
    return np.array([dot(axis, w) for axis in axes])


def _from_body(axes, w_body: np.ndarray) -> np.ndarray:
    """R·w_body: a vector from its components along a body's axes (components-first arrays)."""
    w = axes[0] * w_body[0]
    w += axes[1] * w_body[1]
    w += axes[2] * w_body[2]
    return w


def _lever_axes(params: Parameters, kin: Kinematics):
    """The levers' body axes x, y, z = e (spec §7.1), components-first arrays (xyz, leg, N)."""
    x, y, e = laws.lever_axes(per_leg(params.ujoint_axes), kin.e.T)
    return stack(x), stack(y), e


def _inertia_times(inertia: np.ndarray, w: np.ndarray) -> np.ndarray:
    """I·w for a constant 3x3 inertia I and components-first vectors w (3, ...)."""
    return np.einsum("ab,b...->a...", inertia, w)  # not BLAS: see inverse_kinematics._platform_vectors


def _euler_moment(axes, inertia: np.ndarray, w: np.ndarray, w_dot: np.ndarray) -> np.ndarray:
    """The D'Alembert moment −I_w·ω̇ − ω × I_w·ω in world axes, I_w = R·I·Rᵀ.

    Evaluated in body axes, where the inertia is constant: R·(−I·Rᵀω̇ − Rᵀω × I·Rᵀω).
    ``axes`` are the body's axes (the columns of R), components-first.
    """
    w_body = _body_components(axes, w)
    moment_body = -_inertia_times(inertia, _body_components(axes, w_dot))
    moment_body -= cross_array(w_body, _inertia_times(inertia, w_body))
    return _from_body(axes, moment_body)


def _rotational_energy(axes, inertia: np.ndarray, w: np.ndarray) -> np.ndarray:
    """½·ωᵀ·I_w·ω."""
    w_body = _body_components(axes, w)
    return 0.5 * dot(w_body, _inertia_times(inertia, w_body))


def _platform_axes(kin: Kinematics):
    """The platform's axes, the columns of R, components-first (3, N) each."""
    return kin.R[:, :, 0].T, kin.R[:, :, 1].T, kin.R[:, :, 2].T


#: No force at the lever centre (a pure moment), for :func:`_lever_ends`.
_NO_FORCE = np.zeros((3, 1, 1))


def _lever_ends(
    params: Parameters, kin: Kinematics, lever_spin: bool, force: np.ndarray, moment: np.ndarray, lever_length=None
):
    """A wrench on each lever (force at its centre, moment), as the two end forces of the module docstring.

    ``lever_length``: l in [m], or per leg (3, 1) on a per-chain machine; None for the drawing's.

    Returns:
        Σ_i r_i × f_a,i, the moment of the platform-end forces about the centre (3, N),
        and f_b,z, the slider-end forces along the screws (3, N).
    """
    e = kin.e.T
    if lever_spin:
        moment = laws.spin_transpose(per_leg(params.ujoint_axes), e, moment)
    m_cross_e = cross_array(moment, e)
    m_cross_e /= params.lever_length if lever_length is None else lever_length
    f_a = 0.5 * force + m_cross_e
    f_b_z = 0.5 * force[2] - m_cross_e[2]
    return np.sum(cross_array(kin.r.T, f_a), axis=1), f_b_z


def _lever_inertia(params: Parameters, kin: Kinematics, lever_spin: bool, omega_l, omega_l_dot, lever_length=None):
    """Levers' gravity and D'Alembert wrench, mapped to their ends by :func:`_lever_ends`."""
    gravity = np.array([0.0, 0.0, -params.gravity])[:, None, None]
    F_l = params.lever_mass * (gravity - kin.a_l[:, 0].T)
    M_l = _euler_moment(_lever_axes(params, kin), params.lever_inertia, omega_l, omega_l_dot)
    return _lever_ends(params, kin, lever_spin, F_l, M_l, lever_length)


def _lever_joint_friction(params: Parameters, kin: Kinematics, lever_spin: bool, omega_l, lever_length=None):
    """Friction in the levers' universal (U) and spherical (S) joints.

    U: the lever relative to the non-rotating slider; S: the lever relative to
    the platform, whose moment also acts back on the platform.

    Returns:
        The generalised moment on the platform (3, N), the slider-end forces
        along the screws (3, N), and the power lost (N,); zeros when every
        coefficient is zero (the default), without computing them.
    """
    if not laws.lever_joint_friction_on(params.friction):
        return 0.0, 0.0, 0.0
    omega = kin.omega.T
    tau_bf, tau_af = (stack(moment) for moment in laws.lever_joint_friction(params.friction, omega_l, omega))
    Q, f_b_z = _lever_ends(params, kin, lever_spin, _NO_FORCE, -tau_af - tau_bf, lever_length)
    Q += np.sum(tau_af, axis=1)
    power = np.sum(dot(tau_bf, omega_l) + dot(tau_af, omega_l - omega[:, None]), axis=0)
    return Q, f_b_z, power


def inverse_dynamics(params: Parameters, kin: Kinematics, Fe: np.ndarray, lever_spin: bool = False) -> Torques:
    """Motor torques of the three linear modules and their parts (spec §4).

    Args:
        params: the machine.
        kin: kinematics along the trajectory (:func:`hipsim.analytic.inverse_kinematics.kinematics`).
        Fe: hydraulic load magnitude in [N], (N,).
        lever_spin: False for the spec's lever model (no spin about its axis);
            True to give the levers the spin a universal joint imposes, which
            is what the Pinocchio model does.

    Returns:
        The torques; their parts add up to the total.
    """
    Fe = np.asarray(Fe, dtype=float)
    n_platforms = params.heights.size
    f = params.friction
    p = params.lead
    # Components first: per sample (3, N), per leg (3, 3, N); per-leg scalars (3, N).
    omega = kin.omega.T
    Ld, Ldd = kin.Ld[:, 0].T, kin.Ldd[:, 0].T
    motor_speed = angle_from_travel(Ld, p)
    omega_l, omega_l_dot = kin.omega_l.T, kin.omega_l_dot.T
    if lever_spin:
        u1, e = per_leg(params.ujoint_axes), kin.e.T
        omega_l, omega_l_dot = (
            stack(laws.lever_angular_velocity(u1, e, omega_l)),
            stack(laws.lever_angular_acceleration(u1, e, omega_l, omega_l_dot)),
        )

    # Platforms: the D'Alembert moment about the fixed centre.
    Q_m = _euler_moment(_platform_axes(kin), params.platform_inertia, omega, kin.omega_dot.T)

    # Levers: gravity and inertia at the centre, mapped to the ends.
    Q_l, Fz_l = _lever_inertia(params, kin, lever_spin, omega_l, omega_l_dot)

    # Sliders: gravity and inertia along the screw.
    F_L = params.slider_mass * (-params.gravity - Ldd)

    # Friction: central chain, lever joints, slider guides and screws.
    tau_mf = central_chain_friction_components(
        params.friction, params.platform_mass * params.gravity, omega, Fe, kin.R[:, :, 2].T
    )
    Q_lf, Fz_lf, power_lf = _lever_joint_friction(params, kin, lever_spin, omega_l)
    Q_f = Q_lf - tau_mf
    F_Lf = laws.guide_friction(f, Ld, motor_speed)
    tau_screw_f = laws.screw_friction(f, motor_speed)

    # y = J⁻ᵀ·Q for the platform, lever and friction moments: y_i = (row i of J⁻ᵀ)·Q.
    rows = laws.inverse_transpose(np.moveaxis(kin.J.T, 1, 0))  # from J's rows, (xyz, N) each
    J_inv_T = np.array([[row[k] for row in rows] for k in range(3)])  # its rows as vectors per leg (xyz, row, N)
    scale = -n_platforms * travel_per_radian(p)  # n is 1 or 2: exact, so the same bits as −n·p/2π
    tau_m = scale * dot(J_inv_T, Q_m)
    tau_l = scale * (dot(J_inv_T, Q_l) + Fz_l)
    tau_s = scale * F_L
    tau_L = angle_from_travel(params.screw_inertia, p) * Ldd
    tau_f = tau_screw_f + scale * (dot(J_inv_T, Q_f) + Fz_lf - F_Lf)

    friction_power = np.sum(tau_screw_f * motor_speed, axis=0) + n_platforms * (
        np.sum(F_Lf * Ld, axis=0) + dot(tau_mf, omega) + power_lf
    )
    tau = tau_m + tau_l + tau_s + tau_L + tau_f
    return Torques(
        total=tau.T,
        platforms=tau_m.T,
        levers=tau_l.T,
        sliders=tau_s.T,
        screws=tau_L.T,
        friction=tau_f.T,
        motor_speed=motor_speed.T,
        friction_moment=np.sqrt(dot(tau_mf, tau_mf)),
        friction_power=friction_power,
    )


def mass_and_bias(
    params: Parameters, trajectory: Trajectory, lever_spin: bool = False
) -> tuple[np.ndarray, np.ndarray]:
    """The reduced model τ = M(q)·q̈ + h(q, q̇, F_e) along a trajectory, in gait angles.

    The inverse dynamics is affine in q̈, so its value at q̈ = 0 is h and its
    values at the three unit accelerations minus h are the columns of M: one
    vectorised call on 4N samples. M is the inertia the motors feel (platforms,
    levers, sliders and screws reflected to the motor shafts); h holds gravity,
    the velocity terms and friction. The trajectory's q̈ is not used.

    Args:
        params: the machine.
        trajectory: the states (q, q̇) and loads F_e, N samples along a motion
            (as everywhere, a det J sign change between samples counts as a crossing).
        lever_spin: as in :func:`inverse_dynamics`, whose default (the spec's
            spin-free levers) this keeps; :class:`hipsim.control.simulation.ReducedPlant`
            uses True.

    Returns:
        M in [N·m·s²/rad], (N, 3, 3), and h in [N·m], (N, 3).

    Raises:
        PoseError: naming the time of the first state out of reach or singular.
    """
    kinematics(params, trajectory)  # raises on a bad pose, naming its time
    n = len(trajectory.t)
    states = Trajectory(
        np.tile(trajectory.t, 4),
        np.tile(trajectory.q, (4, 1)),
        np.tile(trajectory.qd, (4, 1)),
        np.repeat(np.vstack([np.zeros(3), np.eye(3)]), n, axis=0),  # q̈ = 0 for the first N samples, then e_1, e_2, e_3
        np.tile(trajectory.Fe, 4),
        name=trajectory.name,
    )
    # Already checked: the copies' boundaries are not motions, so do not look for crossings there.
    tau = inverse_dynamics(params, kinematics(params, states, on_error="flag"), states.Fe, lever_spin).total.reshape(
        4, n, 3
    )
    h = tau[0]
    return np.moveaxis(tau[1:] - h, 0, -1), h


def mechanical_energy(params: Parameters, kin: Kinematics, lever_spin: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """Kinetic and potential energy of the whole machine, computed from body motions alone.

    Independent of :func:`inverse_dynamics` (no wrenches, no Jacobian
    transposes), so the power balance motor power = dE/dt + friction power
    checks the torques.

    Args:
        params: the machine.
        kin: kinematics along the trajectory.
        lever_spin: as in :func:`inverse_dynamics`.

    Returns:
        Kinetic and potential energy in [J], each (N,). Potential energy is
        m·g·z of the levers and sliders (the platform centres do not move).
    """
    n_platforms = params.heights.size
    kinetic_m = _rotational_energy(_platform_axes(kin), params.platform_inertia, kin.omega.T)
    omega_l = kin.omega_l.T
    if lever_spin:
        omega_l = laws.lever_angular_velocity(per_leg(params.ujoint_axes), kin.e.T, omega_l)
    v_l = kin.v_l[:, 0].T
    kinetic_l = 0.5 * params.lever_mass * dot(v_l, v_l)
    kinetic_l += _rotational_energy(_lever_axes(params, kin), params.lever_inertia, omega_l)
    Ld = kin.Ld[:, 0].T
    kinetic_s = 0.5 * params.slider_mass * Ld**2
    kinetic_L = 0.5 * params.screw_inertia * angle_from_travel(Ld, params.lead) ** 2
    kinetic = n_platforms * (kinetic_m + kinetic_l.sum(0) + kinetic_s.sum(0)) + kinetic_L.sum(0)
    lever_height = 0.5 * (kin.a[..., 2] + kin.b[..., 2])
    potential = params.gravity * (params.lever_mass * lever_height.sum((1, 2)) + params.slider_mass * kin.L.sum((1, 2)))
    return kinetic, potential

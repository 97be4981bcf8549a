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
of f_b acts on the slider. ``tests/analytic/test_virtual_work.py`` checks this against the
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
there; ``tests/analytic/test_kernel.py`` ties the two to round-off.

What depends on the motion and the geometry alone (the levers' spin, the body
components of the angular velocities, J⁻ᵀ) is computed first
(:func:`motion_terms`), and each torque part from it and the machine's masses,
inertias and friction coefficients (:data:`PARTS`). :func:`inverse_dynamics`
is the two in a row; the identification's regressor computes the terms once
and a part per column, for many machines of one geometry, with the same
arithmetic, hence the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

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
    "PARTS",
    "MotionTerms",
    "friction_torques",
    "inverse_dynamics",
    "lever_torques",
    "mass_and_bias",
    "mechanical_energy",
    "motion_terms",
    "platform_torques",
    "screw_friction_torque",
    "screw_torques",
    "slider_torques",
    "torques_from_parts",
    "torques_of",
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
    return _lever_axes_of(params, kin.e.T)


def _lever_axes_of(params: Parameters, e: np.ndarray):
    """:func:`_lever_axes` from the lever unit vectors e, components-first (3, 3, N)."""
    x, y, e = laws.lever_axes(per_leg(params.ujoint_axes), e)
    return stack(x), stack(y), e


def _inertia_times(inertia: np.ndarray, w: np.ndarray) -> np.ndarray:
    """I·w for a constant 3x3 inertia I and components-first vectors w (3, ...)."""
    return np.einsum("ab,b...->a...", inertia, w)  # not BLAS: see inverse_kinematics._platform_vectors


def _euler_moment(axes, inertia: np.ndarray, w: np.ndarray, w_dot: np.ndarray) -> np.ndarray:
    """The D'Alembert moment −I_w·ω̇ − ω × I_w·ω in world axes, I_w = R·I·Rᵀ.

    Evaluated in body axes, where the inertia is constant: R·(−I·Rᵀω̇ − Rᵀω × I·Rᵀω).
    ``axes`` are the body's axes (the columns of R), components-first.
    """
    return _euler_moment_body(axes, inertia, _body_components(axes, w), _body_components(axes, w_dot))


def _euler_moment_body(axes, inertia: np.ndarray, w_body: np.ndarray, w_dot_body: np.ndarray) -> np.ndarray:
    """:func:`_euler_moment` of ω and ω̇ given by their components along the body's axes (Rᵀω, Rᵀω̇)."""
    moment_body = -_inertia_times(inertia, w_dot_body)
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
    params: Parameters,
    kin: Kinematics,
    lever_spin: bool,
    force: np.ndarray,
    moment: np.ndarray | None,
    lever_length=None,
):
    """A wrench on each lever (force at its centre, moment), as the two end forces of the module docstring.

    ``lever_length``: l in [m], or per leg (3, 1) on a per-chain machine; None for the drawing's.
    ``moment`` None: no moment (the end forces of a force alone, without computing a zero moment's).

    Returns:
        Σ_i r_i × f_a,i, the moment of the platform-end forces about the centre (3, N),
        and f_b,z, the slider-end forces along the screws (3, N).
    """
    return _lever_end_forces(params, kin.e.T, kin.r.T, lever_spin, force, moment, lever_length)


def _lever_end_forces(params: Parameters, e, r, lever_spin: bool, force, moment, lever_length=None):
    """:func:`_lever_ends` with the lever unit vectors e and platform joint vectors r components-first (3, 3, N)."""
    if moment is None:
        # 0.5·F + 0 is 0.5·F: the same numbers as a zero moment's sum, without its arithmetic.
        f_a = 0.5 * force
        f_b_z = 0.5 * force[2]
    else:
        if lever_spin:
            moment = laws.spin_transpose(per_leg(params.ujoint_axes), e, moment)
        m_cross_e = cross_array(moment, e)
        m_cross_e /= params.lever_length if lever_length is None else lever_length
        f_a = 0.5 * force + m_cross_e
        f_b_z = 0.5 * force[2] - m_cross_e[2]
    return np.sum(cross_array(r, f_a), axis=1), f_b_z


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
    return _lever_joint_friction_terms(params, kin.e.T, kin.r.T, kin.omega.T, lever_spin, omega_l, lever_length)


def _lever_joint_friction_terms(
    params: Parameters, e, r, omega, lever_spin: bool, omega_l, lever_length=None, power: bool = True
):
    """:func:`_lever_joint_friction` with e, r (3, 3, N) and ω (3, N) components-first; ``power`` False: 0.0 for it."""
    if not laws.lever_joint_friction_on(params.friction):
        return 0.0, 0.0, 0.0
    tau_bf, tau_af = (stack(moment) for moment in laws.lever_joint_friction(params.friction, omega_l, omega))
    Q, f_b_z = _lever_end_forces(params, e, r, lever_spin, _NO_FORCE, -tau_af - tau_bf, lever_length)
    Q += np.sum(tau_af, axis=1)
    if not power:
        return Q, f_b_z, 0.0
    lost = np.sum(dot(tau_bf, omega_l) + dot(tau_af, omega_l - omega[:, None]), axis=0)
    return Q, f_b_z, lost


# --- The motion's terms, once; the machine's torques from them --------------------------


@dataclass(frozen=True, eq=False)
class MotionTerms:
    """What the inverse dynamics takes from a motion whatever the machine's masses, inertias and friction coefficients.

    Everything of :func:`inverse_dynamics` that depends on the motion and the
    geometry alone (the lever's spin, the body components of the angular
    velocities, J⁻ᵀ), computed once by :func:`motion_terms`, so that the
    torques of many machines of one geometry along one motion
    (:func:`torques_of`, or a part of them: :data:`PARTS`) cost only what the
    dynamic parameters multiply: the identification's regressor evaluates each
    of its columns on one machine with one parameter at one
    (:mod:`hipsim.rig.identification.regressor`). Components first
    (module docstring); indexing with a slice of samples gives a view of those
    samples, so long motions can be evaluated block by block.

    Attributes:
        lever_spin: as in :func:`inverse_dynamics`.
        n_platforms: platforms counted (1 or 2).
        scale: −n·p/2π in [m/rad], from a generalised force to a motor torque.
        Fe: load in [N], (N,).
        omega: platform angular velocity ω in [rad/s], (3, N).
        platform_z: the platform's z axis, (3, N).
        platform_axes: the platform's axes (the columns of R), each (3, N).
        omega_body, omega_dot_body: Rᵀω in [rad/s] and Rᵀω̇ in [rad/s²], (3, N).
        Ld, Ldd: slider speeds in [m/s] and accelerations in [m/s²], (3, N).
        motor_speed: θ̇ in [rad/s], (3, N).
        e, r: lever unit vectors and platform joint vectors in [m], (3, 3, N).
        omega_l: the levers' angular velocity in [rad/s] (with their spin when ``lever_spin``), (3, 3, N).
        lever_axes: the levers' body axes, each (3, 3, N).
        omega_l_body, omega_l_dot_body: ω_l and ω̇_l along the levers' axes, (3, 3, N).
        gravity_minus_a_l: g − a_l of the lever centres in [m/s²] (the levers' weight and inertia per kg), (3, 3, N).
        J_inv_T: J⁻ᵀ by its rows as vectors per leg (xyz, row, N).
    """

    lever_spin: bool
    n_platforms: int
    scale: float
    Fe: np.ndarray
    omega: np.ndarray
    platform_z: np.ndarray
    platform_axes: tuple[np.ndarray, np.ndarray, np.ndarray]
    omega_body: np.ndarray
    omega_dot_body: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    motor_speed: np.ndarray
    e: np.ndarray
    r: np.ndarray
    omega_l: np.ndarray
    lever_axes: tuple[np.ndarray, np.ndarray, np.ndarray]
    omega_l_body: np.ndarray
    omega_l_dot_body: np.ndarray
    gravity_minus_a_l: np.ndarray
    J_inv_T: np.ndarray

    def __len__(self) -> int:
        return self.Fe.size

    def __getitem__(self, samples: slice) -> MotionTerms:
        """The terms of a slice of the samples (views)."""
        if not isinstance(samples, slice):
            raise TypeError("MotionTerms takes a slice of samples")

        def cut(value):
            if isinstance(value, tuple):
                return tuple(cut(v) for v in value)
            return value[..., samples] if isinstance(value, np.ndarray) else value

        return MotionTerms(**{f.name: cut(getattr(self, f.name)) for f in fields(self)})


def motion_terms(
    params: Parameters, kin: Kinematics, Fe: np.ndarray, lever_spin: bool = False, samples: slice = slice(None)
) -> MotionTerms:
    """The terms of :class:`MotionTerms` along a motion.

    Args:
        params: the machine; only its geometry (and g) is used: the terms serve
            every machine that differs from it in masses, inertias and friction coefficients alone.
        kin: kinematics along the trajectory (:func:`hipsim.analytic.inverse_kinematics.kinematics`).
        Fe: hydraulic load magnitude in [N], (N,).
        lever_spin: as in :func:`inverse_dynamics`.
        samples: the samples to compute them for (a block of a long motion), all by default.
    """
    p = params.lead

    def cut(first: np.ndarray) -> np.ndarray:
        """A field of ``kin`` (sample first) components-first, the samples asked for: a view."""
        return first.T[..., samples]

    omega = cut(kin.omega)
    platform_axes = cut(kin.R[:, :, 0]), cut(kin.R[:, :, 1]), cut(kin.R[:, :, 2])
    Ld, Ldd = cut(kin.Ld[:, 0]), cut(kin.Ldd[:, 0])
    e = cut(kin.e)
    omega_l, omega_l_dot = cut(kin.omega_l), cut(kin.omega_l_dot)
    u1 = per_leg(params.ujoint_axes)
    if lever_spin:
        omega_l, omega_l_dot = (
            stack(laws.lever_angular_velocity(u1, e, omega_l)),
            stack(laws.lever_angular_acceleration(u1, e, omega_l, omega_l_dot)),
        )
    lever_axes = _lever_axes_of(params, e)
    # y = J⁻ᵀ·Q for the platform, lever and friction moments: y_i = (row i of J⁻ᵀ)·Q.
    rows = laws.inverse_transpose(np.moveaxis(cut(kin.J), 1, 0))  # from J's rows, (xyz, N) each
    gravity = np.array([0.0, 0.0, -params.gravity])[:, None, None]
    return MotionTerms(
        lever_spin=lever_spin,
        n_platforms=params.heights.size,
        # n is 1 or 2: exact, so the same bits as −n·p/2π
        scale=-params.heights.size * travel_per_radian(p),
        Fe=np.asarray(Fe, dtype=float)[samples],
        omega=omega,
        platform_z=platform_axes[2],
        platform_axes=platform_axes,
        omega_body=_body_components(platform_axes, omega),
        omega_dot_body=_body_components(platform_axes, cut(kin.omega_dot)),
        Ld=Ld,
        Ldd=Ldd,
        motor_speed=angle_from_travel(Ld, p),
        e=e,
        r=cut(kin.r),
        omega_l=omega_l,
        lever_axes=lever_axes,
        omega_l_body=_body_components(lever_axes, omega_l),
        omega_l_dot_body=_body_components(lever_axes, omega_l_dot),
        gravity_minus_a_l=gravity - cut(kin.a_l[:, 0]),
        J_inv_T=np.array([[row[k] for row in rows] for k in range(3)]),  # its rows as vectors per leg (xyz, row, N)
    )


def platform_torques(params: Parameters, m: MotionTerms) -> np.ndarray:
    """The motor torques in [N·m] of the platforms' D'Alembert moment about the fixed centre, (3, N)."""
    Q_m = _euler_moment_body(m.platform_axes, params.platform_inertia, m.omega_body, m.omega_dot_body)
    return m.scale * dot(m.J_inv_T, Q_m)


def lever_torques(params: Parameters, m: MotionTerms) -> np.ndarray:
    """The motor torques in [N·m] of the levers' gravity and inertia (at the centre, mapped to the ends), (3, N).

    A zero mass or inertia adds nothing and is not computed (the same numbers).
    """
    force = _NO_FORCE if params.lever_mass == 0 else params.lever_mass * m.gravity_minus_a_l
    moment = (
        _euler_moment_body(m.lever_axes, params.lever_inertia, m.omega_l_body, m.omega_l_dot_body)
        if np.any(params.lever_inertia)
        else None
    )
    Q_l, Fz_l = _lever_end_forces(params, m.e, m.r, m.lever_spin, force, moment)
    return m.scale * (dot(m.J_inv_T, Q_l) + Fz_l)


def slider_torques(params: Parameters, m: MotionTerms) -> np.ndarray:
    """The motor torques in [N·m] of the sliders' gravity and inertia along the screws, (3, N)."""
    F_L = params.slider_mass * (-params.gravity - m.Ldd)
    return m.scale * F_L


def screw_torques(params: Parameters, m: MotionTerms) -> np.ndarray:
    """The motor torques in [N·m] of the screws' (and rotors') inertia, (3, N)."""
    return angle_from_travel(params.screw_inertia, params.lead) * m.Ldd


def friction_torques(params: Parameters, m: MotionTerms) -> np.ndarray:
    """The motor torques in [N·m] of friction: central chain, lever joints, slider guides and screws, (3, N)."""
    return _friction(params, m, power=False)[0]


def _friction(params: Parameters, m: MotionTerms, power: bool = True):
    """:func:`friction_torques`, the central chain's friction moment τ_mf in [N·m] (3, N), and the power all
    friction dissipates in [W] (N,) (None unless ``power``)."""
    f = params.friction
    tau_mf = central_chain_friction_components(f, params.platform_mass * params.gravity, m.omega, m.Fe, m.platform_z)
    Q_lf, Fz_lf, power_lf = _lever_joint_friction_terms(params, m.e, m.r, m.omega, m.lever_spin, m.omega_l, power=power)
    Q_f = Q_lf - tau_mf
    F_Lf = laws.guide_friction(f, m.Ld, m.motor_speed)
    tau_screw_f = laws.screw_friction(f, m.motor_speed)
    tau_f = tau_screw_f + m.scale * (dot(m.J_inv_T, Q_f) + Fz_lf - F_Lf)
    if not power:
        return tau_f, tau_mf, None
    friction_power = np.sum(tau_screw_f * m.motor_speed, axis=0) + m.n_platforms * (
        np.sum(F_Lf * m.Ld, axis=0) + dot(tau_mf, m.omega) + power_lf
    )
    return tau_f, tau_mf, friction_power


#: Each torque part (the fields of :class:`~hipsim.results.Torques`) from a machine and the motion's terms, (3, N).
PARTS = {
    "platforms": platform_torques,
    "levers": lever_torques,
    "sliders": slider_torques,
    "screws": screw_torques,
    "friction": friction_torques,
}


def torques_from_parts(
    tau_m: np.ndarray,
    tau_l: np.ndarray,
    tau_s: np.ndarray,
    tau_L: np.ndarray,
    tau_f: np.ndarray,
    motor_speed: np.ndarray,
    tau_mf: np.ndarray,
    friction_power: np.ndarray,
) -> Torques:
    """The :class:`~hipsim.results.Torques` of the analytic models (this one and the per-chain one) from their parts.

    Args:
        tau_m, tau_l, tau_s, tau_L, tau_f: the platforms', levers', sliders', screws' and friction's motor
            torques in [N·m], components first, (3, N); the total is their sum.
        motor_speed: the motors' speeds in [rad/s], (3, N).
        tau_mf: the central chain's friction moment on the platform the trajectory gives, in [N·m], (3, N).
        friction_power: the power all friction dissipates in [W], (N,).
    """
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


def torques_of(params: Parameters, m: MotionTerms) -> Torques:
    """:func:`inverse_dynamics` from the motion's terms (:func:`motion_terms`, of a machine of the same geometry)."""
    tau_f, tau_mf, friction_power = _friction(params, m)
    return torques_from_parts(
        platform_torques(params, m),
        lever_torques(params, m),
        slider_torques(params, m),
        screw_torques(params, m),
        tau_f,
        m.motor_speed,
        tau_mf,
        friction_power,
    )


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
    return torques_of(params, motion_terms(params, kin, Fe, lever_spin))


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

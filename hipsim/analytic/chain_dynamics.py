"""The analytic model on a per-chain machine: both platforms, each with its own chains and Jacobian (spec §3–4).

On the drawing both platforms turn alike and every term is computed once and
counted twice (:mod:`hipsim.analytic.virtual_work`). On a per-chain machine
(:mod:`hipsim.machine.chains`) the trajectory gives the motion of one platform,
the *controlled* one (``[geometry] control``, m_2 by default as in the paper):

1. the carriages follow from its inverse kinematics, L = L_c(q_c), and their
   rates and accelerations from its Jacobian, L̇ = J_c·ω_c, L̈ = J_c·ω̇_c + Φ_c;
2. the other platform's attitude from its forward kinematics through its own
   chains, and its rates and accelerations through its own Jacobian,
   ω_f = J_f⁻¹·L̇, ω̇_f = J_f⁻¹·(L̈ − Φ_f) (:func:`hipsim.analytic.stations.follower_motion`);
3. the motor torques by virtual power, the two platforms summed each through its own J_j:

       τ = τ_L + τ_f − (p/2π)·Σ_j [ J_j⁻ᵀ·Q_j + F_L,j − F_Lf,j ]

   with Q_j the generalised moment of platform j, its three levers (each with
   its own length) and its friction — the same terms as the drawing's, per platform.

The outputs keep the CSV contract: ``L_1i`` are the carriage readings (what the
encoders read) and ``L_2i = L_1i − (h_1 − h_2)``, as on the drawing; the
singularity measure and the friction moment are the controlled platform's.
"""

from __future__ import annotations

import numpy as np

from ..exceptions import PoseError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics import laws
from ..physics.friction import central_chain_friction_components
from ..physics.orientation import (
    angular_velocity_map,
    angular_velocity_map_rate,
    inverse_condition_number,
    rotation_matrix,
)
from ..physics.transmission import angle_from_travel, travel_per_radian
from ..physics.vectors import dot, per_leg, stack
from ..results import Torques
from .chain_kinematics import chain_accelerations, chain_jacobian, chain_positions
from .forward_kinematics import solve_pose
from .inverse_kinematics import SINGULAR_COND_INV, Kinematics
from .stackup import lift_motion, lifted_kinematics
from .stations import follower_motion, platform_motion, platform_rates, stacked_motion
from .virtual_work import _euler_moment, _lever_inertia, _lever_joint_friction, _platform_axes, torques_from_parts

__all__ = [
    "ChainMotion",
    "carriage_motion",
    "chain_forward_dynamics",
    "chain_inverse_dynamics",
    "chain_mechanical_energy",
    "chain_motion",
    "chain_slider_motion",
    "platform_kinematics",
]


def platform_kinematics(params: Parameters, j: int, t: np.ndarray, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray):
    """Platform ``j``'s (0 or 1) own kinematics as a :class:`~hipsim.analytic.inverse_kinematics.Kinematics`.

    The fields are those of the drawing's, for this platform alone: the
    per-platform fields ``a, b, L, Ld, Ldd, v_l, a_l`` have one platform
    ((N, 1, 3) and (N, 1, 3, 3)); ``L`` is the U-joint centres' heights b_ji,z.

    Args:
        params: the machine.
        j: platform index, 0 for m_1, 1 for m_2.
        t: sample times in [s], (N,).
        q, qd, qdd: that platform's gait angles in [rad], rates in [rad/s], accelerations in [rad/s²], (N, 3).
    """
    chains = params.chains
    signs = params.angle_signs
    p, pd, pdd = q * signs, qd * signs, qdd * signs
    R = rotation_matrix(p)
    T = angular_velocity_map(p)
    omega = np.einsum("nij,nj->ni", T, pd)
    omega_dot = np.einsum("nij,nj->ni", T, pdd) + np.einsum("nij,nj->ni", angular_velocity_map_rate(p, pd), pd)
    L, r, d = chain_positions(chains, p, j)
    l = chains.lever_lengths[j][None, :, None]
    e = d / l
    J = chain_jacobian(r, d)
    Ld = np.einsum("nij,nj->ni", J, omega)
    Ldd = chain_accelerations(r, d, omega, omega_dot)
    z = np.array([0.0, 0.0, 1.0])
    a_dot = np.cross(omega[:, None], r)
    a_ddot = np.cross(omega_dot[:, None], r) + np.cross(omega[:, None], a_dot)
    omega_l = np.cross(e, a_dot - Ld[..., None] * z) / l
    omega_l_dot = np.cross(e, a_ddot - Ldd[..., None] * z) / l
    a = chains.centres[j] + r
    b = chains.screw_points[j] + L[..., None] * z
    cond_inv = inverse_condition_number(J)
    return Kinematics(
        t=t,
        q=p,
        qd=pd,
        qdd=pdd,
        R=R,
        omega=omega,
        omega_dot=omega_dot,
        r=r,
        a=a[:, None],
        b=b[:, None],
        e=e,
        L=b[:, None, :, 2],
        Ld=Ld[:, None],
        Ldd=Ldd[:, None],
        J=J,
        cond_inv=cond_inv,
        omega_l=omega_l,
        omega_l_dot=omega_l_dot,
        v_l=(0.5 * (a_dot + Ld[..., None] * z))[:, None],
        a_l=(0.5 * (a_ddot + Ldd[..., None] * z))[:, None],
        flagged=~(cond_inv >= SINGULAR_COND_INV),
    )


class ChainMotion:
    """Both platforms' kinematics along a trajectory on a per-chain machine.

    Attributes:
        control: the controlled platform (1 or 2).
        platforms: the two platforms' :class:`Kinematics` (index 0 for m_1).
        L, Ld, Ldd: carriage readings in [m], rates [m/s], accelerations [m/s²], (N, 3).
        lift: with a stack-up, m_1's centre lift Δz [m], ż [m/s], z̈ [m/s²] (each (N,)) and g [m] (N, 3)
            (:func:`hipsim.analytic.stackup.lift_motion`); None without.
    """

    def __init__(
        self, control: int, platforms: list, L: np.ndarray, Ld: np.ndarray, Ldd: np.ndarray, lift: tuple | None = None
    ):
        self.control, self.platforms, self.L, self.Ld, self.Ldd = control, platforms, L, Ld, Ldd
        self.lift = lift

    @property
    def controlled(self) -> Kinematics:
        """The controlled platform's kinematics."""
        return self.platforms[self.control - 1]


def chain_motion(params: Parameters, trajectory: Trajectory) -> ChainMotion:
    """The carriages and both platforms' motion when the trajectory is the controlled platform's (module docstring).

    Raises:
        PoseError: naming the time of the first pose out of reach or singular, of either platform.
    """
    assert params.geometry is not None
    control = params.geometry.control
    t, q, qd, qdd = trajectory.t, trajectory.q, trajectory.qd, trajectory.qdd
    stacked = params.chains.stacked
    if stacked and control == 1:  # m_2 follows m_1 through the stack-up: one coupled problem
        try:
            L, Ld, Ldd, m2 = stacked_motion(params, q, qd, qdd)
        except PoseError as error:
            k = min(max(error.index, 0), len(t) - 1)
            raise PoseError(
                f"platform 2 under m_1's stack-up: {error.reason}", float(t[k]), k, trajectory.name
            ) from None
    else:
        L, Ld, Ldd = platform_motion(params, q, qd, qdd, control)
    bad = ~np.all(np.isfinite(L), axis=1)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise PoseError(
            f"pose out of reach for platform {control}: a lever cannot span the gap from its U-joint to its platform joint",
            float(t[k]),
            k,
            source=trajectory.name,
        )
    follower = 3 - control
    motions = {control: (q, qd, qdd)}
    lift, flat, seen = None, params, (L, Ld, Ldd)
    if stacked:  # m_1 moves on its seen carriages, lifted with its centre (hipsim.analytic.stackup)
        if control == 1:
            motions[2] = m2
        flat = params.replace(geometry=params.geometry.replace(spline=np.zeros(3)))
        lift = _lift_of(params, motions[2])
        z, zd, zdd, _ = lift
        seen = (L - z[:, None], Ld - zd[:, None], Ldd - zdd[:, None])
    if follower not in motions:
        # The follower turns a fraction of a degree off the controlled platform: its attitude is the guess.
        motions[follower] = follower_motion(flat, *seen, follower, t=t, q0=q[0], source=trajectory.name, guess=q)
    platforms = [platform_kinematics(flat, j - 1, t, *motions[j]) for j in (1, 2)]
    if lift is not None:
        platforms[0] = lifted_kinematics(platforms[0], *lift[:3])
    for j, kin in enumerate(platforms, start=1):
        if np.any(kin.flagged):
            k = int(np.argmax(kin.flagged))
            raise PoseError(
                f"singular pose of platform {j}: inverse condition number of its J is {kin.cond_inv[k]:.3g}",
                float(t[k]),
                k,
                source=trajectory.name,
            )
    return ChainMotion(control, platforms, L, Ld, Ldd, lift)


def carriage_motion(
    params: Parameters, t: np.ndarray, L: np.ndarray, Ld: np.ndarray, Ldd: np.ndarray, guess: np.ndarray
) -> ChainMotion:
    """Both platforms' motion for a given carriage motion (the forward route): each follows through its own chains.

    With a stack-up m_2 first, then m_1 on its seen carriages, lifted with its centre. Each attitude by Newton from
    ``guess`` (:func:`hipsim.analytic.forward_kinematics.solve_pose`: a plant's state, not a log to walk).

    Args:
        params: the machine (per-chain).
        t: sample times in [s], (N,).
        L, Ld, Ldd: carriage readings [m], rates [m/s], accelerations [m/s²], each (N, 3).
        guess: gait angles near both platforms' in [rad], (N, 3).

    Raises:
        PoseError: a platform cannot take the carriages, or is singular there.
    """
    assert params.geometry is not None
    q2 = solve_pose(params, L, guess, platform=2)
    m2 = (q2, *platform_rates(params, q2, Ld, Ldd, 2))
    flat, seen, lift = params, (L, Ld, Ldd), None
    if params.chains.stacked:
        flat = params.replace(geometry=params.geometry.replace(spline=np.zeros(3)))
        lift = _lift_of(params, m2)
        z, zd, zdd, _ = lift
        seen = (L - z[:, None], Ld - zd[:, None], Ldd - zdd[:, None])
    q1 = solve_pose(flat, seen[0], guess, platform=1)
    m1 = (q1, *platform_rates(flat, q1, *seen[1:], 1))
    platforms = [platform_kinematics(flat, 0, t, *m1), platform_kinematics(flat, 1, t, *m2)]
    if lift is not None:
        platforms[0] = lifted_kinematics(platforms[0], *lift[:3])
    return ChainMotion(params.geometry.control, platforms, L, Ld, Ldd, lift)


def chain_forward_dynamics(
    params: Parameters,
    L: np.ndarray,
    Ld: np.ndarray,
    tau: np.ndarray,
    Fe: float,
    guess: np.ndarray,
    lever_spin: bool = False,
) -> np.ndarray:
    """The carriages' accelerations [m/s²], (3,), under motor torques ``tau`` [N·m], (3,), and load Fe [N].

    The inverse dynamics are affine in L̈ at given (L, L̇): τ = M·L̈ + b, M's columns and b from
    :func:`chain_inverse_dynamics` at L̈ = e_k and 0; then L̈ = M⁻¹·(τ − b). Exact, and slow (a plant for checks).

    Args:
        params: the machine (per-chain); L [m], Ld [m/s]: the carriages, (3,); guess: both platforms' gait angles
            near their attitudes [rad], (3,); lever_spin: as :func:`chain_inverse_dynamics`.
    """
    n = 4
    accelerations = np.vstack([np.zeros(3), np.eye(3)])
    motion = carriage_motion(
        params,
        np.zeros(n),
        np.tile(np.asarray(L, dtype=float), (n, 1)),
        np.tile(np.asarray(Ld, dtype=float), (n, 1)),
        accelerations,
        np.tile(np.asarray(guess, dtype=float), (n, 1)),
    )
    total = chain_inverse_dynamics(params, motion, np.full(n, float(Fe)), lever_spin).total
    return np.linalg.solve((total[1:] - total[0]).T, np.asarray(tau, dtype=float) - total[0])


def _lift_of(params: Parameters, m2: tuple) -> tuple:
    """:func:`hipsim.analytic.stackup.lift_motion` of m_2's motion (gait angles, rates, accelerations)."""
    p2, pd2, pdd2 = (x * params.angle_signs for x in m2)
    T = angular_velocity_map(p2)
    omega2 = np.einsum("nij,nj->ni", T, pd2)
    omega2_dot = np.einsum("nij,nj->ni", T, pdd2) + np.einsum("nij,nj->ni", angular_velocity_map_rate(p2, pd2), pd2)
    return lift_motion(params.chains.spline_seat, p2, omega2, omega2_dot)


def chain_inverse_dynamics(
    params: Parameters, motion: ChainMotion, Fe: np.ndarray, lever_spin: bool = False
) -> Torques:
    """Motor torques and their parts on a per-chain machine: both platforms, each through its own Jacobian.

    Args:
        params: the machine (per-chain).
        motion: :func:`chain_motion`'s result.
        Fe: hydraulic load magnitude in [N], (N,).
        lever_spin: as in :func:`hipsim.analytic.virtual_work.inverse_dynamics`.

    Returns:
        The torques; their parts add up to the total. The friction moment is the controlled platform's.
    """
    Fe = np.asarray(Fe, dtype=float)
    f, p = params.friction, params.lead
    chains = params.chains
    Ld, Ldd = motion.Ld.T, motion.Ldd.T  # components first, (3, N)
    motor_speed = angle_from_travel(Ld, p)
    scale = -travel_per_radian(p)
    parts = {name: np.zeros_like(Ldd) for name in ("m", "l", "f")}
    friction_power = laws.screw_friction(f, motor_speed) * motor_speed
    friction_power = np.sum(friction_power, axis=0)
    F_Lf = laws.guide_friction(f, Ld, motor_speed)
    tau_mf_controlled = None
    for j, kin in enumerate(motion.platforms):
        omega = kin.omega.T
        omega_l, omega_l_dot = kin.omega_l.T, kin.omega_l_dot.T
        if lever_spin:
            u1, e = per_leg(params.ujoint_axes), kin.e.T
            omega_l, omega_l_dot = (
                stack(laws.lever_angular_velocity(u1, e, omega_l)),
                stack(laws.lever_angular_acceleration(u1, e, omega_l, omega_l_dot)),
            )
        lengths = chains.lever_lengths[j][:, None]
        Q_m = _euler_moment(_platform_axes(kin), params.platform_inertia, omega, kin.omega_dot.T)
        Q_l, Fz_l = _lever_inertia(params, kin, lever_spin, omega_l, omega_l_dot, lengths)
        tau_mf = central_chain_friction_components(
            f, params.platform_mass * params.gravity, omega, Fe, kin.R[:, :, 2].T
        )
        Q_lf, Fz_lf, power_lf = _lever_joint_friction(params, kin, lever_spin, omega_l, lengths)
        J_inv_T = _inverse_transpose(kin.J)
        G = {"m": dot(J_inv_T, Q_m), "l": dot(J_inv_T, Q_l) + Fz_l, "f": dot(J_inv_T, Q_lf - tau_mf) + Fz_lf}
        if j == 0 and motion.lift is not None:
            for name, coupling in _stackup_coupling(params, motion, G, Fe).items():
                G[name] = G[name] + coupling
        parts["m"] = parts["m"] + scale * G["m"]
        parts["l"] = parts["l"] + scale * G["l"]
        parts["f"] = parts["f"] + scale * (G["f"] - F_Lf)
        friction_power = friction_power + np.sum(F_Lf * Ld, axis=0) + dot(tau_mf, omega) + power_lf
        if j == motion.control - 1:
            tau_mf_controlled = tau_mf
    tau_m, tau_l = parts["m"], parts["l"]
    tau_s = 2 * scale * (params.slider_mass * (-params.gravity - Ldd))  # both sliders of each carriage
    tau_L = angle_from_travel(params.screw_inertia, p) * Ldd
    tau_f = laws.screw_friction(f, motor_speed) + parts["f"]
    assert tau_mf_controlled is not None
    return torques_from_parts(tau_m, tau_l, tau_s, tau_L, tau_f, motor_speed, tau_mf_controlled, friction_power)


def _inverse_transpose(J: np.ndarray) -> np.ndarray:
    """J⁻ᵀ of (N, 3, 3) Jacobians as components-first rows, (3, 3, N), for :func:`hipsim.physics.vectors.dot`."""
    rows = laws.inverse_transpose(np.moveaxis(J.T, 1, 0))
    return np.array([[row[k] for row in rows] for k in range(3)])


def _stackup_coupling(params: Parameters, motion: ChainMotion, G: dict, Fe: np.ndarray) -> dict:
    """The stack-up's term J_2⁻ᵀ·g·(F_1z − 1ᵀ·G_1) per part (:mod:`hipsim.analytic.stackup`), each (3, N) [N].

    G: m_1's generalised forces on its seen carriages by part (platforms, levers, friction), each (3, N) [N]. The
    vertical resultants: the platform's −m_m·(g + z̈) − F_e (the load does work now), the levers' m_l·(g⃗ − a_l)_z;
    friction moments have none.
    """
    assert motion.lift is not None
    _, _, zdd, g = motion.lift
    h = dot(_inverse_transpose(motion.platforms[1].J), g.T)  # J_2⁻ᵀ·g, (3, N)
    a_l = motion.platforms[0].a_l[:, 0, :, 2]  # the levers' real vertical accelerations, (N, 3)
    vertical = {
        "m": -params.platform_mass * (params.gravity + zdd) - Fe,
        "l": -params.lever_mass * (params.gravity + a_l).sum(axis=1),
        "f": np.zeros_like(zdd),
    }
    return {name: h * (vertical[name] - G[name].sum(axis=0)) for name in G}


def chain_slider_motion(params: Parameters, motion: ChainMotion) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The CSV contract's L, L̇, L̈ (N, 2, 3): L_1i the carriage readings, L_2i = L_1i − (h_1 − h_2)."""
    offset = np.array([0.0, params.heights[1] - params.heights[0]])[None, :, None]
    L = motion.L[:, None, :] + offset
    return L, np.repeat(motion.Ld[:, None], 2, axis=1), np.repeat(motion.Ldd[:, None], 2, axis=1)


def chain_mechanical_energy(params: Parameters, motion: ChainMotion, lever_spin: bool = False):
    """Kinetic and potential energy of the whole per-chain machine in [J], each (N,), from body motions alone.

    Independent of :func:`chain_inverse_dynamics`: the power balance Σ τ·θ̇ = dE/dt + friction power checks it
    (with a stack-up, + F_e·ż: the load does work on m_1's moving centre).
    """
    from .virtual_work import _lever_axes, _rotational_energy

    kinetic = 0.5 * params.screw_inertia * np.sum(angle_from_travel(motion.Ld, params.lead) ** 2, axis=1)
    potential = np.zeros(len(motion.L))
    for kin in motion.platforms:
        omega_l = kin.omega_l.T
        if lever_spin:
            omega_l = laws.lever_angular_velocity(per_leg(params.ujoint_axes), kin.e.T, omega_l)
        v_l = kin.v_l[:, 0].T
        kinetic = kinetic + _rotational_energy(_platform_axes(kin), params.platform_inertia, kin.omega.T)
        kinetic = kinetic + np.sum(0.5 * params.lever_mass * dot(v_l, v_l), axis=0)
        kinetic = kinetic + np.sum(_rotational_energy(_lever_axes(params, kin), params.lever_inertia, omega_l), axis=0)
        kinetic = kinetic + 0.5 * params.slider_mass * np.sum(motion.Ld**2, axis=1)
        lever_height = 0.5 * (kin.a[:, 0, :, 2] + kin.b[:, 0, :, 2])
        potential = potential + params.gravity * (
            params.lever_mass * lever_height.sum(axis=1) + params.slider_mass * kin.b[:, 0, :, 2].sum(axis=1)
        )
    if motion.lift is not None:  # m_1 rides up and down with its centre: m_m's own energy changes now
        z, zd, _, _ = motion.lift
        kinetic = kinetic + 0.5 * params.platform_mass * zd**2
        potential = potential + params.platform_mass * params.gravity * z
    return kinetic, potential

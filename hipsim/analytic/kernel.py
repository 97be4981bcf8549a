"""The reduced plant's equations for one state at a time, compiled with numba (spec §3, §4, §7.3, §8).

Why this module exists. The servo loop of :func:`hipsim.control.simulation.simulate`
evaluates the forward dynamics of one state at a time, eight times per servo
period (two RK4 steps of four stages). Through the vectorised model of
:mod:`hipsim.analytic.inverse_kinematics` and :mod:`hipsim.analytic.virtual_work` each evaluation is some
seven hundred NumPy calls on arrays of four samples, ~490 µs of Python
overhead for a few thousand floating-point operations: the reduced plant ran
at a quarter of real time. Here the same equations are written for a single
state on plain floats and compiled, so that a whole servo period costs ~15 µs.

The vectorised model stays the reference: ``tests/analytic/test_kernel.py``
checks :func:`torques`, :func:`mass_and_bias`, :func:`jacobian` and
:func:`workspace_pd` against it to round-off on random states with every
friction coefficient on, and the plant's agreement with the Pinocchio plant
is tested in ``tests/closed_chain/test_plant.py``. The names follow those modules, so
each line here can be read against its vectorised counterpart; the laws both
use (rotation maps, lever spin, friction) are written once, in
:mod:`hipsim.physics.laws`.

Conventions. Vectors are 3-tuples of floats (values, so nothing is allocated
on the heap), matrices are 3-tuples of rows. The machine travels as a
:class:`KernelParameters` named tuple built once by :func:`kernel_parameters`.
Angles come in as gait angles; the parameter file's angle signs are applied
inside, as :func:`hipsim.analytic.inverse_kinematics.kinematics` does. A pose out of reach gives
NaN, which the servo loop reports as the plant leaving its workspace.

The first call compiles the functions (~13 s for the plant and the PD law on
the development machine, others' jobs running); numba caches the machine code next to this file (or in its user-wide
cache when that folder is read-only), keyed on this file and the laws', so
later processes load it in well under a second. Where neither can be written,
the kernels are compiled in every process, with a warning.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from ..exceptions import ArgumentError
from ..machine.parameters import Parameters
from ..physics import laws
from ..physics.laws import FrictionRecord
from ..physics.transmission import angle_from_travel, travel_per_radian
from ..physics.vectors import add, cross, dot, matvec, scale, sub, transpose_times

__all__ = [
    "KernelParameters",
    "advance",
    "derivative",
    "floats",
    "jacobian",
    "kernel_parameters",
    "mass_and_bias",
    "named_parameters",
    "plain_parameters",
    "torques",
    "workspace_pd",
]

Vector = tuple  # (x, y, z) floats
Matrix = tuple  # three rows

#: Compile with numba, caching the machine code (keyed on the laws too: see :func:`hipsim.physics.laws.jit`).
_compile = laws.jit


class KernelParameters(NamedTuple):
    """The machine as the kernels read it, in SI units (fields as in :class:`hipsim.machine.parameters.Parameters`).

    Per-leg vectors are 3-tuples of (x, y, z) rows; inertias are 3-tuples of rows.
    """

    gravity: float
    lever_length: float
    lead: float
    screw_inertia: float
    slider_mass: float
    lever_mass: float
    platform_mass: float
    n_platforms: float
    platform_inertia: Matrix
    lever_inertia: Matrix
    platform_points: Matrix
    screw_points: Matrix
    ujoint_axes: Matrix
    angle_signs: Vector
    lever_spin: bool
    friction: FrictionRecord


def kernel_parameters(params: Parameters, lever_spin: bool = True) -> KernelParameters:
    """The machine for the kernels.

    Args:
        params: the machine.
        lever_spin: give the levers the spin their universal joints impose
            (as :func:`hipsim.analytic.virtual_work.inverse_dynamics` with ``lever_spin=True``).
    """

    params.require_drawing("the compiled single-state model (reduced plant, servo loop, controllers)")

    # Plain floats throughout: numba compiles once per combination of argument types.
    def rows(matrix) -> Matrix:
        return tuple(tuple(float(x) for x in row) for row in np.asarray(matrix))

    return KernelParameters(
        gravity=float(params.gravity),
        lever_length=float(params.lever_length),
        lead=float(params.lead),
        screw_inertia=float(params.screw_inertia),
        slider_mass=float(params.slider_mass),
        lever_mass=float(params.lever_mass),
        platform_mass=float(params.platform_mass),
        n_platforms=float(params.heights.size),
        platform_inertia=rows(params.platform_inertia),
        lever_inertia=rows(params.lever_inertia),
        platform_points=rows(params.platform_points),
        screw_points=rows(params.screw_points),
        ujoint_axes=rows(params.ujoint_axes),
        angle_signs=tuple(float(s) for s in params.angle_signs),
        lever_spin=bool(lever_spin),
        friction=laws.friction_record(params.friction),
    )


def plain_parameters(P: KernelParameters) -> tuple:
    """P as nested plain tuples, for a compiled function called once per servo period (:func:`named_parameters` turns it back).

    numba types a plain tuple in C but a named one in Python, field by field:
    1.1 against 2.9 µs a call on the development machine.
    """
    return (*P[:-1], tuple(P.friction))


@_compile
def named_parameters(plain):
    """The :class:`KernelParameters` of :func:`plain_parameters`, in compiled code."""
    # numba compiles the call form; mypy counts *plain[:-1] as every field, then one more.
    return KernelParameters(*plain[:-1], FrictionRecord(*plain[-1]))  # type: ignore[call-arg]


def floats(x, shape: tuple[int, ...], name: str) -> np.ndarray:
    """x as a float64 array of the given shape (no copy if it is one), to pass to the kernels.

    The kernels are compiled for float64 arrays and, being compiled, do not
    check bounds: a short array would be read past its end.

    Raises:
        HipsimError: naming the argument when x is not numbers of that shape.
    """
    try:
        array = np.asarray(x, dtype=np.float64)
    except (TypeError, ValueError):
        raise ArgumentError(name, x, "numbers") from None
    if array.shape != shape:
        raise ArgumentError(name, array, f"shape {shape}")
    return array


# --- Kinematics (hipsim.analytic.inverse_kinematics) ----------------------------------


@_compile
def _trig(q):
    """The cosines and sines of q = [α, β, γ] after angle signs, as the rotation laws take them."""
    return (math.cos(q[0]), math.cos(q[1]), math.cos(q[2])), (math.sin(q[0]), math.sin(q[1]), math.sin(q[2]))


@_compile
def _lever_geometry(P, R, platform_point, screw_point):
    """r_i = R·r⁰_i and the lever's unit vector e_i; NaN when the lever cannot reach."""
    r = matvec(R, platform_point)
    c = screw_point
    dx, dy = r[0] - c[0], r[1] - c[1]
    l = P.lever_length
    radicand = l**2 - (dx**2 + dy**2)
    if not radicand > 0:
        return r, (math.nan, math.nan, math.nan)
    return r, (dx / l, dy / l, math.sqrt(radicand) / l)


@_compile
def _jacobian_rows(P, R):
    """The rows (r_i × e_i)/e_i,z of J (L̇ = J·ω) and the r_i, e_i, at the platform rotation R (rows)."""
    r0, e0 = _lever_geometry(P, R, P.platform_points[0], P.screw_points[0])
    r1, e1 = _lever_geometry(P, R, P.platform_points[1], P.screw_points[1])
    r2, e2 = _lever_geometry(P, R, P.platform_points[2], P.screw_points[2])
    J = (scale(cross(r0, e0), 1.0 / e0[2]), scale(cross(r1, e1), 1.0 / e1[2]), scale(cross(r2, e2), 1.0 / e2[2]))
    return J, (r0, r1, r2), (e0, e1, e2)


@_compile
def _jacobian_at(P, q):
    """J's rows at gait angles q."""
    c, s = _trig(_signed(P, q))
    J, _, _ = _jacobian_rows(P, laws.rotation(c, s))
    return J


@_compile
def _signed(P, v):
    """Gait angles (or their rates) to the platform's angles: the parameter file's angle signs."""
    return (v[0] * P.angle_signs[0], v[1] * P.angle_signs[1], v[2] * P.angle_signs[2])


# --- Inverse dynamics (hipsim.analytic.virtual_work) -----------------------------------
# The vectorised model and this kernel stay two transcriptions of the virtual-work
# assembly because one runs whole-array NumPy operations on every sample at once and the
# other scalar code on one state: the laws they share come from hipsim.physics.laws,
# and tests/analytic/test_kernel.py ties the two to round-off.


class _LeverMotion(NamedTuple):
    """One leg's velocity level, what its acceleration level needs (inverse_kinematics._kinematics)."""

    r: Vector  # r_i = R·r⁰_i [m]
    e: Vector  # lever unit vector e_i
    w_perp: Vector  # lever angular velocity without spin [rad/s]
    centripetal: Vector  # ω × ȧ, the velocity part of ä [m/s²]
    l_w_perp_sq: float  # l·|w_perp|², the centripetal part of e_z·L̈ [m/s²]
    omega_l: Vector  # lever angular velocity, with spin when P.lever_spin [rad/s]
    axes: Matrix  # rows: the lever's x, y, z axes (spec §7.1)
    u1: Vector  # its universal joint's slider-fixed axis


@_compile
def _lever_velocity(P, r, e, J_i, omega, u1):
    """Velocity level of a leg whose U joint's axis is u1 (inverse_kinematics._kinematics; the laws' lever spin and axes).

    The kernels pass each leg's own vectors rather than its index: numba would
    compile a function once per literal index (three times the compile time).
    """
    l = P.lever_length
    Ld = dot(J_i, omega)
    a_dot = cross(omega, r)
    w_perp = scale(cross(e, (a_dot[0], a_dot[1], a_dot[2] - Ld)), 1.0 / l)
    omega_l = laws.lever_angular_velocity(u1, e, w_perp) if P.lever_spin else w_perp
    return _LeverMotion(r, e, w_perp, cross(omega, a_dot), l * dot(w_perp, w_perp), omega_l, laws.lever_axes(u1, e), u1)


@_compile
def _euler_moment(axes, inertia, w, w_dot):
    """The D'Alembert moment −I_w·ω̇ − ω × I_w·ω in world axes, evaluated in body axes (the rows of ``axes``)."""
    w_body = matvec(axes, w)
    moment_body = sub(scale(matvec(inertia, matvec(axes, w_dot)), -1.0), cross(w_body, matvec(inertia, w_body)))
    return transpose_times(axes, moment_body)


@_compile
def _lever_ends(P, lever, force, moment):
    """A wrench on the lever (force at its centre, moment) as r × f_a on the platform and f_b,z on the slider."""
    if P.lever_spin:
        moment = laws.spin_transpose(lever.u1, lever.e, moment)
    m_cross_e = scale(cross(moment, lever.e), 1.0 / P.lever_length)
    f_a = add(scale(force, 0.5), m_cross_e)
    return cross(lever.r, f_a), 0.5 * force[2] - m_cross_e[2]


@_compile
def _lever_acceleration(P, lever, omega_dot, full):
    """A leg at platform acceleration ω̇: L̈_i, and its lever's gravity and D'Alembert wrench mapped to the ends.

    ``full`` False: only the terms proportional to ω̇ (no velocity terms, no
    gravity), the lever's share of a column of M.
    """
    l, e = P.lever_length, lever.e
    a_ddot = add(cross(omega_dot, lever.r), lever.centripetal) if full else cross(omega_dot, lever.r)
    Ldd = (dot(e, a_ddot) + lever.l_w_perp_sq) / e[2] if full else dot(e, a_ddot) / e[2]
    omega_l_dot = scale(cross(e, (a_ddot[0], a_ddot[1], a_ddot[2] - Ldd)), 1.0 / l)
    if P.lever_spin:
        if full:
            omega_l_dot = laws.lever_angular_acceleration(lever.u1, e, lever.w_perp, omega_l_dot)
        else:  # the spin's rate, ṡ·e + s·ė, is the spin map of ω̇_⊥ plus velocity terms
            omega_l_dot = laws.lever_angular_velocity(lever.u1, e, omega_l_dot)
    a_l = (0.5 * a_ddot[0], 0.5 * a_ddot[1], 0.5 * a_ddot[2] + 0.5 * Ldd)
    force = scale((a_l[0], a_l[1], a_l[2] + P.gravity if full else a_l[2]), -P.lever_mass)  # m_l·(g − a_l)
    if full:
        moment = _euler_moment(lever.axes, P.lever_inertia, lever.omega_l, omega_l_dot)
    else:
        moment = transpose_times(lever.axes, scale(matvec(P.lever_inertia, matvec(lever.axes, omega_l_dot)), -1.0))
    Q, f_b_z = _lever_ends(P, lever, force, moment)
    return Ldd, Q, f_b_z


@_compile
def _leg_friction(P, lever, J_i, omega):
    """A leg's friction: generalised moment of its lever joints, forces along the screw, screw torque."""
    Ld = dot(J_i, omega)
    motor_speed = angle_from_travel(Ld, P.lead)
    F = P.friction
    screw = laws.screw_friction(F, motor_speed)
    guide = laws.guide_friction(F, Ld, motor_speed)
    if not laws.lever_joint_friction_on(F):
        return (0.0, 0.0, 0.0), -guide, screw
    tau_bf, tau_af = laws.lever_joint_friction(F, lever.omega_l, omega)
    Q, f_b_z = _lever_ends(P, lever, (0.0, 0.0, 0.0), scale(add(tau_af, tau_bf), -1.0))
    return add(Q, tau_af), f_b_z - guide, screw


class _State(NamedTuple):
    """Everything at one state (q, q̇) that does not depend on the acceleration."""

    cos_sin: tuple  # the cosines and sines of q, for the rotation laws
    platform_axes: Matrix  # rows: the platform's x, y, z axes (the columns of R)
    omega: Vector  # platform angular velocity [rad/s]
    J_inv_T: Matrix  # J⁻ᵀ
    levers: tuple  # three _LeverMotion
    Q_f: Vector  # friction moment on the platform [N·m]
    slider_f: Vector  # friction forces along the screws, per leg [N]
    screw_f: Vector  # screw friction torques, per motor [N·m]


@_compile
def _state(P, q, qd, Fe):
    """The velocity level at orientation q [rad] and rate q̇ [rad/s] (after angle signs), load Fe [N]."""
    c, s = _trig(q)
    R = laws.rotation(c, s)
    omega = laws.t_times(c, s, qd)
    J, r, e = _jacobian_rows(P, R)
    levers = (
        _lever_velocity(P, r[0], e[0], J[0], omega, P.ujoint_axes[0]),
        _lever_velocity(P, r[1], e[1], J[1], omega, P.ujoint_axes[1]),
        _lever_velocity(P, r[2], e[2], J[2], omega, P.ujoint_axes[2]),
    )
    platform_axes = ((R[0][0], R[1][0], R[2][0]), (R[0][1], R[1][1], R[2][1]), (R[0][2], R[1][2], R[2][2]))
    # Central chain: hip joint and thrust bearing (spec §4.3).
    tau_mf = laws.central_friction_moment(P.friction, omega, platform_axes[2], Fe, P.platform_mass * P.gravity)
    Q0, slider0, screw0 = _leg_friction(P, levers[0], J[0], omega)
    Q1, slider1, screw1 = _leg_friction(P, levers[1], J[1], omega)
    Q2, slider2, screw2 = _leg_friction(P, levers[2], J[2], omega)
    Q_f = sub(add(add(Q0, Q1), Q2), tau_mf)
    return _State(
        (c, s),
        platform_axes,
        omega,
        laws.inverse_transpose(J),
        levers,
        Q_f,
        (slider0, slider1, slider2),
        (screw0, screw1, screw2),
    )


@_compile
def _torques_at(P, S, omega_dot, full):
    """Motor torques [N·m] at state S and platform angular acceleration ω̇ [rad/s²] (spec §4.2).

    ``full`` False: only the part proportional to ω̇, M·ω̇ in the platform's
    angular acceleration (no velocity terms, gravity or friction).
    """
    Ldd0, Q0, fz0 = _lever_acceleration(P, S.levers[0], omega_dot, full)
    Ldd1, Q1, fz1 = _lever_acceleration(P, S.levers[1], omega_dot, full)
    Ldd2, Q2, fz2 = _lever_acceleration(P, S.levers[2], omega_dot, full)
    if full:
        Q_m = _euler_moment(S.platform_axes, P.platform_inertia, S.omega, omega_dot)
        Q = add(add(add(add(Q_m, Q0), Q1), Q2), S.Q_f)
    else:
        Q_m = transpose_times(
            S.platform_axes, scale(matvec(P.platform_inertia, matvec(S.platform_axes, omega_dot)), -1.0)
        )
        Q = add(add(add(Q_m, Q0), Q1), Q2)
    scale_ = -P.n_platforms * travel_per_radian(P.lead)  # n is 1 or 2: exact, so the same bits as −n·p/2π
    screw = angle_from_travel(P.screw_inertia, P.lead)
    gravity = P.gravity if full else 0.0

    def motor(i, Ldd, f_b_z):
        slider = P.slider_mass * (-gravity - Ldd)
        if not full:
            return scale_ * (dot(S.J_inv_T[i], Q) + f_b_z + slider) + screw * Ldd
        return scale_ * (dot(S.J_inv_T[i], Q) + f_b_z + slider + S.slider_f[i]) + screw * Ldd + S.screw_f[i]

    return (motor(0, Ldd0, fz0), motor(1, Ldd1, fz1), motor(2, Ldd2, fz2))


@_compile
def _mass_and_bias(P, x, Fe):
    """M (three columns) and h with τ = M·q̈ + h, in gait angles, at state x = (q, q̇) and load Fe."""
    q = _signed(P, (x[0], x[1], x[2]))
    qd = _signed(P, (x[3], x[4], x[5]))
    S = _state(P, q, qd, Fe)
    c, s = S.cos_sin
    bias = laws.t_dot_times(c, s, qd, qd)  # ω̇ at q̈ = 0
    # bool(...): a plain boolean, not a literal, so that numba compiles _torques_at once, not per value.
    full, inertial = True, False
    h = _torques_at(P, S, bias, full)
    sg = P.angle_signs
    # τ is affine in q̈: column k of M is the part proportional to ω̇ = T·(sign_k·unit_k),
    # evaluated alone (cheaper than τ(q̈ = unit k) − h, and without its cancellation).
    m0 = _torques_at(P, S, laws.t_times(c, s, (sg[0], 0.0, 0.0)), inertial)
    m1 = _torques_at(P, S, laws.t_times(c, s, (0.0, sg[1], 0.0)), inertial)
    m2 = _torques_at(P, S, laws.t_times(c, s, (0.0, 0.0, sg[2])), inertial)
    return (m0, m1, m2), h


@_compile
def _solve(columns, b):
    """x with M·x = b, M given by its columns, by Cramer's rule."""
    c0, c1, c2 = columns
    c12 = cross(c1, c2)
    det = dot(c0, c12)
    return (dot(b, c12) / det, dot(c0, cross(b, c2)) / det, dot(c0, cross(c1, b)) / det)


@_compile
def _derivative(P, x, tau, Fe):
    """dx/dt = (q̇, M⁻¹·(τ − h)) as a 6-tuple."""
    M, h = _mass_and_bias(P, x, Fe)
    qdd = _solve(M, sub(tau, h))
    return (x[3], x[4], x[5], qdd[0], qdd[1], qdd[2])


@_compile
def _axpy(x, a, k):
    """x + a·k for 6-tuples."""
    return (x[0] + a * k[0], x[1] + a * k[1], x[2] + a * k[2], x[3] + a * k[3], x[4] + a * k[4], x[5] + a * k[5])


# --- Public kernels: NumPy arrays in and out ------------------------------------------


@_compile
def torques(P, q, qd, qdd, Fe):
    """Inverse dynamics at one state: motor torques in [N·m], (3,).

    Args:
        P: the machine (:func:`kernel_parameters`).
        q: gait angles [α, β, γ] in [rad], (3,).
        qd: their rates in [rad/s], (3,).
        qdd: their accelerations in [rad/s²], (3,).
        Fe: load in [N].
    """
    q_s, qd_s, qdd_s = _signed(P, q), _signed(P, qd), _signed(P, qdd)
    S = _state(P, q_s, qd_s, Fe)
    c, s = S.cos_sin
    omega_dot = add(laws.t_times(c, s, qdd_s), laws.t_dot_times(c, s, qd_s, qd_s))
    return np.array(_torques_at(P, S, omega_dot, True))


@_compile
def mass_and_bias(P, q, qd, Fe):
    """M(q) in [N·m·s²/rad], (3, 3), and h(q, q̇, F_e) in [N·m], (3,), with τ = M·q̈ + h (gait angles)."""
    M, h = _mass_and_bias(P, (q[0], q[1], q[2], qd[0], qd[1], qd[2]), Fe)
    return np.array(M).T.copy(), np.array(h)


@_compile
def derivative(P, x, tau, Fe):
    """dx/dt for the state x = [q, q̇] (gait angles, [rad], [rad/s]), (6,), under motor torques tau [N·m], load Fe [N]."""
    return np.array(_derivative(P, (x[0], x[1], x[2], x[3], x[4], x[5]), (tau[0], tau[1], tau[2]), Fe))


@_compile
def advance(P, x, tau, loads, h, substeps):
    """The state after ``substeps`` classic RK4 steps of h [s] under constant motor torques tau [N·m].

    Args:
        P: the machine.
        x: state [q, q̇] in [rad], [rad/s], (6,).
        tau: motor torques in [N·m], (3,), held over the steps.
        loads: the load F_e in [N] at every half step, (2·substeps + 1,).
        h: step in [s].
        substeps: number of steps.
    """
    y = _advance(P, (x[0], x[1], x[2], x[3], x[4], x[5]), (tau[0], tau[1], tau[2]), loads, 0, h, substeps)
    return np.array(y)


@_compile
def _advance(P, y, t, loads, first, h, substeps):
    """:func:`advance` on tuples; the loads at every half step start at ``loads[first]``."""
    for k in range(substeps):
        at = first + 2 * k
        k1 = _derivative(P, y, t, loads[at])
        k2 = _derivative(P, _axpy(y, h / 2, k1), t, loads[at + 1])
        k3 = _derivative(P, _axpy(y, h / 2, k2), t, loads[at + 1])
        k4 = _derivative(P, _axpy(y, h, k3), t, loads[at + 2])
        y = _axpy(_axpy(_axpy(_axpy(y, h / 6, k1), h / 3, k2), h / 3, k3), h / 6, k4)
    return y


@_compile
def jacobian(P, q):
    """J (L̇_j = J·ω), (3, 3), at gait angles q in [rad], (3,); NaN rows where a lever cannot reach."""
    return np.array(_jacobian_at(P, q))


@_compile
def workspace_pd(P, q, qd, q_desired, qd_desired, kp, kd):
    """Workspace PD motor torques (p/2π)·J⁻ᵀ·(K_p·Δq + K_d·Δq̇) in [N·m], (3,) (:class:`hipsim.control.WorkspacePD`).

    Args:
        P: the controller's machine.
        q, qd: measured gait angles in [rad] and rates in [rad/s], (3,).
        q_desired, qd_desired: desired ones, (3,).
        kp: K_p per angle in [N·m/rad], (3,).
        kd: K_d per angle in [N·m·s/rad], (3,).
    """
    return np.array(
        _workspace_pd(
            P,
            (q[0], q[1], q[2]),
            (qd[0], qd[1], qd[2]),
            (q_desired[0], q_desired[1], q_desired[2]),
            (qd_desired[0], qd_desired[1], qd_desired[2]),
            (kp[0], kp[1], kp[2]),
            (kd[0], kd[1], kd[2]),
        )
    )


@_compile
def _workspace_pd(P, q, qd, q_desired, qd_desired, kp, kd):
    """:func:`workspace_pd` on tuples."""
    error = (
        kp[0] * (q_desired[0] - q[0]) + kd[0] * (qd_desired[0] - qd[0]),
        kp[1] * (q_desired[1] - q[1]) + kd[1] * (qd_desired[1] - qd[1]),
        kp[2] * (q_desired[2] - q[2]) + kd[2] * (qd_desired[2] - qd[2]),
    )
    moment = _signed(P, error)  # the moment acts on the platform, whose angles may be flipped
    J_inv_T = laws.inverse_transpose(_jacobian_at(P, q))
    return scale(matvec(J_inv_T, moment), travel_per_radian(P.lead))

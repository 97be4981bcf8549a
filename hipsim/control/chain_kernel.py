"""One platform of a machine (the drawing or per-chain) at one instant, compiled: what the servo loop needs of the controller's model.

The servo loop of a plant that is not the controller's model
(:mod:`hipsim.control.machine_loop`) asks the model, once per servo period,
for the controlled platform's attitude from the carriage encoders (its
forward kinematics), its rate, and the workspace PD's torques through its
Jacobian. These are the laws of :mod:`hipsim.analytic.stations` and
:mod:`hipsim.analytic.chain_kinematics` (chain ji: ``L_i = d_z − √(l_ji² −
d_x² − d_y²)`` with ``d = R·r⁰_ji + o_j − c_ji``; ``L̇ = J·ω``, J's rows
``(r × d)/d_z``) written for one sample in scalar code, because NumPy's
per-call overhead on 3-vectors is most of a servo period.

A platform is given by :func:`platform_arrays` as three arrays: its joints
r⁰_ji in platform axes (3, 3), o_j − c_ji (3, 3) and its lever lengths (3,),
all in [m]; on the drawing these are the drawing's, on a per-chain machine
platform j's own (``Parameters.chains``), so whatever ``[geometry]`` holds
reaches the loop through the same builder the stations use. That is the
seam: a ``[geometry]`` feature that moves a platform's joints or centre in
``Chains`` reaches the controller's model here, as it reaches the plants
through the per-chain URDF.

The intermediate chain's stack-up couples the two platforms (m_1's centre rides
Δz = ẑᵀ(R_2 − I)·e with m_2's attitude, :mod:`hipsim.analytic.stackup`): with
m_1 controlled the model needs m_2 too. :func:`model_arrays` gives the
controlled platform, m_2 and the seat e (zero unless m_1 is controlled on a
stacked model), and the ``model_*`` functions read the encoders through it:
m_1's attitude is its forward kinematics on the seen carriages L − Δz(q_2(L))·1,
its rate ω_1 = J_1⁻¹·(L̇ − 1·gᵀ·J_2⁻¹·L̇) (g = R_2·e × ẑ), and the PD's forces
J_1⁻ᵀ·M − J_2⁻ᵀ·g·(1ᵀ·J_1⁻ᵀ·M) (virtual work through the seat). With a zero seat
they are :func:`attitude`, :func:`rates` and :func:`workspace_pd`, call for call.
"""

from __future__ import annotations

import math

import numpy as np

from ..machine.parameters import Parameters
from ..physics import laws
from ..physics.transmission import travel_per_radian
from ..physics.vectors import cross, matvec, scale, transpose_times

__all__ = [
    "attitude",
    "carriages",
    "model_arrays",
    "model_attitude",
    "model_pd",
    "model_rates",
    "platform_arrays",
    "rates",
    "workspace_pd",
]

_compile = laws.jit

#: Newton's stop on the attitude step, in [rad]; and its most iterations.
_STEP_TOL = 1e-13
_MAX_ITER = 30
#: The stack-up's fixed point (m_2's attitude for m_1's): stop on a lift change below this in [m]; most steps.
_LIFT_TOL = 1e-15
_LIFT_STEPS = 60


def platform_arrays(params: Parameters, platform: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Platform ``platform`` (1 or 2) of ``params`` as the compiled functions take it: (r⁰ (3, 3), o − c (3, 3), l (3,), angle signs (3,))."""
    chains, j = params.chains, platform - 1
    return (
        np.ascontiguousarray(chains.platform_points[j]),
        np.ascontiguousarray(chains.centres[j] - chains.screw_points[j]),
        np.ascontiguousarray(chains.lever_lengths[j]),
        np.ascontiguousarray(params.angle_signs, dtype=float),
    )


@_compile
def _rows(points, offsets, levers, p):
    """Carriage readings L (3-tuple) and J's rows (L̇ = J·ω) at platform angles p; NaN where a lever cannot reach."""
    R = laws.rotation(
        (math.cos(p[0]), math.cos(p[1]), math.cos(p[2])), (math.sin(p[0]), math.sin(p[1]), math.sin(p[2]))
    )
    L = [0.0, 0.0, 0.0]
    J = []
    for i in range(3):
        r = matvec(R, (points[i, 0], points[i, 1], points[i, 2]))
        dx, dy = r[0] + offsets[i, 0], r[1] + offsets[i, 1]
        radicand = levers[i] ** 2 - (dx * dx + dy * dy)
        dz = math.sqrt(radicand) if radicand > 0 else math.nan
        L[i] = r[2] + offsets[i, 2] - dz
        J.append(scale(cross(r, (dx, dy, dz)), 1.0 / dz))
    return (L[0], L[1], L[2]), (J[0], J[1], J[2])


@_compile
def _t_columns(p):
    """T(p)'s columns: ω = T·ṗ (world frame)."""
    c = (math.cos(p[0]), math.cos(p[1]), math.cos(p[2]))
    s = (math.sin(p[0]), math.sin(p[1]), math.sin(p[2]))
    return (
        laws.t_times(c, s, (1.0, 0.0, 0.0)),
        laws.t_times(c, s, (0.0, 1.0, 0.0)),
        laws.t_times(c, s, (0.0, 0.0, 1.0)),
    )


@_compile
def _solve(rows, b):
    """x with A·x = b, A by its rows (closed form: x = (A⁻ᵀ)ᵀ·b)."""
    return transpose_times(laws.inverse_transpose(rows), b)


@_compile
def carriages(points, offsets, levers, signs, q):
    """The carriage readings [m], (3,), that put the platform at gait angles q [rad], (3,); NaN out of reach."""
    p = (q[0] * signs[0], q[1] * signs[1], q[2] * signs[2])
    L, _ = _rows(points, offsets, levers, p)
    return np.array(L)


@_compile
def attitude(points, offsets, levers, signs, L, guess):
    """The platform's gait angles [rad], (3,), at carriage readings L [m], (3,), by Newton from ``guess`` [rad], (3,).

    NaN when Newton does not converge in its iterations (out of reach, singular, or a step beyond 0.1 rad).
    """
    p = [guess[0] * signs[0], guess[1] * signs[1], guess[2] * signs[2]]
    for _ in range(_MAX_ITER):
        pt = (p[0], p[1], p[2])
        Lp, J = _rows(points, offsets, levers, pt)
        T = _t_columns(pt)
        # ∂L/∂p = J·T, by its rows.
        D = (
            (
                J[0][0] * T[0][0] + J[0][1] * T[0][1] + J[0][2] * T[0][2],
                J[0][0] * T[1][0] + J[0][1] * T[1][1] + J[0][2] * T[1][2],
                J[0][0] * T[2][0] + J[0][1] * T[2][1] + J[0][2] * T[2][2],
            ),
            (
                J[1][0] * T[0][0] + J[1][1] * T[0][1] + J[1][2] * T[0][2],
                J[1][0] * T[1][0] + J[1][1] * T[1][1] + J[1][2] * T[1][2],
                J[1][0] * T[2][0] + J[1][1] * T[2][1] + J[1][2] * T[2][2],
            ),
            (
                J[2][0] * T[0][0] + J[2][1] * T[0][1] + J[2][2] * T[0][2],
                J[2][0] * T[1][0] + J[2][1] * T[1][1] + J[2][2] * T[1][2],
                J[2][0] * T[2][0] + J[2][1] * T[2][1] + J[2][2] * T[2][2],
            ),
        )
        step = _solve(D, (Lp[0] - L[0], Lp[1] - L[1], Lp[2] - L[2]))
        size = max(abs(step[0]), abs(step[1]), abs(step[2]))
        if not size < 0.1:
            break
        p[0] -= step[0]
        p[1] -= step[1]
        p[2] -= step[2]
        if size < _STEP_TOL:
            return np.array([p[0] * signs[0], p[1] * signs[1], p[2] * signs[2]])
    return np.full(3, math.nan)


@_compile
def rates(points, offsets, levers, signs, q, Ld):
    """The gait angles' rates [rad/s], (3,), at gait angles q [rad] for carriage rates Ld [m/s]: q̇ = T⁻¹·J⁻¹·L̇."""
    p = (q[0] * signs[0], q[1] * signs[1], q[2] * signs[2])
    _, J = _rows(points, offsets, levers, p)
    omega = _solve(J, (Ld[0], Ld[1], Ld[2]))
    T = _t_columns(p)
    T_rows = ((T[0][0], T[1][0], T[2][0]), (T[0][1], T[1][1], T[2][1]), (T[0][2], T[1][2], T[2][2]))
    pd = _solve(T_rows, omega)
    return np.array([pd[0] * signs[0], pd[1] * signs[1], pd[2] * signs[2]])


@_compile
def workspace_pd(points, offsets, levers, signs, lead, q, qd, q_desired, qd_desired, kp, kd):
    """Workspace PD motor torques (p/2π)·J⁻ᵀ·(K_p·Δq + K_d·Δq̇) in [N·m], (3,), J the platform's at the measured q.

    The law of :func:`hipsim.analytic.kernel.workspace_pd` on this platform's own chains.

    Args:
        points, offsets, levers, signs: the platform (:func:`platform_arrays`).
        lead: screw lead in [m/turn].
        q, qd: measured gait angles [rad] and rates [rad/s], (3,).
        q_desired, qd_desired: desired ones, (3,).
        kp, kd: gains per angle in [N·m/rad] and [N·m·s/rad], (3,).
    """
    p = (q[0] * signs[0], q[1] * signs[1], q[2] * signs[2])
    _, J = _rows(points, offsets, levers, p)
    moment = (
        signs[0] * (kp[0] * (q_desired[0] - q[0]) + kd[0] * (qd_desired[0] - qd[0])),
        signs[1] * (kp[1] * (q_desired[1] - q[1]) + kd[1] * (qd_desired[1] - qd[1])),
        signs[2] * (kp[2] * (q_desired[2] - q[2]) + kd[2] * (qd_desired[2] - qd[2])),
    )
    return np.array(scale(matvec(laws.inverse_transpose(J), moment), travel_per_radian(lead)))


def model_arrays(params: Parameters, control: int) -> tuple[np.ndarray, ...]:
    """The controller's model as the ``model_*`` functions take it: the controlled platform's
    :func:`platform_arrays` (4), m_2's joints, offsets and levers (3), and the seat e [m] (3,): zero unless
    ``control`` is 1 on a model with a stack-up (m_2's own attitude never depends on the seat)."""
    seat = params.chains.spline_seat if control == 1 else np.zeros(3)
    # A copy, writable whichever platform: the parameters' seat is read-only and numba compiles a function once per
    # array type, so a read-only seat for m_1 compiled machine_kernel's loop and each model_* function twice.
    return (*platform_arrays(params, control), *platform_arrays(params, 2)[:3], np.array(seat, dtype=float))


@_compile
def _stacked(seat):
    return seat[0] != 0.0 or seat[1] != 0.0 or seat[2] != 0.0


@_compile
def _seat_point(seat, p2):
    """s = R_2·e [m] at m_2's platform angles p2: m_1's lift is s_z − e_z, and g = s × ẑ = (s_y, −s_x, 0)."""
    R = laws.rotation(
        (math.cos(p2[0]), math.cos(p2[1]), math.cos(p2[2])), (math.sin(p2[0]), math.sin(p2[1]), math.sin(p2[2]))
    )
    return matvec(R, (seat[0], seat[1], seat[2]))


@_compile
def _follower_of(points, offsets, levers, signs, points2, offsets2, levers2, seat, q):
    """m_2's platform angles p_2 and seat point s when m_1 is at gait angles q (the stack-up's fixed point).

    NaN when m_2 finds no attitude.
    """
    p = (q[0] * signs[0], q[1] * signs[1], q[2] * signs[2])
    seen, _ = _rows(points, offsets, levers, p)
    q2 = np.array([q[0], q[1], q[2]])
    lift = 0.0
    L = np.empty(3)
    p2 = (math.nan, math.nan, math.nan)
    s = (math.nan, math.nan, math.nan)
    for _ in range(_LIFT_STEPS):
        for i in range(3):
            L[i] = seen[i] + lift
        q2 = attitude(points2, offsets2, levers2, signs, L, q2)
        p2 = (q2[0] * signs[0], q2[1] * signs[1], q2[2] * signs[2])
        s = _seat_point(seat, p2)
        new = s[2] - seat[2]
        if not abs(new - lift) > _LIFT_TOL:  # settled, or NaN: stop either way
            break
        lift = new
    return p2, s


@_compile
def model_attitude(points, offsets, levers, signs, points2, offsets2, levers2, seat, L, guess):
    """The controlled platform's gait angles [rad], (3,), at carriage readings L [m] (:func:`attitude`; with a seat:
    m_2's first, then m_1's on the seen carriages L − Δz). NaN where the model finds none."""
    if not _stacked(seat):
        return attitude(points, offsets, levers, signs, L, guess)
    q2 = attitude(points2, offsets2, levers2, signs, L, guess)  # m_2 turns within a degree of m_1
    s = _seat_point(seat, (q2[0] * signs[0], q2[1] * signs[1], q2[2] * signs[2]))
    lift = s[2] - seat[2]
    return attitude(points, offsets, levers, signs, np.array([L[0] - lift, L[1] - lift, L[2] - lift]), guess)


@_compile
def model_rates(points, offsets, levers, signs, points2, offsets2, levers2, seat, q, Ld):
    """The controlled platform's gait rates [rad/s], (3,), at gait angles q [rad] for carriage rates Ld [m/s]
    (:func:`rates`; with a seat, on the seen rates L̇ − 1·gᵀ·J_2⁻¹·L̇)."""
    if not _stacked(seat):
        return rates(points, offsets, levers, signs, q, Ld)
    p2, s = _follower_of(points, offsets, levers, signs, points2, offsets2, levers2, seat, q)
    _, J2 = _rows(points2, offsets2, levers2, p2)
    omega2 = _solve(J2, (Ld[0], Ld[1], Ld[2]))
    zd = s[1] * omega2[0] - s[0] * omega2[1]  # g·ω_2
    return rates(points, offsets, levers, signs, q, np.array([Ld[0] - zd, Ld[1] - zd, Ld[2] - zd]))


@_compile
def model_pd(
    points, offsets, levers, signs, points2, offsets2, levers2, seat, lead, q, qd, q_desired, qd_desired, kp, kd
):
    """The workspace PD's motor torques [N·m], (3,), on the controller's model (:func:`workspace_pd`; with a seat the
    moment M reaches the carriages as J_1⁻ᵀ·M − J_2⁻ᵀ·g·(1ᵀ·J_1⁻ᵀ·M), g = s × ẑ)."""
    tau = workspace_pd(points, offsets, levers, signs, lead, q, qd, q_desired, qd_desired, kp, kd)
    if not _stacked(seat):
        return tau
    p2, s = _follower_of(points, offsets, levers, signs, points2, offsets2, levers2, seat, q)
    _, J2 = _rows(points2, offsets2, levers2, p2)
    h = matvec(laws.inverse_transpose(J2), (s[1], -s[0], 0.0))  # J_2⁻ᵀ·g
    total = tau[0] + tau[1] + tau[2]  # 1ᵀ·J_1⁻ᵀ·M, in motor torque
    return np.array([tau[0] - h[0] * total, tau[1] - h[1] * total, tau[2] - h[2] * total])

"""Each platform on its own: inverse and forward kinematics of platform m_1 or m_2 from the shared carriages.

On the drawing both platforms turn alike; on a per-chain machine
(:mod:`hipsim.machine.chains`, the parameter file's ``[geometry]`` table) each
platform's chains differ, so the same carriages turn the two platforms
differently. These functions work on either machine, vectorised over samples:

- :func:`carriages_for_platform`: the carriage readings that put platform j at
  an attitude (its inverse kinematics);
- :func:`platform_jacobian`: its Jacobian, L̇ = J_j·ω_j;
- :func:`platform_attitude`: the attitude of platform j for given carriages
  (its forward kinematics, along a log);
- :func:`platform_motion` and :func:`follower_motion`: the same with rates and
  accelerations, for the dynamics of a machine driven by one platform's motion.

Carriage readings L_i are what module i's encoder reads: on the drawing the
slider heights L_1i of platform 1 (so a log's ``L_11_mm, L_12_mm, L_13_mm``),
and L_2i = L_1i − (h_1 − h_2). Angles are gait angles [α, β, γ] (the parameter
file's angle signs are applied inside, as everywhere); angular velocities are
world-frame, ω = T(q)·q̇.

The intermediate chain's stack-up (``[geometry] spline_seat_mm``, :func:`hipsim.machine.chains.stackup_lift`)
lifts m_1's centre by Δz(q_2): m_1 then sees the carriages L − Δz·(1, 1, 1). Its forward kinematics solves m_2
first; its inverse kinematics is the fixed point L = L_1'(q_1) + Δz(q_2(L)) (a contraction by ~|e|/(50 mm) a step).
Its Jacobian :func:`platform_jacobian` is m_1's at m_2 held. The rates: :func:`follower_motion` of m_1 takes m_2's
motion from the carriages, then m_1's on the seen carriages L − Δz; :func:`platform_motion` of m_1 (control = 1)
solves the coupled rates of :func:`hipsim.analytic.stackup.follower_rates` (:func:`stacked_motion`).

On the drawing (no ``[geometry]``) the carriages are the drawing's L_1i for
either platform, bit for bit those of
:func:`hipsim.analytic.inverse_kinematics.slider_heights`.

Example:
    >>> import numpy as np, hipsim
    >>> from hipsim.analytic.stations import carriages_for_platform, platform_attitude
    >>> params = hipsim.load_parameters()
    >>> q = np.radians([[10.0, 3.0, -5.0]])
    >>> L = carriages_for_platform(params, q, platform=2)
    >>> bool(np.allclose(platform_attitude(params, L, platform=1, q0=q[0]), q, atol=1e-12))
    True
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from ..exceptions import ArgumentError, PoseError
from ..machine.chains import stackup_lift
from ..machine.parameters import Parameters
from ..physics.orientation import angular_velocity_map, angular_velocity_map_rate, rotation_matrix
from .chain_kinematics import chain_accelerations, chain_jacobian, chain_positions
from .forward_kinematics import forward_kinematics, solve_pose
from .inverse_kinematics import slider_heights, slider_jacobian
from .stackup import follower_rates, lift_motion

__all__ = [
    "attitude_sensitivities",
    "carriage_sensitivities",
    "carriages_for_platform",
    "follower_motion",
    "platform_attitude",
    "platform_jacobian",
    "platform_motion",
    "platform_rates",
    "stacked_carriages",
    "stacked_motion",
]

#: The stack-up's fixed point stops when the lift moves less than this in [m] (round-off of ~1 m readings).
LIFT_TOL = 1e-15
#: Fixed-point steps at most (each contracts by ~|e|/(50 mm): a 50 mm seat, the file's largest, needs ~20).
LIFT_STEPS = 60


_COUNT = 51  # the per-chain values (ChainGeometry.names()): 48 of the chains and centres, 3 of the stack-up


def _platform_index(platform: int) -> int:
    if platform not in (1, 2) or isinstance(platform, bool):
        raise ArgumentError("platform", platform, "1 (m_1) or 2 (m_2)")
    return platform - 1


def _angles(params: Parameters, q: np.ndarray, name: str = "q") -> np.ndarray:
    """Gait angles (N, 3) to platform angles (after the angle signs)."""
    q = np.asarray(q, dtype=float)
    if q.ndim != 2 or q.shape[1] != 3:
        raise ArgumentError(name, q.shape, "an array of shape (N, 3)")
    return q * params.angle_signs


def carriages_for_platform(params: Parameters, q: np.ndarray, platform: int) -> np.ndarray:
    """The carriage readings L_1, L_2, L_3 that give platform ``platform`` the attitude ``q``.

    Args:
        params: the machine (per-chain or the drawing).
        q: gait angles [α, β, γ] of that platform in [rad], (N, 3).
        platform: 1 for m_1, 2 for m_2.

    Returns:
        Carriage readings in [m], (N, 3); NaN where a lever cannot reach.
    """
    j = _platform_index(platform)
    p = _angles(params, q)
    if params.geometry is None:
        with np.errstate(invalid="ignore"):
            return slider_heights(params, p)[:, 0, :]
    L = chain_positions(params.chains, p, j)[0]
    return stacked_carriages(params, q, L) if j == 0 and params.chains.stacked else L


def stacked_carriages(
    params: Parameters,
    q1: np.ndarray,
    seen: np.ndarray,
    guess: np.ndarray | None = None,
    solve: Callable[[np.ndarray, np.ndarray], np.ndarray] | None = None,
) -> np.ndarray:
    """The carriages that give m_1 the attitude ``q1`` when its centre rides on m_2 (the stack-up's fixed point).

    m_1 needs the carriages ``seen`` below its lifted centre: L = seen + Δz(q_2(L))·(1, 1, 1), q_2(L) m_2's
    forward kinematics. Iterated from q_2 = ``guess`` (default q1) until the lift moves less than :data:`LIFT_TOL`.

    Args:
        params: the machine (with a stack-up).
        q1: m_1's gait angles in [rad], (N, 3).
        seen: m_1's own carriage readings at q1 with its centre at home (:func:`chain_positions`) in [m], (N, 3).
        guess: m_2's gait angles near the solution in [rad], (N, 3); None for q1.
        solve: (carriages (n, 3) [m], guess (n, 3) [rad]) → m_2's gait angles [rad]: its forward kinematics from
            close guesses; None for :func:`hipsim.analytic.forward_kinematics.solve_pose`.

    Returns:
        Carriage readings in [m], (N, 3); NaN rows where m_1 cannot reach.

    Raises:
        PoseError: m_2 cannot take the carriages, or the fixed point does not settle.
    """
    return _stacked_fixed_point(params, q1, seen, guess, solve)[0]


def _stacked_fixed_point(params, q1, seen, guess=None, solve=None) -> tuple[np.ndarray, np.ndarray]:
    """:func:`stacked_carriages`' carriages [m] and m_2's gait angles there [rad], each (N, 3)."""
    seen = np.asarray(seen, dtype=float)
    q2 = np.array(q1 if guess is None else guess, dtype=float)
    ok = np.all(np.isfinite(seen), axis=1)
    lift = np.zeros(len(seen))
    for _ in range(LIFT_STEPS):
        L = seen + lift[:, None]
        try:
            q2[ok] = solve(L[ok], q2[ok]) if solve is not None else solve_pose(params, L[ok], q2[ok], platform=2)
        except PoseError as error:  # name the sample among all, not among the reachable ones
            index = int(np.flatnonzero(ok)[error.index]) if 0 <= error.index < ok.sum() else error.index
            raise PoseError(error.reason, error.time, index, error.source) from None
        new = stackup_lift(params.chains.spline_seat, q2 * params.angle_signs)
        change = np.abs(new - lift)[ok]
        lift = new
        if not change.size or change.max() <= LIFT_TOL:
            return seen + lift[:, None], q2
    raise PoseError("the stack-up's fixed point does not settle (m_1's centre lift)", 0.0, 0)


def platform_jacobian(params: Parameters, q: np.ndarray, platform: int) -> np.ndarray:
    """J_j at attitude ``q`` of platform ``platform``: L̇ = J_j·ω_j (ω_j its world-frame angular velocity).

    Args:
        params: the machine.
        q: gait angles of that platform in [rad], (N, 3).
        platform: 1 or 2.

    Returns:
        J_j in [m/rad], (N, 3, 3); NaN rows where a lever cannot reach. With a stack-up, m_1's at m_2 held.
    """
    j = _platform_index(platform)
    p = _angles(params, q)
    if params.geometry is None:
        with np.errstate(invalid="ignore", divide="ignore"):
            return slider_jacobian(params, p)
    _, r, d = chain_positions(params.chains, p, j)
    return chain_jacobian(r, d)


def platform_attitude(
    params: Parameters,
    L: np.ndarray,
    platform: int,
    t: np.ndarray | None = None,
    q0: np.ndarray | None = None,
    source: str | None = None,
    guess: np.ndarray | None = None,
) -> np.ndarray:
    """The attitude of platform ``platform`` along a log of carriage readings (its forward kinematics).

    Each sample continues the previous one from the start pose ``q0``, as
    :func:`hipsim.analytic.forward_kinematics.forward_kinematics` does; the
    round trip through :func:`carriages_for_platform` is the identity to ~1e-13 rad.

    Args:
        params: the machine.
        L: carriage readings in [m], (N, 3).
        platform: 1 or 2.
        t: sample times in [s], (N,), for messages; None for the indices.
        q0: gait angles in [rad] near the first sample, (3,); None for home.
        source: the log's name, for messages.
        guess: gait angles in [rad] near each sample's solution, (N, 3) (e.g. the other platform's, or the
            desired motion): Newton then needs two or three steps a sample; None for the linearisation about q0.

    Returns:
        Gait angles [α, β, γ] of that platform in [rad], (N, 3).

    Raises:
        PoseError: naming the time of a sample out of reach, singular, or in another assembly mode.
    """
    _platform_index(platform)
    if platform == 1 and params.geometry is not None and params.chains.stacked:  # m_1 sees L − Δz(q_2(L))
        q2 = forward_kinematics(params, L, t=t, q0=q0, source=source, platform=2, guess=guess)
        L = np.asarray(L, dtype=float) - stackup_lift(params.chains.spline_seat, q2 * params.angle_signs)[:, None]
        guess = q2 if guess is None else guess
    return forward_kinematics(
        params, L, t=t, q0=q0, source=source, platform=None if params.geometry is None else platform, guess=guess
    )


def platform_motion(
    params: Parameters, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray, platform: int
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Carriage readings, velocities and accelerations that give platform ``platform`` the motion (q, q̇, q̈).

    Args:
        params: the machine.
        q, qd, qdd: gait angles in [rad], rates in [rad/s], accelerations in [rad/s²], each (N, 3).
        platform: 1 or 2.

    Returns:
        L in [m], L̇ in [m/s], L̈ in [m/s²], each (N, 3); NaN where out of reach.

    Raises:
        PoseError: m_1 with a stack-up, where the stacked machine is singular (:func:`stacked_motion`).
    """
    j = _platform_index(platform)
    if j == 0 and params.geometry is not None and params.chains.stacked:
        return stacked_motion(params, q, qd, qdd)[:3]
    p, omega, omega_dot = _world_motion(params, q, qd, qdd)
    L, r, d = chain_positions(params.chains, p, j)
    Ld = np.einsum("nij,nj->ni", chain_jacobian(r, d), omega)
    return L, Ld, chain_accelerations(r, d, omega, omega_dot)


def stacked_motion(
    params: Parameters, q1: np.ndarray, qd1: np.ndarray, qdd1: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """With a stack-up and m_1 controlled: the carriages' motion and m_2's for m_1's motion (q_1, q̇_1, q̈_1).

    The carriages from the fixed point of :func:`stacked_carriages` (m_2's attitude with them); the rates by
    implicit differentiation of L − Δz(q_2)·1 = L_1'(q_1), L = L_2(q_2)
    (:func:`hipsim.analytic.stackup.follower_rates`).

    Args:
        params: the machine, with a stack-up.
        q1, qd1, qdd1: m_1's gait angles [rad], rates [rad/s], accelerations [rad/s²], each (N, 3).

    Returns:
        L [m], L̇ [m/s], L̈ [m/s²], each (N, 3), and m_2's (q_2 [rad], q̇_2 [rad/s], q̈_2 [rad/s²]).

    Raises:
        PoseError: m_2 cannot take the carriages, or the stacked machine is singular.
    """
    p1, omega1, omega1_dot = _world_motion(params, q1, qd1, qdd1)
    seen, r1, d1 = chain_positions(params.chains, p1, 0)
    seen_d = np.einsum("nij,nj->ni", chain_jacobian(r1, d1), omega1)
    seen_dd = chain_accelerations(r1, d1, omega1, omega1_dot)
    L, q2 = _stacked_fixed_point(params, q1, seen)
    p2 = q2 * params.angle_signs
    _, r2, d2 = chain_positions(params.chains, p2, 1)
    try:
        omega2, omega2_dot = follower_rates(params.chains.spline_seat, p2, r2, d2, seen_d, seen_dd)
    except np.linalg.LinAlgError:
        raise PoseError("singular pose: the stacked machine's Jacobian J_2 − 1·gᵀ is singular", 0.0, 0) from None
    J2 = chain_jacobian(r2, d2)
    Ld = np.einsum("nij,nj->ni", J2, omega2)
    Ldd = chain_accelerations(r2, d2, omega2, omega2_dot)
    return L, Ld, Ldd, _gait_motion(params, p2, omega2, omega2_dot)


def _world_motion(params: Parameters, q, qd, qdd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Platform angles [rad], ω [rad/s] and ω̇ [rad/s²] (world frame, (N, 3) each) of gait angles and their rates."""
    p, pd, pdd = _angles(params, q), _angles(params, qd, "qd"), _angles(params, qdd, "qdd")
    T = angular_velocity_map(p)
    omega = np.einsum("nij,nj->ni", T, pd)
    omega_dot = np.einsum("nij,nj->ni", T, pdd) + np.einsum("nij,nj->ni", angular_velocity_map_rate(p, pd), pd)
    return p, omega, omega_dot


def _gait_motion(params: Parameters, p, omega, omega_dot) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Gait angles q [rad], q̇ = T⁻¹·ω [rad/s], q̈ = T⁻¹·(ω̇ − Ṫ·q̇) [rad/s²] of platform angles p and ω, ω̇."""
    signs = params.angle_signs
    T = angular_velocity_map(p)
    pd = np.linalg.solve(T, omega[..., None])[..., 0]
    pdd = np.linalg.solve(T, (omega_dot - np.einsum("nij,nj->ni", angular_velocity_map_rate(p, pd), pd))[..., None])[
        ..., 0
    ]
    return p * signs, pd * signs, pdd * signs


def follower_motion(
    params: Parameters,
    L: np.ndarray,
    Ld: np.ndarray,
    Ldd: np.ndarray,
    platform: int,
    t: np.ndarray | None = None,
    q0: np.ndarray | None = None,
    source: str | None = None,
    guess: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The motion of platform ``platform`` driven by given carriage motion: forward kinematics through its own Jacobian.

    q from :func:`platform_attitude`; ω = J⁻¹·L̇; ω̇ = J⁻¹·(L̈ − Φ(ω)), Φ the
    velocity terms of L̈; then q̇ = T⁻¹·ω and q̈ = T⁻¹·(ω̇ − Ṫ·q̇). With a stack-up, m_1's: m_2's motion
    first, then m_1's on the seen carriages L − Δz, L̇ − ż, L̈ − z̈ (:func:`hipsim.analytic.stackup.lift_motion`).

    Args:
        params: the machine.
        L, Ld, Ldd: carriage readings in [m], velocities in [m/s], accelerations in [m/s²], each (N, 3).
        platform: 1 or 2.
        t, q0, source, guess: as in :func:`platform_attitude`.

    Returns:
        Gait angles q in [rad], q̇ in [rad/s], q̈ in [rad/s²], each (N, 3).

    Raises:
        PoseError: as :func:`platform_attitude`, or where the Jacobian is singular.
    """
    j = _platform_index(platform)
    if j == 0 and params.geometry is not None and params.chains.stacked:
        q2, qd2, qdd2 = follower_motion(params, L, Ld, Ldd, 2, t=t, q0=q0, source=source, guess=guess)
        _, omega2, omega2_dot = _world_motion(params, q2, qd2, qdd2)
        z, zd, zdd, _ = lift_motion(params.chains.spline_seat, q2 * params.angle_signs, omega2, omega2_dot)
        flat = params.replace(geometry=params.geometry.replace(spline=np.zeros(3)))
        seen = (np.asarray(L) - z[:, None], np.asarray(Ld) - zd[:, None], np.asarray(Ldd) - zdd[:, None])
        return follower_motion(flat, *seen, 1, t=t, q0=q0, source=source, guess=q2 if guess is None else guess)
    q = platform_attitude(params, L, platform, t=t, q0=q0, source=source, guess=guess)
    return q, *platform_rates(params, q, Ld, Ldd, platform, source)


def platform_rates(
    params: Parameters, q: np.ndarray, Ld: np.ndarray, Ldd: np.ndarray, platform: int, source: str | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Platform ``platform``'s gait rates [rad/s] and accelerations [rad/s²], (N, 3) each, at its attitude q [rad]
    driven by carriage rates Ld [m/s] and accelerations Ldd [m/s²]: ω = J⁻¹·L̇, ω̇ = J⁻¹·(L̈ − Φ(ω)) through its own
    chains (with a stack-up, m_1's at m_2 held: give it the seen carriages' rates).

    Raises:
        PoseError: where its Jacobian is singular.
    """
    j = _platform_index(platform)
    p = _angles(params, q)
    _, r, d = chain_positions(params.chains, p, j)
    J = chain_jacobian(r, d)
    try:
        omega = np.linalg.solve(J, np.asarray(Ld, dtype=float)[..., None])[..., 0]
        phi = chain_accelerations(r, d, omega, np.zeros_like(omega))
        omega_dot = np.linalg.solve(J, (np.asarray(Ldd, dtype=float) - phi)[..., None])[..., 0]
    except np.linalg.LinAlgError:
        raise PoseError("singular pose: the Jacobian of the following platform is singular", 0.0, 0, source) from None
    return _gait_motion(params, p, omega, omega_dot)[1:]


def carriage_sensitivities(
    params: Parameters, q: np.ndarray, platform: int, q_other: np.ndarray | None = None
) -> np.ndarray:
    """∂L/∂θ: how the carriage readings that give platform ``platform`` the attitude ``q`` move with each geometry value θ.

    θ are the 51 deviations of :meth:`hipsim.machine.chains.ChainGeometry.names` (in [m], that order). With
    g_i = a_ji − c_ji and the lever vector d_i of :mod:`hipsim.analytic.chain_kinematics`,
    L_i = g_i,z − √(l_ji² − g_i,x² − g_i,y²), so ∂L_i/∂g_i = d_i/d_i,z and ∂L_i/∂l_ji = −l_ji/d_i,z:
    the U-joint offset moves L_i by −d_i,xy/d_i,z, the slider offset by −1, the platform joint offset
    (platform axes) by Rᵀd_i/d_i,z, the rotation centre by d_i/d_i,z. The stack-up's seat e moves m_1's three
    readings alike by ∂Δz/∂e = ẑᵀ(R_2 − I) at m_2's attitude. The other platform's values do not enter (through
    m_2's attitude under a stack-up they do, by a product of two deviations: left out).

    Args:
        params: the machine (per-chain or the drawing).
        q: gait angles of that platform in [rad], (N, 3).
        platform: 1 or 2.
        q_other: m_2's gait angles in [rad], (N, 3), for the stack-up's column of m_1; None for ``q``.

    Returns:
        ∂L/∂θ, dimensionless ([m/m]), (N, 3, 51); NaN where a lever cannot reach.
    """
    j = _platform_index(platform)
    p = _angles(params, q)
    chains = params.chains
    _, _, d = chain_positions(chains, p, j)
    with np.errstate(invalid="ignore", divide="ignore"):
        n = d / d[..., 2:3]  # ∂L_i/∂g_i, (N, leg, xyz)
    R = rotation_matrix(p)
    out = np.zeros((len(p), 3, _COUNT))
    legs = np.arange(3)
    # Offsets into the vector of ChainGeometry.names(): ujoint (12), slider (6), joint (18), lever (6), centre (6).
    chain = 3 * j + legs  # this platform's chains, in the file's row order
    for k in range(2):
        out[:, legs, 2 * chain + k] = -n[..., k]
    out[:, legs, 12 + chain] = -1.0
    joint = np.einsum("nik,nkm->nim", n, R)  # ∂L_i/∂δr = (∂L_i/∂g)·R
    for k in range(3):
        out[:, legs, 18 + 3 * chain + k] = joint[..., k]
    with np.errstate(invalid="ignore", divide="ignore"):
        out[:, legs, 36 + chain] = -chains.lever_lengths[j] / d[..., 2]
    out[:, :, 42 + 3 * j : 45 + 3 * j] = n
    if j == 0:
        p2 = p if q_other is None else _angles(params, q_other, "q_other")
        R2 = rotation_matrix(p2)
        out[:, :, 48:51] = (R2[:, 2, :] - np.array([0.0, 0.0, 1.0]))[:, None, :]
    return out


def attitude_sensitivities(
    params: Parameters, q: np.ndarray, platform: int, q_other: np.ndarray | None = None
) -> np.ndarray:
    """∂q/∂θ at fixed carriages: how platform ``platform``'s attitude moves with each geometry value θ.

    From L(q, θ) = L_measured: ∂q/∂θ = −(∂L/∂q)⁻¹·∂L/∂θ with ∂L/∂q = J·T (gait angles: the angle
    signs applied). What a kinematic calibration's Gauss–Newton and a tolerance study need.

    Args:
        params: the machine.
        q: gait angles of that platform in [rad] (its attitude for the carriages in question), (N, 3).
        platform: 1 or 2.
        q_other: m_2's gait angles for m_1's stack-up column (:func:`carriage_sensitivities`).

    Returns:
        ∂q/∂θ in [rad/m], (N, 3, 51), in the order of :meth:`hipsim.machine.chains.ChainGeometry.names`.
    """
    p = _angles(params, q)
    D = np.einsum("nij,njk->nik", platform_jacobian(params, q, platform), angular_velocity_map(p))
    D *= params.angle_signs  # ∂L/∂(gait angles) = ∂L/∂p·diag(signs)
    return -np.linalg.solve(D, carriage_sensitivities(params, q, platform, q_other))

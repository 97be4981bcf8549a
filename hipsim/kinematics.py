"""Analytic kinematics of the 2(3PUS+S) machine (spec §3), vectorised over samples.

Both platforms turn about fixed centres o_j = h_j·ẑ with the same orientation
R = Rz(γ)·Ry(β)·Rx(α); leg i of platform j joins the slider's universal joint
b_ji = c_i + L_ji·ẑ to the platform joint a_ji = o_j + R·r⁰_i through a lever
of length l. Because a_1i − b_1i = a_2i − b_2i, the two platforms share their
lever directions, their Jacobian and their slider motion up to the constant
offset h_1 − h_2, and every per-leg array below is computed once, shape
(N, 3, 3) = (sample, leg i, xyz).

Every function is a pure function of arrays; :func:`kinematics` bundles them
along a trajectory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .exceptions import PoseError
from .parameters import Parameters
from .trajectories import Trajectory

__all__ = [
    "Kinematics",
    "angular_velocity_map",
    "angular_velocity_map_rate",
    "inverse_condition_number",
    "kinematics",
    "lever_frames",
    "lever_jacobians",
    "lever_rotation",
    "rotation_matrix",
    "slider_heights",
]

#: Inverse condition number of J below which a pose counts as singular.
SINGULAR_COND_INV = 1e-6


def rotation_matrix(q: np.ndarray) -> np.ndarray:
    """R = Rz(γ)·Ry(β)·Rx(α).

    Args:
        q: orientations [α, β, γ] in [rad], shape (N, 3).

    Returns:
        Rotation matrices, shape (N, 3, 3).
    """
    ca, cb, cg = np.cos(q).T
    sa, sb, sg = np.sin(q).T
    R = np.empty((q.shape[0], 3, 3))
    R[:, 0, 0] = cb * cg
    R[:, 0, 1] = cg * sb * sa - sg * ca
    R[:, 0, 2] = cg * sb * ca + sg * sa
    R[:, 1, 0] = cb * sg
    R[:, 1, 1] = sg * sb * sa + cg * ca
    R[:, 1, 2] = sg * sb * ca - cg * sa
    R[:, 2, 0] = -sb
    R[:, 2, 1] = cb * sa
    R[:, 2, 2] = cb * ca
    return R


def angular_velocity_map(q: np.ndarray) -> np.ndarray:
    """T(q) with ω = T(q)·q̇ (world frame), shape (N, 3, 3); q in [rad], shape (N, 3)."""
    _, b, g = q.T
    T = np.zeros((q.shape[0], 3, 3))
    T[:, 0, 0] = np.cos(b) * np.cos(g)
    T[:, 0, 1] = -np.sin(g)
    T[:, 1, 0] = np.cos(b) * np.sin(g)
    T[:, 1, 1] = np.cos(g)
    T[:, 2, 0] = -np.sin(b)
    T[:, 2, 2] = 1.0
    return T


def angular_velocity_map_rate(q: np.ndarray, qd: np.ndarray) -> np.ndarray:
    """Ṫ(q, q̇), so that ω̇ = T·q̈ + Ṫ·q̇; q in [rad], qd in [rad/s], shapes (N, 3)."""
    _, b, g = q.T
    _, bd, gd = qd.T
    cb, sb, cg, sg = np.cos(b), np.sin(b), np.cos(g), np.sin(g)
    Td = np.zeros((q.shape[0], 3, 3))
    Td[:, 0, 0] = -sb * cg * bd - cb * sg * gd
    Td[:, 0, 1] = -cg * gd
    Td[:, 1, 0] = -sb * sg * bd + cb * cg * gd
    Td[:, 1, 1] = -sg * gd
    Td[:, 2, 0] = -cb * bd
    return Td


def _platform_vectors(params: Parameters, R: np.ndarray) -> np.ndarray:
    """r_i = R·r⁰_i in [m], shape (N, 3, 3)."""
    return np.einsum("nab,ib->nia", R, params.platform_points)


def _lever_vectors(params: Parameters, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lever vectors a_1i − b_1i and the radicand l² − (horizontal gap)², from r_i."""
    gap = r[..., :2] - params.screw_points[:, :2]  # a_ji − c_i, horizontal part
    radicand = params.lever_length**2 - np.sum(gap**2, axis=-1)
    d = np.empty_like(r)
    d[..., :2] = gap
    d[..., 2] = np.sqrt(np.maximum(radicand, 0.0))
    return d, radicand


def slider_heights(params: Parameters, q: np.ndarray) -> np.ndarray:
    """L_ji, the slider heights in [m], shape (N, 2, 3), from orientations q in [rad], shape (N, 3).

    Poses out of reach give NaN; :func:`kinematics` turns them into errors.
    """
    r = _platform_vectors(params, rotation_matrix(q))
    d, radicand = _lever_vectors(params, r)
    L1 = params.heights[0] + r[..., 2] - d[..., 2]
    L1 = np.where(radicand > 0, L1, np.nan)
    return L1[:, None, :] + (params.heights - params.heights[0])[None, :, None]


def inverse_condition_number(J: np.ndarray) -> np.ndarray:
    """σ_min/σ_max of 3x3 matrices, shape (..., 3, 3) → (...); NaN where J is NaN.

    The eigenvalues of the symmetric JᵀJ in closed form (the trigonometric
    solution of its characteristic cubic): LAPACK's batched SVD costs a
    hundred times more on 3x3 matrices.
    """
    A = np.swapaxes(J, -1, -2) @ J
    trace = np.trace(A, axis1=-2, axis2=-1)
    mean = trace / 3.0
    off = A[..., 0, 1] ** 2 + A[..., 0, 2] ** 2 + A[..., 1, 2] ** 2
    spread = np.sqrt(((A[..., 0, 0] - mean) ** 2 + (A[..., 1, 1] - mean) ** 2 + (A[..., 2, 2] - mean) ** 2 + 2.0 * off) / 6.0)
    with np.errstate(invalid="ignore", divide="ignore"):
        B = (A - mean[..., None, None] * np.eye(3)) / spread[..., None, None]
        half_det = np.clip(np.linalg.det(B) / 2.0, -1.0, 1.0)
        phi = np.arccos(half_det) / 3.0
        largest = mean + 2.0 * spread * np.cos(phi)
        smallest = mean + 2.0 * spread * np.cos(phi + 2.0 * np.pi / 3.0)
        ratio = np.sqrt(np.maximum(smallest, 0.0) / largest)
    # An isotropic J (spread 0) has all singular values equal.
    return np.where(spread > 1e-300, ratio, np.where(np.isnan(trace), np.nan, 1.0))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    # np.cross is several times slower than this on small trailing axes.
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("...k,...k->...", a, b)


@dataclass(frozen=True, eq=False)
class Kinematics:
    """The machine's motion along a trajectory, in SI units.

    Shapes: N samples; j = platform (2); i = leg/linear module (3).

    Attributes:
        t: sample times in [s], (N,).
        q, qd, qdd: platform orientation [α, β, γ] in [rad] and its derivatives
            (after the parameter file's angle signs), (N, 3).
        R: platform rotation, (N, 3, 3).
        omega, omega_dot: platform angular velocity in [rad/s] and acceleration
            in [rad/s²], world frame, (N, 3).
        r: platform joint vectors r_i = R·r⁰_i in [m], (N, 3, 3).
        a: platform joints a_ji in [m], (N, 2, 3, 3).
        b: universal joint centres b_ji in [m], (N, 2, 3, 3).
        e: lever unit vectors e_ji (same for both platforms), (N, 3, 3).
        L, Ld, Ldd: slider heights in [m], velocities in [m/s], accelerations
            in [m/s²], (N, 2, 3).
        J: the Jacobian L̇_j = J·ω (same for both platforms), (N, 3, 3).
        cond_inv: inverse condition number of J, 0 singular, 1 isotropic, (N,).
        omega_l, omega_l_dot: lever angular velocity in [rad/s] and acceleration
            in [rad/s²] without spin about the lever axis (spec §3), (N, 3, 3).
        v_l, a_l: lever centre velocity in [m/s] and acceleration in [m/s²], (N, 2, 3, 3).
        flagged: samples out of reach or singular, kept only when asked, (N,).
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    R: np.ndarray
    omega: np.ndarray
    omega_dot: np.ndarray
    r: np.ndarray
    a: np.ndarray
    b: np.ndarray
    e: np.ndarray
    L: np.ndarray
    Ld: np.ndarray
    Ldd: np.ndarray
    J: np.ndarray
    cond_inv: np.ndarray
    omega_l: np.ndarray
    omega_l_dot: np.ndarray
    v_l: np.ndarray
    a_l: np.ndarray
    flagged: np.ndarray

    def __len__(self) -> int:
        return self.t.size


def kinematics(params: Parameters, trajectory: Trajectory, on_error: str = "raise") -> Kinematics:
    """Slider motion, Jacobians and lever motion along a trajectory (spec §3).

    Args:
        params: the machine.
        trajectory: platform orientation (gait angles) and derivatives.
        on_error: ``"raise"`` to stop at the first pose out of reach or singular
            (inverse condition number below 1e-6), ``"flag"`` to carry on and
            mark those samples in ``flagged`` (their values are NaN where out of reach).

    Returns:
        The kinematics along the trajectory.

    Raises:
        PoseError: naming the time of the first pose out of reach or singular.
    """
    if on_error not in ("raise", "flag"):
        raise ValueError(f"on_error must be 'raise' or 'flag', got {on_error!r}")
    with np.errstate(divide="ignore", invalid="ignore"):  # poses out of reach give NaN and are flagged
        return _kinematics(params, trajectory, on_error)


def _kinematics(params: Parameters, trajectory: Trajectory, on_error: str) -> Kinematics:
    signs = params.angle_signs
    q, qd, qdd = trajectory.q * signs, trajectory.qd * signs, trajectory.qdd * signs
    R = rotation_matrix(q)
    T = angular_velocity_map(q)
    omega = np.einsum("nab,nb->na", T, qd)
    omega_dot = np.einsum("nab,nb->na", T, qdd) + np.einsum("nab,nb->na", angular_velocity_map_rate(q, qd), qd)

    l = params.lever_length
    r = _platform_vectors(params, R)
    d, radicand = _lever_vectors(params, r)
    out_of_reach = np.any(radicand <= 0, axis=1)
    e = d / l
    ez = e[..., 2]

    # Velocity: L̇_i = (r_i × e_i)·ω / e_i,z; row i of J is (r_i × e_i)ᵀ / e_i,z.
    J = _cross(r, e) / ez[..., None]
    w = omega[:, None, :]
    Ld = _dot(J, w)
    a_dot = _cross(w, r)
    d_dot = a_dot.copy()
    d_dot[..., 2] -= Ld
    omega_l = _cross(e, d_dot) / l

    # Acceleration: L̈_i = [e_i·(ω̇ × r_i + ω × (ω × r_i)) + l·|ω_l|²] / e_i,z.
    a_ddot = _cross(omega_dot[:, None, :], r) + _cross(w, a_dot)
    Ldd = (_dot(e, a_ddot) + l * _dot(omega_l, omega_l)) / ez
    d_ddot = a_ddot.copy()
    d_ddot[..., 2] -= Ldd
    omega_l_dot = _cross(e, d_ddot) / l

    cond_inv = inverse_condition_number(np.where(out_of_reach[:, None, None], np.nan, J))
    singular = ~(cond_inv >= SINGULAR_COND_INV)
    flagged = out_of_reach | singular
    if on_error == "raise" and np.any(flagged):
        k = int(np.argmax(flagged))
        if out_of_reach[k]:
            leg = int(np.argmax(radicand[k] <= 0)) + 1
            message = f"pose out of reach: lever {leg} cannot span the gap from its screw to its platform joint"
        else:
            message = f"singular pose: inverse condition number of J is {cond_inv[k]:.3g}"
        raise PoseError(message, float(trajectory.t[k]), k, source=trajectory.name)

    dh = (params.heights - params.heights[0])[None, :, None]
    L1 = params.heights[0] + r[..., 2] - d[..., 2]
    L1 = np.where(out_of_reach[:, None], np.nan, L1)
    L = L1[:, None, :] + dh
    Ld2 = np.repeat(Ld[:, None, :], 2, axis=1)
    Ldd2 = np.repeat(Ldd[:, None, :], 2, axis=1)

    o = params.heights[None, :, None, None] * np.array([0.0, 0.0, 1.0])
    a = o + r[:, None]
    b = params.screw_points[None, None] + L[..., None] * np.array([0.0, 0.0, 1.0])
    # The lever centre is the midpoint of a and b, so its motion is the mean of theirs.
    b_dot = np.zeros_like(a_dot)
    b_dot[..., 2] = Ld
    b_ddot = np.zeros_like(a_ddot)
    b_ddot[..., 2] = Ldd
    v_l = np.repeat((0.5 * (a_dot + b_dot))[:, None], 2, axis=1)
    a_l = np.repeat((0.5 * (a_ddot + b_ddot))[:, None], 2, axis=1)

    return Kinematics(
        t=trajectory.t, q=q, qd=qd, qdd=qdd, R=R, omega=omega, omega_dot=omega_dot,
        r=r, a=a, b=b, e=e, L=L, Ld=Ld2, Ldd=Ldd2, J=J, cond_inv=cond_inv,
        omega_l=omega_l, omega_l_dot=omega_l_dot, v_l=v_l, a_l=a_l, flagged=flagged,
    )


def lever_jacobians(kin: Kinematics) -> tuple[np.ndarray, np.ndarray]:
    """J_v,i and J_ω,i of spec §4.2: v_l,i = J_v,i·ω and ω_l,i = J_ω,i·ω.

    Returns:
        J_v, J_omega, each of shape (N, 3, 3, 3) = (sample, leg, row, column);
        the same for both platforms. Lever length is read from the kinematics
        (|a − b|), so no parameters are needed.
    """
    n = len(kin)
    l = np.linalg.norm(kin.a[:, 0] - kin.b[:, 0], axis=-1)[..., None, None]
    r_hat = _skew(kin.r)
    # ȧ = ω × r = −[r]× ω;  ḃ = ẑ·(J_i ω).
    z_J = np.zeros((n, 3, 3, 3))
    z_J[:, :, 2, :] = kin.J
    J_v = 0.5 * (-r_hat + z_J)
    J_omega = _skew(kin.e) @ (-r_hat - z_J) / l
    return J_v, J_omega


def _skew(v: np.ndarray) -> np.ndarray:
    """[v]×, shape (..., 3, 3), from v of shape (..., 3)."""
    out = np.zeros(v.shape + (3,))
    out[..., 0, 1], out[..., 0, 2] = -v[..., 2], v[..., 1]
    out[..., 1, 0], out[..., 1, 2] = v[..., 2], -v[..., 0]
    out[..., 2, 0], out[..., 2, 1] = -v[..., 1], v[..., 0]
    return out


def lever_frames(params: Parameters, kin: Kinematics) -> np.ndarray:
    """Lever body frames R_l of spec §7.1 (z along e, x along u2 = e × u1/|e × u1|).

    Returns:
        Rotation matrices, shape (N, 3, 3, 3) = (sample, leg, 3, 3), columns the
        lever's x, y, z axes in world coordinates; the same for both platforms.
    """
    u1 = params.ujoint_axes[None]
    x = _cross(kin.e, u1)
    x /= np.linalg.norm(x, axis=-1, keepdims=True)
    y = _cross(kin.e, x)
    return np.stack([x, y, kin.e], axis=-1)


def lever_rotation(params: Parameters, kin: Kinematics, spin: bool) -> tuple[np.ndarray, np.ndarray]:
    """Lever angular velocity and acceleration, with or without the universal joint's spin.

    The analytic model of spec §3 gives the lever no spin about its axis
    (ω_l ⊥ e). A real universal joint constrains ω_l to span{u1, u2}, which adds
    a spin s·e with s = (u1·e)(ω_⊥·u1)/(1 − (u1·e)²).

    Args:
        params: the machine (for the universal joint axes u1).
        kin: the kinematics.
        spin: True for the universal joint's lever motion, False for the spec's.

    Returns:
        ω_l in [rad/s] and ω̇_l in [rad/s²], each (N, 3, 3).
    """
    if not spin:
        return kin.omega_l, kin.omega_l_dot
    u1 = params.ujoint_axes[None]
    e, w_perp, w_perp_dot = kin.e, kin.omega_l, kin.omega_l_dot
    c = _dot(u1, e)
    d = 1.0 - c**2
    w = _dot(w_perp, u1)
    s = c * w / d
    e_dot = _cross(w_perp, e)
    c_dot = _dot(u1, e_dot)
    s_dot = (c_dot * w + c * _dot(w_perp_dot, u1)) / d + 2.0 * c**2 * c_dot * w / d**2
    omega_l = w_perp + s[..., None] * e
    omega_l_dot = w_perp_dot + s_dot[..., None] * e + s[..., None] * e_dot
    return omega_l, omega_l_dot


def spin_transpose(params: Parameters, kin: Kinematics, moment: np.ndarray) -> np.ndarray:
    """Maps a lever moment through the spin: J_Ωᵀ τ = J_ωᵀ (τ + (c/d)(e·τ) u1).

    Args:
        moment: moments on the levers in [N·m], (N, 3, 3).

    Returns:
        The equivalent moment to map with the spin-free J_ωᵀ, (N, 3, 3).
    """
    u1 = params.ujoint_axes[None]
    c = _dot(u1, kin.e)
    return moment + (c / (1.0 - c**2) * _dot(kin.e, moment))[..., None] * u1

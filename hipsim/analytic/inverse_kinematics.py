"""Analytic kinematics of the 2(3PUS+S) machine (spec §3), vectorised over samples.

Both platforms turn about fixed centres o_j = h_j·ẑ with the same orientation
R = Rz(γ)·Ry(β)·Rx(α); leg i of platform j joins the slider's universal joint
b_ji = c_i + L_ji·ẑ to the platform joint a_ji = o_j + R·r⁰_i through a lever
of length l. Because a_1i − b_1i = a_2i − b_2i, the two platforms share their
lever directions, their Jacobian and their slider motion up to the constant
offset h_1 − h_2, so every per-leg quantity is computed once.

Array layout. The public arrays (:class:`Kinematics`, the functions' results)
put the sample first and xyz last: a vector per leg is (N, 3, 3) = (sample,
leg i, xyz). The computations inside put the components first and the sample
last — the same vector is (3, 3, N) = (xyz, leg i, sample), a vector per
sample (3, N), a scalar per leg (3, N) — so that ``v[2]`` is the z component of
every leg at every sample and each NumPy operation runs over one contiguous
block instead of over many 3-element rows (three to twenty times faster here).
The two layouts are each other's ``.T``, a view, so converting costs nothing:
the fields of :class:`Kinematics` are views of the arrays computed inside.
The helpers of :mod:`hipsim.physics.vectors` work component by component, so a
vector per sample (components of shape (N,)) broadcasts against a vector per
leg (components (3, N)) and a constant per leg (components (3, 1)); whole
arrays do not (write ``omega[:, None]`` to add a vector per sample to one per
leg). A matrix whose rows belong to the legs, like J with rows j_i, is stored
as the vector per leg j_i, so L̇_i = j_i·ω is ``dot(J, omega)``. The rotation
maps and the lever's spin are the laws of :mod:`hipsim.physics.laws`, which
the compiled kernel calls too.

Every function is a pure function of arrays; :func:`kinematics` bundles them
along a trajectory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..exceptions import ArgumentError, PoseError
from ..machine.parameters import Parameters
from ..motion.trajectories import Trajectory
from ..physics import laws
from ..physics.orientation import (  # the orientation laws, re-exported here as part of the kinematics
    angular_velocity_map,
    angular_velocity_map_rate,
    inverse_condition_number,
    inverse_condition_number_components,
    rotation_matrix,
    rotation_matrix_components,
)
from ..physics.vectors import cross_array, dot, per_leg, stack

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
    "singularity_crossings",
    "slider_jacobian",
    "solve_transpose",
]

#: Inverse condition number of J below which a pose counts as singular.
SINGULAR_COND_INV = 1e-6


# --- Orientation ----------------------------------------------------------------------


# --- Position level --------------------------------------------------------------------


def _platform_vectors(params: Parameters, R: np.ndarray) -> np.ndarray:
    """r_i = R·r⁰_i in [m], (xyz, leg, N), from R components-first (3, 3, N)."""
    # einsum, not a matrix product: OpenBLAS would run this 3x3 contraction on
    # several threads from about 3·10⁴ samples on, and its waiting threads slow
    # everything else on a busy machine.
    return np.einsum("im,kmn->kin", params.platform_points, R)


def _lever_vectors(params: Parameters, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The lever vectors d_i = a_1i − b_1i (xyz, leg, N) and the radicands l² − |horizontal gap|² (leg, N)."""
    c = per_leg(params.screw_points)
    d = np.empty_like(r)
    d[:2] = r[:2] - c[:2]  # a_ji − c_i, horizontal part
    radicand = params.lever_length**2 - (d[0] ** 2 + d[1] ** 2)
    d[2] = np.sqrt(np.maximum(radicand, 0.0))  # the lever below its platform joint
    return d, radicand


def slider_heights(params: Parameters, q: np.ndarray) -> np.ndarray:
    """L_ji, the slider heights in [m], shape (N, 2, 3), from orientations q in [rad], shape (N, 3).

    Poses out of reach give NaN; :func:`kinematics` turns them into errors.
    The drawing only: a per-chain machine is refused (:mod:`hipsim.analytic.stations` serves it).
    """
    params.require_drawing("the drawing's inverse kinematics")
    r = _platform_vectors(params, rotation_matrix_components(np.cos(q.T), np.sin(q.T)))
    d, radicand = _lever_vectors(params, r)
    L1 = params.heights[0] + r[2] - d[2]
    L1 = np.where(radicand > 0, L1, np.nan)
    return (L1[:, None, :] + (params.heights - params.heights[0])[:, None]).T


def slider_jacobian(params: Parameters, q: np.ndarray) -> np.ndarray:
    """J(q) from positions alone (L̇_j = J·ω), without the rest of :func:`kinematics`.

    For the servo loop and workspace grids, where only J is needed.

    Args:
        params: the machine.
        q: platform orientations [α, β, γ] in [rad] (after angle signs), shape (N, 3).

    Returns:
        J, shape (N, 3, 3); NaN rows where a lever cannot reach.
    """
    params.require_drawing("the drawing's Jacobian")
    r = _platform_vectors(params, rotation_matrix_components(np.cos(q.T), np.sin(q.T)))
    d, radicand = _lever_vectors(params, r)
    with np.errstate(divide="ignore", invalid="ignore"):
        J = cross_array(r, d) / d[2]  # rows (r_i × d_i)/d_i,z: the lever length cancels
    return np.where(radicand > 0, J, np.nan).T


# --- The Jacobian's conditioning and inverse --------------------------------------------


def _sign_changes(det: np.ndarray, periodic: bool) -> np.ndarray:
    """Samples whose det J has the other sign than the previous sample within reach, (N,) bool.

    Within reach every lever points up (e_i,z > 0), so det J = det J_b / Π e_i,z
    changes sign only where det J_b does: at the singularity of spec §3 where
    the lever projections meet at the platform centre.
    """
    sign = np.sign(det)
    kept = np.flatnonzero(np.isfinite(det) & (sign != 0))  # an exact zero is caught by cond_inv
    crossed = np.zeros(det.shape, dtype=bool)
    crossed[kept[1:][sign[kept[1:]] != sign[kept[:-1]]]] = True
    if periodic and kept.size > 1 and sign[kept[0]] != sign[kept[-1]]:
        crossed[kept[0]] = True
    return crossed


def singularity_crossings(J: np.ndarray, periodic: bool = False) -> int:
    """How often a sampled motion passes *through* a singularity: the sign changes of det J.

    Args:
        J: Jacobians along the motion, shape (N, 3, 3); NaN (out of reach) samples are skipped.
        periodic: also compare the last sample with the first.
    """
    with np.errstate(invalid="ignore"):  # NaN Jacobians (out of reach) give NaN determinants, skipped
        det = np.linalg.det(J) if len(J) else np.zeros(0)
    return int(np.count_nonzero(_sign_changes(det, periodic)))


def solve_transpose(J: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """y = J⁻ᵀ·Q for 3x3 matrices J (N, 3, 3) and right-hand sides Q (N, 3, K)."""
    rows = laws.inverse_transpose(np.moveaxis(J, 0, -1))  # J's rows j_i, components-first (xyz, N)
    Q = np.moveaxis(Q, 0, -1)  # (xyz, column, N)
    return np.moveaxis(np.array([dot(row, Q) for row in rows]), -1, 0)  # y_ic = (row i of J⁻ᵀ)·Q_c


@dataclass(frozen=True, eq=False)
class Kinematics:
    """The machine's motion along a trajectory, in SI units.

    Shapes: N samples; j = platform (2); i = leg/linear module (3).

    The arrays are views of the components-first arrays computed inside (see
    the module docstring), so they need not be C-contiguous; the per-platform
    Ld, Ldd, v_l, a_l are read-only views that repeat platform 1's values.

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
        flagged: samples out of reach, singular, or reached through a singularity
            since the previous sample; kept only when asked, (N,).
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
        raise ArgumentError("on_error", on_error, "'raise' or 'flag'")
    params.require_drawing("the drawing's kinematics")
    with np.errstate(divide="ignore", invalid="ignore"):  # poses out of reach give NaN and are flagged
        return _kinematics(params, trajectory, on_error)


def _kinematics(params: Parameters, trajectory: Trajectory, on_error: str) -> Kinematics:
    # Components first throughout (module docstring): vectors per sample (3, N), per leg (3, 3, N).
    # Temporaries are updated in place where that reads as well: at 10⁴ samples
    # fresh memory costs more than the arithmetic.
    signs = params.angle_signs
    q, qd, qdd = (trajectory.q * signs).T, (trajectory.qd * signs).T, (trajectory.qdd * signs).T
    c, s = np.cos(q), np.sin(q)
    R = rotation_matrix_components(c, s)
    omega = stack(laws.t_times(c, s, qd))
    omega_dot = stack(laws.t_times(c, s, qdd))
    omega_dot += laws.t_dot_times(c, s, qd, qd)

    # Position: the lever vectors d_i = a_1i − b_1i, so L_1i = a_1i,z − d_i,z, and e_i = d_i/l.
    l = params.lever_length
    r = _platform_vectors(params, R)
    d, radicand = _lever_vectors(params, r)
    out_of_reach = np.any(radicand <= 0, axis=0)
    L1 = np.where(out_of_reach, np.nan, params.heights[0] + r[2] - d[2])
    e = d / l
    del d  # only e is needed from here on: free the memory early

    # Velocity: L̇_i = (r_i × e_i)·ω / e_i,z; row i of J is (r_i × e_i)ᵀ / e_i,z.
    J = cross_array(r, e)
    J /= e[2]
    Ld = dot(J, omega)
    a_dot = cross_array(omega, r)
    omega_l = cross_array(e, (a_dot[0], a_dot[1], a_dot[2] - Ld))  # e × (ȧ − ḃ)/l with ḃ = L̇·ẑ
    omega_l /= l
    # The lever centre is the midpoint of a and b, so its motion is the mean of theirs.
    v_l = 0.5 * a_dot
    v_l[2] += 0.5 * Ld

    # Acceleration: L̈_i = [e_i·(ω̇ × r_i + ω × (ω × r_i)) + l·|ω_l|²] / e_i,z.
    a_ddot = cross_array(omega_dot, r)
    a_ddot += cross_array(omega, a_dot)
    del a_dot  # likewise
    Ldd = (dot(e, a_ddot) + l * dot(omega_l, omega_l)) / e[2]
    omega_l_dot = cross_array(e, (a_ddot[0], a_ddot[1], a_ddot[2] - Ldd))  # e × (ä − b̈)/l
    omega_l_dot /= l
    a_l = a_ddot  # becomes (ä + b̈)/2 in place
    a_l *= 0.5
    a_l[2] += 0.5 * Ldd

    reachable_J = np.where(out_of_reach, np.nan, J)
    cond_inv = inverse_condition_number_components(reachable_J)
    singular = ~(cond_inv >= SINGULAR_COND_INV)
    # A motion can also pass through a singularity between two samples without
    # coming close to it at either: det J then changes sign.
    crossed = _sign_changes(
        dot(reachable_J[:, 0], cross_array(reachable_J[:, 1], reachable_J[:, 2])), trajectory.periodic
    )
    flagged = out_of_reach | singular | crossed
    if on_error == "raise" and np.any(flagged):
        k = int(np.argmax(flagged))
        if out_of_reach[k]:
            leg = int(np.argmax(radicand[:, k] <= 0)) + 1
            message = f"pose out of reach: lever {leg} cannot span the gap from its screw to its platform joint"
        elif singular[k]:
            message = f"singular pose: inverse condition number of J is {cond_inv[k]:.3g}"
        else:
            message = "the motion passes through a singular pose since the previous sample (det J changes sign)"
        raise PoseError(message, float(trajectory.t[k]), k, source=trajectory.name)

    # Both platforms, inside as (xyz, leg, platform, N) or (leg, platform, N).
    z = np.array([0.0, 0.0, 1.0])[:, None, None, None]
    h = params.heights[:, None]
    L = L1[:, None] + (h - params.heights[0])
    a = r[:, :, None] + z * h  # a_ji = o_j + r_i
    b = z * L  # b_ji = c_i + L_ji·ẑ
    b += per_leg(params.screw_points)[..., None]

    def both_platforms(x):
        """Platform 1's x (…, N) for both platforms, (…, 2, N), as a read-only view."""
        return np.broadcast_to(x[..., None, :], x.shape[:-1] + (2, x.shape[-1]))

    return Kinematics(
        t=trajectory.t,
        q=q.T,
        qd=qd.T,
        qdd=qdd.T,
        R=np.moveaxis(R, -1, 0),
        omega=omega.T,
        omega_dot=omega_dot.T,
        r=r.T,
        a=a.T,
        b=b.T,
        e=e.T,
        L=L.T,
        Ld=both_platforms(Ld).T,
        Ldd=both_platforms(Ldd).T,
        J=J.T,
        cond_inv=cond_inv,
        omega_l=omega_l.T,
        omega_l_dot=omega_l_dot.T,
        v_l=both_platforms(v_l).T,
        a_l=both_platforms(a_l).T,
        flagged=flagged,
    )


# --- Lever motion and the lever Jacobians -----------------------------------------------


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
    """[v]×, shape (..., 3, 3), from v of shape (..., 3): row k is e_k × v."""
    return np.cross(np.eye(3), v[..., None, :])


def lever_frames(params: Parameters, kin: Kinematics) -> np.ndarray:
    """Lever body frames R_l of spec §7.1 (z along e, x along u2 = e × u1/|e × u1|).

    Returns:
        Rotation matrices, shape (N, 3, 3, 3) = (sample, leg, 3, 3), columns the
        lever's x, y, z axes in world coordinates; the same for both platforms.
    """
    axes = laws.lever_axes(per_leg(params.ujoint_axes), kin.e.T)  # components-first (xyz, leg, N) each
    return np.stack([stack(axis).T for axis in axes], axis=-1)


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
    u1, e, w_perp, w_perp_dot = per_leg(params.ujoint_axes), kin.e.T, kin.omega_l.T, kin.omega_l_dot.T
    omega_l = stack(laws.lever_angular_velocity(u1, e, w_perp))
    omega_l_dot = stack(laws.lever_angular_acceleration(u1, e, w_perp, w_perp_dot))
    return omega_l.T, omega_l_dot.T

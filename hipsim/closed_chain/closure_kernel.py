"""The arithmetic between Pinocchio's calls in the closure solver, compiled with numba.

Why this module exists. Closing the chain at one sample takes two
Pinocchio calls (forward kinematics at the prediction, joint Jacobians at the
corrected configuration), each a microsecond or two. Around them the solver
did some thirty NumPy operations on 21-vectors and a 21×21 inverse, and read
the closures' placements and Jacobian back property by property, each
costing a microsecond of Python overhead for a few hundred floating-point
operations: together more than the Pinocchio calls. Here that arithmetic
runs compiled on views of Pinocchio's Data, one call after each Pinocchio
call (:func:`gaps_and_chord_step`, :func:`closed_sample`; the other
functions are their parts, and the tests' handles on them).

Nothing here knows the machine's geometry: every joint placement and
Jacobian comes from Pinocchio (:mod:`hipsim.closed_chain.closure` calls it),
every closure frame's placement in its joint from the closure file; these
functions only combine them. The closure velocities and accelerations
solve

    K v = [q̇; 0],    K a = [q̈; −J̇_c v],    K = [P₁; J_c]

(P₁ selects platform 1's three angle coordinates, J_c is the 18×21 closure
Jacobian in the lever-tip frames), and J̇_c v is the closures' relative
classical acceleration at a = 0, from the world-frame joint Jacobians J and
v (J̇·v follows from them: :func:`_frame_motion`).

Indices are velocity indices (all the tree's joints are 1-DoF).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..physics import laws
from ..physics.vectors import add, cross, matvec, scale, sub, transpose_times
from . import block_inverse
from .block_inverse import block_lower_inverse, cramer

#: The kernels call the block inverse's: its source is part of their cache key.
_DEPENDS_ON = (*laws.LAW_FILES, Path(block_inverse.__file__))

__all__ = [
    "OK",
    "LEVER_DOWN",
    "OPEN",
    "SINGULAR",
    "acceleration",
    "actuator_and_closure_forces",
    "block_lower_inverse",
    "chord_step",
    "closed_sample",
    "closure_frames",
    "closure_jacobian",
    "gaps_and_chord_step",
    "predict",
    "rates",
    "store",
    "velocity",
]

#: Status codes of :func:`velocity` (and :func:`closed_sample`'s OPEN: the gaps are not within the limit).
OK, SINGULAR, LEVER_DOWN, OPEN = 0, 1, 2, 3

#: K⁻¹'s entries are O(1..10) in m, rad and s away from singular poses; beyond this the closure has lost rank.
_SINGULAR_ENTRY = 1e8
#: A lever tip frame whose z axis has sunk this low is horizontal or upside down.
_LEVER_DOWN_Z = 1e-6


@laws.jit(depends_on=_DEPENDS_ON)
def closure_frames(rotations, origins, joints, placements, tips, p2, d):
    """The closures' frames and gaps from the joints' world placements: frame 1's placement, frame 2's origin, d = R₁ᵀ(p₂ − p₁).

    Pinocchio's ``RigidConstraintModel.calc`` computes the same (oMc = oMi·jMc
    for both frames); here it is one compiled call over views that Pinocchio
    keeps up to date in its Data, instead of six calls and six read-backs.

    Args:
        rotations, origins: every joint's world rotation and origin [m], (njoints, 3, 3) and (njoints, 3).
        joints: per closure, the joints of its frames 1 and 2, (n, 2).
        placements: per closure, its frames' placements in those joints, (n, 2, 4, 4).
        tips: out, frame 1's world placement per closure, (n, 4, 4).
        p2: out, frame 2's world origin per closure [m], (n, 3).
        d: out, the gaps [m], (3·n,).

    Returns:
        |d|² [m²].

    Outputs go into arrays the caller keeps (here and below): a compiled
    function that returns a new array costs ~1 µs more a call, in boxing it.
    """
    n = joints.shape[0]
    for c in range(n):
        R, o, M = rotations[joints[c, 0]], origins[joints[c, 0]], placements[c, 0]
        for i in range(3):
            for j in range(3):
                tips[c, i, j] = R[i, 0] * M[0, j] + R[i, 1] * M[1, j] + R[i, 2] * M[2, j]
            tips[c, i, 3] = o[i] + R[i, 0] * M[0, 3] + R[i, 1] * M[1, 3] + R[i, 2] * M[2, 3]
            tips[c, 3, i] = 0.0
        tips[c, 3, 3] = 1.0
        R, o, M = rotations[joints[c, 1]], origins[joints[c, 1]], placements[c, 1]
        for i in range(3):
            p2[c, i] = o[i] + R[i, 0] * M[0, 3] + R[i, 1] * M[1, 3] + R[i, 2] * M[2, 3]
        gap = (p2[c, 0] - tips[c, 0, 3], p2[c, 1] - tips[c, 1, 3], p2[c, 2] - tips[c, 2, 3])
        for i in range(3):
            d[3 * c + i] = tips[c, 0, i] * gap[0] + tips[c, 1, i] * gap[1] + tips[c, 2, i] * gap[2]
    size = 0.0
    for i in range(d.size):
        size += d[i] * d[i]
    return size


@laws.jit(depends_on=_DEPENDS_ON)
def closure_jacobian(J, masks, tips, p2, J_c):
    """The closure Jacobian J_c = ∂/∂v of R₁ᵀ(ṗ₁ − ṗ₂), (3·n, nv), from the world-frame joint Jacobians J (6, nv).

    Pinocchio's ``getConstraintsJacobian`` (LOCAL, 3-D) computes the same.
    A point p of a body moves at ṗ = v_o + ω × p, (v_o, ω) = J·v summed over
    the body's supporting joints (``masks``, as in :func:`acceleration`).

    Args:
        J: world-frame joint Jacobians at q, (6, nv).
        masks: per closure, its two frames' supporting joints as 0/1 over the velocity indices, (2·n, nv).
        tips, p2: frame 1's world placements (n, 4, 4) and frame 2's origins [m] (n, 3), from :func:`closure_frames`.
        J_c: out, (3·n, nv).
    """
    n, nv = tips.shape[0], J.shape[1]
    J_c[:] = 0.0
    for c in range(n):
        p1 = (tips[c, 0, 3], tips[c, 1, 3], tips[c, 2, 3])
        q2 = (p2[c, 0], p2[c, 1], p2[c, 2])
        for col in range(nv):
            w1, w2 = masks[2 * c, col], masks[2 * c + 1, col]
            if w1 == 0.0 and w2 == 0.0:
                continue
            v_o, omega = (J[0, col], J[1, col], J[2, col]), (J[3, col], J[4, col], J[5, col])
            world = sub(scale(_point_velocity(v_o, omega, p1), w1), scale(_point_velocity(v_o, omega, q2), w2))
            for i in range(3):
                J_c[3 * c + i, col] = tips[c, 0, i] * world[0] + tips[c, 1, i] * world[1] + tips[c, 2, i] * world[2]


@laws.jit(depends_on=_DEPENDS_ON)
def predict(t, Q, V, A, row, platforms, angles, out):
    """``out``, the configuration at sample ``row`` predicted from the closed samples before it, its platforms' coordinates at ``angles``.

    A third-order Taylor step from the last sample's q, v, a, with the jerk
    from the last two accelerations (second order after the first sample).
    Its error, ~3e-11 m at 1 kHz on the ISO cycle, is above the solver's
    tolerance on purpose: one chord step from there closes the chain to
    round-off (~1e-16 m), where a fourth-order prediction (~4e-13 m) would be
    accepted as it stands and leave the models agreeing to 1e-12 instead of 1e-14.

    Args:
        t: sample times in [s], (rows,).
        Q, V, A: configurations, velocities and accelerations of the closed samples, (rows, nv).
        row: the sample to predict (≥ 1).
        platforms, angles: the platforms' coordinates and their values at ``row``.
        out: where the prediction goes, (nv,) (the solver keeps it apart
            from Q[row], where the corrected configuration goes).
    """
    h = t[row] - t[row - 1]
    last = row - 1
    if row == 1:
        for i in range(Q.shape[1]):
            out[i] = Q[0, i] + h * (V[0, i] + 0.5 * h * A[0, i])
    else:
        dt = t[last] - t[row - 2]
        for i in range(Q.shape[1]):
            jerk = (A[last, i] - A[row - 2, i]) / dt
            out[i] = Q[last, i] + h * (V[last, i] + h * (0.5 * A[last, i] + h / 6.0 * jerk))
    for k in range(platforms.size):
        out[platforms[k]] = angles[k]


@laws.jit(depends_on=_DEPENDS_ON)
def chord_step(q, K_inv, d, platforms, angles, trial):
    """``trial``, a Newton step from q on the closure gaps d = R₁ᵀ(p₂ − p₁) [m] with an earlier K⁻¹.

    The platforms' coordinates are kept at ``angles``: platform 1's rows of
    K⁻¹[:, 3:] vanish, platform 2's would move its coordinates by O(|d|²).
    """
    for i in range(q.size):
        step = 0.0
        for j in range(d.size):
            step += K_inv[i, 3 + j] * d[j]
        trial[i] = q[i] + step
    for k in range(platforms.size):
        trial[platforms[k]] = angles[k]


@laws.jit(depends_on=_DEPENDS_ON)
def gaps_and_chord_step(rotations, origins, joints, placements, tips, p2, d, q, K_inv, platforms, angles, limit, trial):
    """After forward kinematics at q: the closures' frames and gaps (:func:`closure_frames`) and, unless |d|² ≤ ``limit`` [m²], a chord step from q into ``trial`` (:func:`chord_step`).

    The solver's usual first call of a sample, between its two Pinocchio calls. Returns |d|² [m²].
    """
    size = closure_frames(rotations, origins, joints, placements, tips, p2, d)
    if size > limit:
        chord_step(q, K_inv, d, platforms, angles, trial)
    return size


@laws.jit(depends_on=_DEPENDS_ON)
def closed_sample(
    rotations,
    origins,
    joints,
    placements,
    tips,
    p2,
    d,
    limit,
    J,
    masks,
    J_c,
    platform1,
    rows,
    columns,
    starts,
    platform2,
    sliders,
    qd,
    qdd,
    V,
    A,
    row,
    J_rates,
    residual,
    k,
    K_inv,
    K_invs,
    angular,
    tip_rotations,
    slot,
):
    """After the joint Jacobians at a corrected q: its frames and gaps and, if |d|² ≤ ``limit`` [m²], all the solver keeps of sample k.

    :func:`closure_frames`, then :func:`rates` and :func:`store`, in one
    call: numba's dispatch costs ~0.25 µs a call and ~0.05 µs an argument.

    Args:
        rotations, origins, joints, placements, tips, p2, d: as in :func:`closure_frames`.
        limit: the largest |d|² [m²] accepted as closed.
        J, masks, J_c, platform1, rows, columns, starts, platform2, sliders, qd, qdd, V, A, row, J_rates, residual, k, K_inv: as
            in :func:`rates`.
        K_invs, angular, tip_rotations, slot: as ``K_invs, angular, rotations, slot`` in :func:`store`;
            slot < 0: nothing kept (no inverse dynamics asked for).

    Returns:
        (status, |d|² [m²]): :data:`OPEN` when |d|² > limit (nothing else is
        computed), else :func:`rates`' status (nothing kept unless :data:`OK`).
    """
    size = closure_frames(rotations, origins, joints, placements, tips, p2, d)
    if size > limit:
        return OPEN, size
    status = rates(
        J,
        masks,
        tips,
        p2,
        d,
        J_c,
        platform1,
        rows,
        columns,
        starts,
        platform2,
        sliders,
        qd,
        qdd,
        V,
        A,
        row,
        J_rates,
        residual,
        k,
        K_inv,
    )
    if status == OK and slot >= 0:
        store(K_invs, angular, tip_rotations, slot, k, K_inv, J, tips)
    return status, size


@laws.jit(depends_on=_DEPENDS_ON)
def velocity(J_c, platform1, rows, columns, starts, qd, platform2, tips, V, row, sliders, J_rates, k, K_inv):
    """K⁻¹ and the tree velocity v = V[row] at a closed configuration; J_rates[k], the sliders' rows of K⁻¹'s first three columns.

    K = [P₁; J_c] is inverted by blocks: with B = J_c's columns of the other
    coordinates and C its columns of platform 1's, K x = [y₁; y₂] gives
    x[platform 1] = y₁ and x[others] = B⁻¹(y₂ − C y₁). B's rows and columns
    are taken in an order that makes it block lower triangular (see
    :func:`block_lower_inverse`; a single block is a plain inverse).

    Args:
        J_c: the closure Jacobian, (3·n_closures, nv).
        platform1: platform 1's velocity indices, (3,), the coordinates P₁ selects.
        rows, columns: B's rows (rows of J_c) and columns (velocity indices, the others than platform 1's), in block order, (nv − 3,) each.
        starts: where each diagonal block of the reordered B starts, and its size at the end, (blocks + 1,).
        qd: platform angle rates [rad/s], (3,).
        platform2: platform 2's velocity indices, (3,): set to q̇ exactly.
        tips: the lever-tip frames' homogeneous placements (n_closures, 4, 4).
        V, row: where v goes, V[row] (nv,).
        sliders: the sliders' velocity indices, (3,).
        J_rates, k: where ∂L̇/∂q̇ goes, J_rates[k] (3, 3).
        K_inv: out, K⁻¹ (nv, nv).

    Returns:
        :data:`OK`, :data:`SINGULAR` (K⁻¹ blows up) or :data:`LEVER_DOWN`
        (a lever horizontal or pointing down); V and J_rates are not written
        unless OK.
    """
    nv, n = J_c.shape[1], rows.size
    M, C = np.empty((n, n)), np.empty((n, 3))
    for i in range(n):
        for j in range(n):
            M[i, j] = J_c[rows[i], columns[j]]
        for j in range(3):
            C[i, j] = J_c[rows[i], platform1[j]]
    M_inv = block_lower_inverse(M, starts)
    K_inv[:] = 0.0
    for j in range(3):
        K_inv[platform1[j], j] = 1.0
    largest = 0.0
    for i in range(n):
        out = columns[i]
        n0 = n1 = n2 = 0.0  # −(B⁻¹C)[i]: K⁻¹'s first three columns, three sums at once
        for m in range(n):
            x = M_inv[i, m]
            K_inv[out, 3 + rows[m]] = x
            largest = max(largest, abs(x))
            n0 += x * C[m, 0]
            n1 += x * C[m, 1]
            n2 += x * C[m, 2]
        K_inv[out, 0], K_inv[out, 1], K_inv[out, 2] = -n0, -n1, -n2
        largest = max(largest, abs(n0), abs(n1), abs(n2))
    if not largest < _SINGULAR_ENTRY:
        return SINGULAR
    for c in range(tips.shape[0]):
        if tips[c, 2, 2] <= _LEVER_DOWN_Z:
            return LEVER_DOWN
    for i in range(nv):
        V[row, i] = K_inv[i, 0] * qd[0] + K_inv[i, 1] * qd[1] + K_inv[i, 2] * qd[2]
    for i in range(3):
        V[row, platform2[i]] = qd[i]
        for j in range(3):
            J_rates[k, i, j] = K_inv[sliders[i], j]
    return OK


@laws.jit(depends_on=_DEPENDS_ON)
def rates(
    J,
    masks,
    tips,
    p2,
    d,
    J_c,
    platform1,
    rows,
    columns,
    starts,
    platform2,
    sliders,
    qd,
    qdd,
    V,
    A,
    row,
    J_rates,
    residual,
    k,
    K_inv,
):
    """Everything the solver needs of sample k once it is closed, in one call: J_c, K⁻¹, V[row], A[row], J_rates[k] and residual[k].

    :func:`closure_jacobian`, :func:`velocity` and :func:`acceleration` in
    turn (no Pinocchio call is needed between them), and the largest closure
    gap.

    Args:
        J, masks, tips, p2, d, J_c: as in :func:`closure_jacobian` and :func:`acceleration` (d: the gaps at q [m]).
        platform1, rows, columns, starts, platform2, sliders: as in :func:`velocity`.
        qd, qdd: platform angle rates [rad/s] and accelerations [rad/s²] of every sample, (samples, 3).
        V, A, row: where the tree velocity and acceleration go, V[row], A[row].
        J_rates, residual, k: where ∂L̇/∂q̇ (3, 3) and the largest closure gap [m] go, J_rates[k] and residual[k].
        K_inv: out, K⁻¹ (nv, nv).

    Returns:
        :data:`OK`, :data:`SINGULAR` or :data:`LEVER_DOWN`, as :func:`velocity`
        (A and residual are not written unless OK).
    """
    closure_jacobian(J, masks, tips, p2, J_c)
    status = velocity(J_c, platform1, rows, columns, starts, qd[k], platform2, tips, V, row, sliders, J_rates, k, K_inv)
    if status != OK:
        return status
    acceleration(K_inv, J, V, A, row, masks, tips, d, qdd[k], platform2)
    largest = 0.0
    for c in range(tips.shape[0]):
        largest = max(largest, np.sqrt(d[3 * c] ** 2 + d[3 * c + 1] ** 2 + d[3 * c + 2] ** 2))
    residual[k] = largest
    return OK


@laws.jit(depends_on=_DEPENDS_ON)
def acceleration(K_inv, J, V, A, row, masks, tips, d, qdd, platform2):
    """The tree acceleration A[row], in [m/s², rad/s²], from K a = [q̈; −J̇_c v] at a closed configuration.

    Args:
        K_inv: K⁻¹ from :func:`velocity`, (nv, nv).
        J: the world-frame joint Jacobians at q, (6, nv).
        V, A, row: the tree velocity V[row] (nv,) and where the acceleration goes, A[row].
        masks: per closure, its two frames' supporting joints as 0/1 over the velocity indices, (2·n_closures, nv).
        tips: the lever-tip frames' homogeneous placements, (n_closures, 4, 4).
        d: the closure gaps R₁ᵀ(p₂ − p₁) [m], (3·n_closures,).
        qdd: platform angle accelerations [rad/s²], (3,).
        platform2: platform 2's velocity indices, (3,): set to q̈ exactly.

    J̇_c v of closure c is R₁ᵀ(p̈₁ − p̈₂) at a = 0 (valid where J_c v = 0:
    the two frames then move together, so R₁'s rotation adds nothing), with
    p₂ = p₁ + R₁·d_c the platform point exactly. A point p of a body whose
    world-frame spatial velocity is (v_o, ω) = J·v and acceleration
    (a_o, ω̇) = J̇·v, both at the world origin (the body's supporting joints'
    columns only, J̇·v from J and v by :func:`_frame_motion`), has
    ṗ = v_o + ω × p and p̈ = a_o + ω̇ × p + ω × ṗ.
    """
    n, nv = tips.shape[0], V.shape[1]
    drift = np.empty(3 * n)
    for c in range(n):
        R = (
            (tips[c, 0, 0], tips[c, 0, 1], tips[c, 0, 2]),
            (tips[c, 1, 0], tips[c, 1, 1], tips[c, 1, 2]),
            (tips[c, 2, 0], tips[c, 2, 1], tips[c, 2, 2]),
        )
        p1 = (tips[c, 0, 3], tips[c, 1, 3], tips[c, 2, 3])
        p2 = add(p1, matvec(R, (d[3 * c], d[3 * c + 1], d[3 * c + 2])))
        twist1, rate1 = _frame_motion(masks[2 * c], V[row], J)
        twist2, rate2 = _frame_motion(masks[2 * c + 1], V[row], J)
        local = transpose_times(R, sub(_point_acceleration(twist1, rate1, p1), _point_acceleration(twist2, rate2, p2)))
        drift[3 * c], drift[3 * c + 1], drift[3 * c + 2] = local[0], local[1], local[2]
    for i in range(nv):  # A[row] = K⁻¹·[q̈; −J̇_c v]
        total = K_inv[i, 0] * qdd[0] + K_inv[i, 1] * qdd[1] + K_inv[i, 2] * qdd[2]
        for j in range(3 * n):
            total -= K_inv[i, 3 + j] * drift[j]
        A[row, i] = total
    for k in range(3):
        A[row, platform2[k]] = qdd[k]


@laws.jit(depends_on=_DEPENDS_ON)
def _frame_motion(mask, v, J):
    """A closure frame's spatial velocity (v_o, ω) = Σ J·v and acceleration at a = 0 (a_o, ω̇) = Σ J̇·v over its supporting joints, (6-tuples).

    Why not Pinocchio's J̇ (``computeJointJacobiansTimeVariation``): it is a
    third Pinocchio call per sample, a third of their cost, for what follows
    from J and v. A joint's world-frame column S_k (a motion at the world
    origin) is fixed in its body, so it changes as Ṡ_k = V_k × S_k, with V_k
    its body's spatial velocity, the sum of S_j v_j over the joints j up to k
    (k's own term drops, S_k × S_k = 0). Hence J̇·v = Σ_{j before k} (S_j v_j) × (S_k v_k)
    along the frame's supporting chain, which is Pinocchio's own definition of
    J̇ (the test of this module holds the two equal). "Before" is the
    velocity index order: Pinocchio numbers a joint after its parent, so the
    mask's columns, read in increasing order, go from the root outwards.
    """
    # (v, ω) × (v', ω') = (ω × v' + v × ω', ω × ω'): the motion cross product.
    v0 = v1 = v2 = w0 = w1 = w2 = 0.0  # the running sum Σ S_j v_j
    a0 = a1 = a2 = b0 = b1 = b2 = 0.0  # the running Σ (S_j v_j) × (S_k v_k)
    for col in range(v.size):
        if mask[col] == 0.0:
            continue
        x = mask[col] * v[col]
        s0, s1, s2 = x * J[0, col], x * J[1, col], x * J[2, col]
        t0, t1, t2 = x * J[3, col], x * J[4, col], x * J[5, col]
        a0 += w1 * s2 - w2 * s1 + v1 * t2 - v2 * t1
        a1 += w2 * s0 - w0 * s2 + v2 * t0 - v0 * t2
        a2 += w0 * s1 - w1 * s0 + v0 * t1 - v1 * t0
        b0 += w1 * t2 - w2 * t1
        b1 += w2 * t0 - w0 * t2
        b2 += w0 * t1 - w1 * t0
        v0, v1, v2, w0, w1, w2 = v0 + s0, v1 + s1, v2 + s2, w0 + t0, w1 + t1, w2 + t2
    return (v0, v1, v2, w0, w1, w2), (a0, a1, a2, b0, b1, b2)


@laws.jit(depends_on=_DEPENDS_ON)
def _point_velocity(v_o, omega, p):
    """ṗ = v_o + ω × p of the point at p [m] on a body moving at (v_o, ω) (world origin).

    Given the body's acceleration (a_o, ω̇) instead, the same sum a_o + ω̇ × p is the part of p̈ they make.
    """
    return add(v_o, cross(omega, p))


@laws.jit(depends_on=_DEPENDS_ON)
def _point_acceleration(twist, rate, p):
    """p̈ at a = 0 of the point at p [m] on a body of spatial velocity ``twist`` and acceleration ``rate`` (world origin)."""
    v_o, omega = (twist[0], twist[1], twist[2]), (twist[3], twist[4], twist[5])
    a_o, omega_dot = (rate[0], rate[1], rate[2]), (rate[3], rate[4], rate[5])
    return add(_point_velocity(a_o, omega_dot, p), cross(omega, _point_velocity(v_o, omega, p)))


@laws.jit(depends_on=_DEPENDS_ON)
def store(K_invs, angular, rotations, slot, k, K_inv, J, tips):
    """Keep what the inverse dynamics reuse of sample k: K⁻¹ and the joint Jacobians' angular rows at ``slot`` of the chunk, the lever-tip rotations at k."""
    K_invs[slot] = K_inv
    angular[slot] = J[3:]
    rotations[k] = tips[:, :3, :3]


@laws.jit(depends_on=_DEPENDS_ON)
def actuator_and_closure_forces(K_invs, tau, actuated, F, lambdas):
    """Per sample, the actuator forces F and closure forces λ of Sᵀ F + J_cᵀ λ = τ, from K⁻¹.

    With N = K⁻¹[:, :3] (tree velocities per platform angle rate, J_c N = 0)
    and G = S N (the actuated joints' rows of N), projecting on the motions the
    closures allow gives Gᵀ F = Nᵀ τ (solved by Cramer's rule); then
    λ = (K⁻ᵀ (τ − Sᵀ F))[3:], whose first three components vanish because
    τ − Sᵀ F lies in the range of J_cᵀ.

    Args:
        K_invs: K⁻¹ per sample, (m, nv, nv).
        tau: the tree's generalised forces per sample and part, (m, nv, parts).
        actuated: the actuated joints' velocity indices, (3,).
        F: out, actuator forces [N] per sample and part, (m, 3, parts).
        lambdas: out, closure forces [N] of all parts together, (m, 3·n_closures).
    """
    m, nv, parts = tau.shape
    for s in range(m):
        K_inv = K_invs[s]
        G = (
            (K_inv[actuated[0], 0], K_inv[actuated[1], 0], K_inv[actuated[2], 0]),
            (K_inv[actuated[0], 1], K_inv[actuated[1], 1], K_inv[actuated[2], 1]),
            (K_inv[actuated[0], 2], K_inv[actuated[1], 2], K_inv[actuated[2], 2]),
        )  # Gᵀ by rows
        rest = tau[s].sum(axis=1)
        for p in range(parts):
            b = (0.0, 0.0, 0.0)
            for k in range(nv):
                b = add(b, (K_inv[k, 0] * tau[s, k, p], K_inv[k, 1] * tau[s, k, p], K_inv[k, 2] * tau[s, k, p]))
            f = cramer(G, b)
            for i in range(3):
                F[s, i, p] = f[i]
                rest[actuated[i]] -= f[i]
        for c in range(nv - 3):
            total = 0.0
            for k in range(nv):
                total += K_inv[k, 3 + c] * rest[k]
            lambdas[s, c] = total

"""The Pinocchio plant's compiled closure solver: the tree's constrained acceleration from M, h and J in one call.

:class:`~hipsim.closed_chain.plant.PinocchioPlant` evaluates a derivative
with one Pinocchio call, ``crba`` in the WORLD convention (the joint-space
inertia M, armature included, and, as by-products, the joints' world
placements ``data.oMi`` and world Jacobians ``data.J``), then one call of
:func:`constrained_acceleration` here, which evaluates h = C(q, v)·v + g(q)
by Newton–Euler over the bodies (``nonLinearEffects`` would be a second
Pinocchio call, 3.2 µs) and solves

    M a + h = τ + J_cᵀ λ,   J_c a = −J̇_c v + K_p·d − K_d·(J_c v)

exactly (no proximal regularisation) by coordinate partitioning. Away from
singular poses the closures fix every coordinate but platform 1's three
angles (the same partition as the inverse dynamics' K = [P₁; J_c], see
:mod:`~hipsim.closed_chain.closure`): with B the 18 columns of J_c of the
other coordinates and J_i those of the angles, the accelerations that keep
the closures are a = G·α̈ + c, G = [I; −B⁻¹J_i], c = [0; B⁻¹r] (r the
right-hand side above), and projecting the dynamics on G (Gᵀ J_cᵀ = 0, so
λ drops out) leaves three equations, (GᵀMG)·α̈ = Gᵀ(τ − h − M c).

Why: ``pin.constraintDynamics`` costs ~12.5 µs a call here (CRBA, bias
forces, the constraint Cholesky, the proximal loop) and ``pin.lcaba`` as
much or more at equal accuracy (it needs μ ≈ 1e-6 and three proximal
iterations for 3e-9 m/s², and ignores the Baumgarte corrector); ``crba``
costs 2.6 µs and this call 4.6 µs (1.2 µs of it numba's unboxing of the
arguments; an 18×18 elimination, block by block in B's block lower
triangular order (:func:`block_order`: three 3×3 blocks and a 9×9 for the
hip), M·G over M's nonzero entries, a 3×3 system). The closures' frames, gaps, Jacobian and drift J̇_c v are those of
:mod:`~hipsim.closed_chain.closure_kernel`, held equal to Pinocchio's by
its tests; the acceleration is held equal to ``constraintDynamics``'s by
this module's tests.

The gaps d = R₁ᵀ(p₂ − p₁) are the negated position errors R₁ᵀ(p₁ − p₂) of
Pinocchio's legacy 3-D constraints (LOCAL), so the Baumgarte terms read as
Pinocchio's corrector with the same scalar gains.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..physics import laws
from ..physics.vectors import add, cross, matvec, scale, sub, transpose_times
from . import block_inverse, closure_kernel
from .closure_kernel import _point_acceleration, closure_frames
from .workspace import block_triangular_order

#: The kernels call closure_kernel's: its source (and what it calls) is part of their cache key.
_DEPENDS_ON = (*laws.LAW_FILES, Path(closure_kernel.__file__), Path(block_inverse.__file__))

__all__ = ["block_order", "constrained_acceleration", "tree_constants"]


def tree_constants(model) -> tuple[np.ndarray, np.ndarray]:
    """The tree's bodies for :func:`constrained_acceleration`: per joint (mass [kg], lever [m] (3), rotational inertia [kg·m²] (3×3)) and (parent, velocity slot).

    Args:
        model: a Pinocchio model whose joints have one velocity each (revolute, prismatic).

    Returns:
        bodies: (njoints, 13) floats; joints: (njoints, 2) integers (the universe's slot is −1).
    """
    bodies = np.zeros((model.njoints, 13))
    joints = np.zeros((model.njoints, 2), dtype=np.int64)
    for j in range(model.njoints):
        inertia = model.inertias[j]
        bodies[j, 0], bodies[j, 1:4], bodies[j, 4:] = inertia.mass, inertia.lever, inertia.inertia.ravel()
        joints[j] = model.parents[j], model.joints[j].idx_v if j else -1
    return bodies, joints


def block_order(joints: np.ndarray, closures: np.ndarray, others: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The orders of the eliminated system's rows and columns that make B block lower triangular, for :func:`constrained_acceleration`.

    Closure c's three rows of J_c reach the columns of the joints that support
    its two frames, and no other: from that pattern, the Dulmage–Mendelsohn
    block triangular form (:func:`~hipsim.closed_chain.workspace.block_triangular_order`).
    For the hip: each platform-1 lever's slider and universal joint (3×3, three
    of them), then platform 2's levers and spherical joint together (9×9).

    Args:
        joints: per joint (parent, velocity slot), (njoints, 2) (:func:`tree_constants`).
        closures: per closure, its frames' joints, (n, 2).
        others: the velocity slots of B's columns, (3·n,).

    Returns:
        others in the system's column order (3·n,), and ``blocks`` as :func:`constrained_acceleration` takes it.
    """
    reach = np.zeros((closures.shape[0], joints.shape[0] - 1), dtype=bool)
    for c, ends in enumerate(closures):
        for j in ends:
            while j > 0:
                reach[c, joints[j, 1]] = True
                j = joints[j, 0]
    rows, columns, starts = block_triangular_order(np.repeat(reach[:, others], 3, axis=0))
    blocks = np.zeros((2, others.size), dtype=np.int64)
    blocks[0, rows] = np.arange(others.size)
    for start, stop in zip(starts[:-1], starts[1:]):
        blocks[1, start:stop] = stop
    return others[columns], blocks


@laws.jit(depends_on=_DEPENDS_ON)
def _motion_cross(a, b):
    """The motion cross product (v, ω) × (v', ω') = (ω × v' + v × ω', ω × ω') of two 6-tuples (linear first)."""
    v, w = (a[0], a[1], a[2]), (a[3], a[4], a[5])
    u, s = (b[0], b[1], b[2]), (b[3], b[4], b[5])
    lin = add(cross(w, u), cross(v, s))
    ang = cross(w, s)
    return (lin[0], lin[1], lin[2], ang[0], ang[1], ang[2])


@laws.jit(depends_on=_DEPENDS_ON)
def _motions(J, joints, v, twists, rates):
    """Every joint's body spatial velocity V (world origin, linear first) and its acceleration at a = 0, into (njoints, 6) each.

    V_j = V_parent + S_j v_j, and since a joint's world column S_j is fixed
    in its body (Ṡ_j = V_j × S_j), the acceleration at a = 0 is
    A_j = A_parent + V_parent × S_j v_j: Pinocchio's J̇·v along the chain
    (:func:`~hipsim.closed_chain.closure_kernel._frame_motion`, recursively).
    """
    for i in range(6):
        twists[0, i] = rates[0, i] = 0.0
    for j in range(1, joints.shape[0]):
        parent, slot = joints[j, 0], joints[j, 1]
        x = v[slot]
        sv = (x * J[0, slot], x * J[1, slot], x * J[2, slot], x * J[3, slot], x * J[4, slot], x * J[5, slot])
        bias = _motion_cross(
            (
                twists[parent, 0],
                twists[parent, 1],
                twists[parent, 2],
                twists[parent, 3],
                twists[parent, 4],
                twists[parent, 5],
            ),
            sv,
        )
        for i in range(6):
            twists[j, i] = twists[parent, i] + sv[i]
            rates[j, i] = rates[parent, i] + bias[i]


@laws.jit(depends_on=_DEPENDS_ON)
def _nonlinear_effects(J, rotations, origins, bodies, joints, gravity, twists, rates, wrenches, h):
    """h = C(q, v)·v + g(q) [N, N·m] into h, by Newton–Euler in the world frame from the bodies' motions at a = 0.

    Body j (mass m, centre of mass c = o_j + R_j·lever, world inertia R_j I R_jᵀ)
    takes the force f = m·(c̈ − g) and the moment about c, I ω̇ + ω × I ω;
    its wrench about the world origin (f, n + c × f) adds into its parent's,
    and a joint's entry of h is its column's power against its subtree's wrench.
    """
    nj = joints.shape[0]
    for j in range(nj):
        for i in range(6):
            wrenches[j, i] = 0.0
    for j in range(1, nj):
        m = bodies[j, 0]
        if m == 0.0:
            continue
        R = rotations[j]
        Rm = ((R[0, 0], R[0, 1], R[0, 2]), (R[1, 0], R[1, 1], R[1, 2]), (R[2, 0], R[2, 1], R[2, 2]))
        c = add((origins[j, 0], origins[j, 1], origins[j, 2]), matvec(Rm, (bodies[j, 1], bodies[j, 2], bodies[j, 3])))
        v_o, w = (twists[j, 0], twists[j, 1], twists[j, 2]), (twists[j, 3], twists[j, 4], twists[j, 5])
        a_o, w_dot = (rates[j, 0], rates[j, 1], rates[j, 2]), (rates[j, 3], rates[j, 4], rates[j, 5])
        c_dot = add(v_o, cross(w, c))
        c_ddot = add(add(a_o, cross(w_dot, c)), cross(w, c_dot))
        f = scale(sub(c_ddot, gravity), m)
        I = (
            (bodies[j, 4], bodies[j, 5], bodies[j, 6]),
            (bodies[j, 7], bodies[j, 8], bodies[j, 9]),
            (bodies[j, 10], bodies[j, 11], bodies[j, 12]),
        )
        # R I Rᵀ x = R (I (Rᵀ x)), in the world.
        Iw = matvec(Rm, matvec(I, transpose_times(Rm, w)))
        Iw_dot = matvec(Rm, matvec(I, transpose_times(Rm, w_dot)))
        n = add(add(Iw_dot, cross(w, Iw)), cross(c, f))
        for i in range(3):
            wrenches[j, i] = f[i]
            wrenches[j, 3 + i] = n[i]
    for j in range(nj - 1, 0, -1):
        slot = joints[j, 1]
        total = 0.0
        for i in range(6):
            total += J[i, slot] * wrenches[j, i]
        h[slot] = total
        parent = joints[j, 0]
        if parent > 0:
            for i in range(6):
                wrenches[parent, i] += wrenches[j, i]


@laws.jit(depends_on=_DEPENDS_ON)
def constrained_acceleration(
    M, J, rotations, origins, y, tau, bodies, joints, closures, placements, order, blocks, settings, a
):  # pragma: no cover - compiled
    """The tree acceleration a [m/s², rad/s²] at state y = [q, v] under generalised forces tau, the closures held; returns |d|² [m²].

    Args:
        M: the joint-space inertia at q, upper triangle read (Pinocchio's ``data.M`` after ``crba``), (nv, nv).
        J, rotations, origins: the world-frame joint Jacobians (6, nv), every joint's world rotation
            (njoints, 3, 3) and origin [m] (njoints, 3) at q (views of ``data.J`` and ``data.oMi``).
        y: the state [q, v], (nq + nv,); only v is read.
        tau: the generalised forces in [N, N·m], (nv,).
        bodies, joints: :func:`tree_constants`.
        closures, placements: per closure, its frames' joints (n, 2) and their placements in them (n, 2, 4, 4).
        order: row 0, the independent platform's three angle slots (platform 1's; with a stack-up platform 2's), then the other nv − 3 (J_c's columns of those: square,
            regular); row 1, each slot's column in the eliminated system (the others' first, the angles' after), (2, nv).
        blocks: row 0, each row of J_c's row in the eliminated system; row 1, for each row (and column) of the
            system, where its diagonal block ends, (2, nv − 3). The system's rows and columns are in an order
            that makes B block lower triangular (:func:`block_order`; a single block is the plain order).
        settings: Baumgarte's K_p [1/s²], K_d [1/s], then the gravity vector [m/s²].
        a: out, (nv,).
    """
    nj, n, nv = joints.shape[0], closures.shape[0], a.size
    v = y[y.size - nv :]
    m = nv - 3
    tips, p2, d = np.empty((n, 4, 4)), np.empty((n, 3)), np.empty(3 * n)
    size = closure_frames(rotations, origins, closures, placements, tips, p2, d)
    twists, rates, wrenches = np.empty((nj, 6)), np.empty((nj, 6)), np.empty((nj, 6))
    _motions(J, joints, v, twists, rates)
    h = np.empty(nv)
    _nonlinear_effects(
        J, rotations, origins, bodies, joints, (settings[2], settings[3], settings[4]), twists, rates, wrenches, h
    )
    kp, kd = settings[0], settings[1]
    # Each closure's rows of the augmented system B·X = [J_i | r]: J_c's columns in ``order`` (the dependent
    # ones first, then the angles'), and r = −J̇_c v + K_p·d − K_d·J_c v.
    work = np.zeros((m, nv + 1))
    for c in range(n):
        R = (
            (tips[c, 0, 0], tips[c, 0, 1], tips[c, 0, 2]),
            (tips[c, 1, 0], tips[c, 1, 1], tips[c, 1, 2]),
            (tips[c, 2, 0], tips[c, 2, 1], tips[c, 2, 2]),
        )
        p1 = (tips[c, 0, 3], tips[c, 1, 3], tips[c, 2, 3])
        q2 = (p2[c, 0], p2[c, 1], p2[c, 2])
        ends = (closures[c, 0], closures[c, 1])
        # J̇_c v = R₁ᵀ(p̈₁ − p̈₂) at a = 0, J_c v = R₁ᵀ(ṗ₁ − ṗ₂).
        p_ddot = sub(
            _point_acceleration(twists[ends[0]], rates[ends[0]], p1),
            _point_acceleration(twists[ends[1]], rates[ends[1]], q2),
        )
        p_dot = sub(
            add(
                (twists[ends[0], 0], twists[ends[0], 1], twists[ends[0], 2]),
                cross((twists[ends[0], 3], twists[ends[0], 4], twists[ends[0], 5]), p1),
            ),
            add(
                (twists[ends[1], 0], twists[ends[1], 1], twists[ends[1], 2]),
                cross((twists[ends[1], 3], twists[ends[1], 4], twists[ends[1], 5]), q2),
            ),
        )
        drift, rate = transpose_times(R, p_ddot), transpose_times(R, p_dot)
        for i in range(3):
            work[blocks[0, 3 * c + i], nv] = -drift[i] + kp * d[3 * c + i] - kd * rate[i]
        # J_c's columns: ∂/∂v of R₁ᵀ(ṗ₁ − ṗ₂) along each frame's supporting chain (closure_kernel.closure_jacobian).
        for end in range(2):
            point, sign = (p1, 1.0) if end == 0 else (q2, -1.0)
            j = ends[end]
            while j > 0:
                slot = joints[j, 1]
                world = add((J[0, slot], J[1, slot], J[2, slot]), cross((J[3, slot], J[4, slot], J[5, slot]), point))
                local = transpose_times(R, world)
                column = order[1, slot]
                for i in range(3):
                    work[blocks[0, 3 * c + i], column] += sign * local[i]
                j = joints[j, 0]
    # Eliminate over the m dependent columns, X = B⁻¹[J_i | r] ending in columns m … nv. B is block lower
    # triangular: pivots are sought within a diagonal block (det B is the product of the blocks'), and a pivot
    # row, whose earlier blocks' entries are gone by then, only reaches its own block's columns and the last four.
    for k in range(m):
        end = blocks[1, k]
        pivot, best = k, abs(work[k, k])
        for i in range(k + 1, end):
            if abs(work[i, k]) > best:
                pivot, best = i, abs(work[i, k])
        if pivot != k:
            for j in range(k, nv + 1):
                work[k, j], work[pivot, j] = work[pivot, j], work[k, j]
        inverse = 1.0 / work[k, k]
        for i in range(k + 1, m):
            factor = work[i, k] * inverse
            if factor != 0.0:
                for j in range(k + 1, end):
                    work[i, j] -= factor * work[k, j]
                for j in range(m, nv + 1):
                    work[i, j] -= factor * work[k, j]
    for k in range(m - 1, -1, -1):
        inverse = 1.0 / work[k, k]
        for j in range(m, nv + 1):
            total = work[k, j]
            for i in range(k + 1, blocks[1, k]):
                total -= work[k, i] * work[i, j]
            work[k, j] = total * inverse
    # G = [I; −X_i] over the slots (three columns) and c = [0; X_r] (the fourth).
    G = np.zeros((nv, 4))
    for k in range(3):
        G[order[0, k], k] = 1.0
    for k in range(m):
        slot = order[0, 3 + k]
        for j in range(3):
            G[slot, j] = -work[k, m + j]
        G[slot, 3] = work[k, nv]
    # M·G over M's nonzero entries only: M[i, k] ≠ 0 needs joint i on k's path to the root (or the reverse),
    # 93 of 441 entries here; an ancestor's velocity slot comes first, so M[i, k] is in the upper triangle.
    MG = np.zeros((nv, 4))
    for j in range(1, nj):
        k = joints[j, 1]
        for c in range(4):
            MG[k, c] += M[k, k] * G[k, c]
        i = joints[j, 0]
        while i > 0:
            slot = joints[i, 1]
            Mik = M[slot, k]
            for c in range(4):
                MG[slot, c] += Mik * G[k, c]
                MG[k, c] += Mik * G[slot, c]
            i = joints[i, 0]
    A = np.zeros((3, 3))
    b = np.zeros(3)
    for r in range(3):
        for i in range(nv):
            b[r] += G[i, r] * (tau[i] - h[i] - MG[i, 3])
            for j in range(3):
                A[r, j] += G[i, r] * MG[i, j]
    # GᵀMG is symmetric positive definite, 3×3: its adjugate over its determinant.
    c00 = A[1, 1] * A[2, 2] - A[1, 2] * A[2, 1]
    c01 = A[1, 2] * A[2, 0] - A[1, 0] * A[2, 2]
    c02 = A[1, 0] * A[2, 1] - A[1, 1] * A[2, 0]
    det = A[0, 0] * c00 + A[0, 1] * c01 + A[0, 2] * c02
    alpha = matvec(
        (
            (c00, A[0, 2] * A[2, 1] - A[0, 1] * A[2, 2], A[0, 1] * A[1, 2] - A[0, 2] * A[1, 1]),
            (c01, A[0, 0] * A[2, 2] - A[0, 2] * A[2, 0], A[0, 2] * A[1, 0] - A[0, 0] * A[1, 2]),
            (c02, A[0, 1] * A[2, 0] - A[0, 0] * A[2, 1], A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]),
        ),
        (b[0] / det, b[1] / det, b[2] / det),
    )
    for i in range(nv):
        a[i] = G[i, 0] * alpha[0] + G[i, 1] * alpha[1] + G[i, 2] * alpha[2] + G[i, 3]
    return size

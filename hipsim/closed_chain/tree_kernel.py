"""The tree's forward kinematics and joint-space inertia, compiled with numba: what ``pin.crba`` gave the plant.

Why this module exists. The Pinocchio plant's compiled route evaluated each
RK4 stage with one Pinocchio call (``crba`` in the WORLD convention: M, and
the joints' world placements and Jacobians as by-products) and one compiled
call (:func:`~hipsim.closed_chain.plant_kernel.constrained_acceleration`).
Profiled on 2,000 servo periods of the ISO cycle (27 Nov) those two calls
and the Python crossings around them took the whole period: ``crba`` 3.8 µs,
the compiled solve 6.6 µs, the stage arithmetic 2.2 µs, eight stages and ten
crossings a period. With the tree's kinematics and inertia compiled too, a
whole period's RK4 steps run in one compiled call
(:func:`~hipsim.closed_chain.plant_step.advance`).

Nothing here knows the machine: the joints' placements in their parents
(``model.jointPlacements``), their motion subspaces (each joint's column of
Pinocchio's LOCAL joint Jacobian at q = 0) and the bodies' inertias
(:func:`~hipsim.closed_chain.plant_kernel.tree_constants`) are read from
the Pinocchio model once (:func:`tree_geometry`); the plant checks the
result against ``pin.crba`` at random configurations before it uses this
route. Every joint has one velocity and is revolute (the subspace is an
axis u: the joint turns by Rodrigues' R(u, q)) or prismatic (it slides by
u·q); Pinocchio numbers a joint after its parent, so one pass outwards
places them all.

Conventions as Pinocchio's WORLD ones: a joint's Jacobian column is its
motion (linear, angular) at the world origin in world axes, and M the
joint-space inertia with the armature on its diagonal.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from ..physics import laws
from ..physics.vectors import add, cross, matvec

__all__ = ["forward_kinematics", "mass_matrix", "tree_geometry"]


def tree_geometry(model) -> tuple[np.ndarray, np.ndarray] | None:
    """Each joint's placement in its parent (njoints, 3, 4) and motion subspace (njoints, 6; linear, angular), or None.

    None when a joint is neither a pure rotation about an axis through its
    origin nor a pure translation (or has other than one velocity).

    Args:
        model: a Pinocchio model.
    """
    if model.nq != model.nv or any(joint.nv != 1 for joint in list(model.joints)[1:]):
        return None
    data = model.createData()
    pin.computeJointJacobians(model, data, pin.neutral(model))
    placements = np.zeros((model.njoints, 3, 4))
    motions = np.zeros((model.njoints, 6))
    placements[0, :, :3] = np.eye(3)
    for j in range(1, model.njoints):
        placement = model.jointPlacements[j]
        placements[j, :, :3], placements[j, :, 3] = placement.rotation, placement.translation
        S = np.reshape(pin.getJointJacobian(model, data, j, pin.ReferenceFrame.LOCAL), (6, -1))[
            :, model.joints[j].idx_v
        ]
        linear, angular = np.linalg.norm(S[:3]), np.linalg.norm(S[3:])
        if not (abs(linear - 1.0) < 1e-12 and angular == 0.0) and not (abs(angular - 1.0) < 1e-12 and linear == 0.0):
            return None
        motions[j] = S
    return placements, motions


@laws.jit
def forward_kinematics(placements, motions, joints, q, rotations, origins, J):  # pragma: no cover - compiled
    """The joints' world rotations, origins [m] and world-frame Jacobian columns at q, into rotations, origins and J.

    Args:
        placements, motions: :func:`tree_geometry`.
        joints: per joint (parent, velocity slot), (njoints, 2) (:func:`~hipsim.closed_chain.plant_kernel.tree_constants`).
        q: the configuration [m, rad], (nq,).
        rotations, origins: out, (njoints, 3, 3) and (njoints, 3) (as Pinocchio's ``data.oMi``).
        J: out, (6, nv) (as Pinocchio's ``data.J`` after ``computeJointJacobians``).
    """
    for i in range(3):
        origins[0, i] = 0.0
        for k in range(3):
            rotations[0, i, k] = 1.0 if i == k else 0.0
    for j in range(1, joints.shape[0]):
        parent, slot = joints[j, 0], joints[j, 1]
        x = q[slot]
        u = (motions[j, 3], motions[j, 4], motions[j, 5])
        P = placements[j]
        # The joint's own motion in its parent's placement frame: rotation E about u by x, or a shift t along u.
        if u[0] != 0.0 or u[1] != 0.0 or u[2] != 0.0:
            c, s = math.cos(x), math.sin(x)
            r = 1.0 - c
            E = (
                (c + r * u[0] * u[0], r * u[0] * u[1] - s * u[2], r * u[0] * u[2] + s * u[1]),
                (r * u[1] * u[0] + s * u[2], c + r * u[1] * u[1], r * u[1] * u[2] - s * u[0]),
                (r * u[2] * u[0] - s * u[1], r * u[2] * u[1] + s * u[0], c + r * u[2] * u[2]),
            )
            t = (P[0, 3], P[1, 3], P[2, 3])
        else:
            E = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
            t = (
                P[0, 3] + x * (P[0, 0] * motions[j, 0] + P[0, 1] * motions[j, 1] + P[0, 2] * motions[j, 2]),
                P[1, 3] + x * (P[1, 0] * motions[j, 0] + P[1, 1] * motions[j, 1] + P[1, 2] * motions[j, 2]),
                P[2, 3] + x * (P[2, 0] * motions[j, 0] + P[2, 1] * motions[j, 1] + P[2, 2] * motions[j, 2]),
            )
        Rp = rotations[parent]
        for i in range(3):
            # world = parent · placement · joint motion.
            a0 = Rp[i, 0] * P[0, 0] + Rp[i, 1] * P[1, 0] + Rp[i, 2] * P[2, 0]
            a1 = Rp[i, 0] * P[0, 1] + Rp[i, 1] * P[1, 1] + Rp[i, 2] * P[2, 1]
            a2 = Rp[i, 0] * P[0, 2] + Rp[i, 1] * P[1, 2] + Rp[i, 2] * P[2, 2]
            for k in range(3):
                rotations[j, i, k] = a0 * E[0][k] + a1 * E[1][k] + a2 * E[2][k]
            origins[j, i] = origins[parent, i] + Rp[i, 0] * t[0] + Rp[i, 1] * t[1] + Rp[i, 2] * t[2]
        R = rotations[j]
        Rm = ((R[0, 0], R[0, 1], R[0, 2]), (R[1, 0], R[1, 1], R[1, 2]), (R[2, 0], R[2, 1], R[2, 2]))
        v = matvec(Rm, (motions[j, 0], motions[j, 1], motions[j, 2]))
        w = matvec(Rm, u)
        # The column's linear part at the world origin: v + ω × (0 − o) = v + o × ω.
        lin = add(v, cross((origins[j, 0], origins[j, 1], origins[j, 2]), w))
        for i in range(3):
            J[i, slot] = lin[i]
            J[3 + i, slot] = w[i]


@laws.jit
def mass_matrix(J, rotations, origins, bodies, joints, armature, composites, M):  # pragma: no cover - compiled
    """The joint-space inertia M [kg, kg·m, kg·m²] at the configuration forward_kinematics left in J, rotations, origins.

    The composite-rigid-body algorithm in world axes: each body's inertia
    about the world origin (mass m, first moment m·c, rotational inertia
    I_O = R I Rᵀ + m(|c|² 1 − c cᵀ)) summed over its subtree; a joint's
    column S_k carried by the composite gives the momentum
    (m v + ω × m c, m c × v + I_O ω), and M[i, k] is S_i's power against it
    for every joint i from k to the root. Then the armature on the diagonal.

    Args:
        J, rotations, origins: from :func:`forward_kinematics`.
        bodies, joints: :func:`~hipsim.closed_chain.plant_kernel.tree_constants`.
        armature: per velocity [kg, kg·m²], (nv,).
        composites: scratch, (njoints, 13).
        M: out, (nv, nv), both triangles.
    """
    nj = joints.shape[0]
    M[:] = 0.0  # the entries of two joints on different branches stay 0
    for j in range(1, nj):
        m = bodies[j, 0]
        if m == 0.0 and not bodies[j, 4:].any():  # a massless link (a universal joint's cross): nothing to add
            composites[j, :] = 0.0
            continue
        R = rotations[j]
        Rm = ((R[0, 0], R[0, 1], R[0, 2]), (R[1, 0], R[1, 1], R[1, 2]), (R[2, 0], R[2, 1], R[2, 2]))
        c = add((origins[j, 0], origins[j, 1], origins[j, 2]), matvec(Rm, (bodies[j, 1], bodies[j, 2], bodies[j, 3])))
        composites[j, 0] = m
        for i in range(3):
            composites[j, 1 + i] = m * c[i]
        # R I Rᵀ, then the parallel-axis shift to the world origin.
        size = c[0] * c[0] + c[1] * c[1] + c[2] * c[2]
        for i in range(3):
            for k in range(3):
                total = 0.0
                for p in range(3):
                    RI = R[i, 0] * bodies[j, 4 + 3 * 0 + p] + R[i, 1] * bodies[j, 4 + 3 * 1 + p]
                    RI += R[i, 2] * bodies[j, 4 + 3 * 2 + p]
                    total += RI * R[k, p]
                composites[j, 4 + 3 * i + k] = total + m * ((size if i == k else 0.0) - c[i] * c[k])
    for k in range(nj - 1, 0, -1):
        slot = joints[k, 1]
        v = (J[0, slot], J[1, slot], J[2, slot])
        w = (J[3, slot], J[4, slot], J[5, slot])
        m = composites[k, 0]
        mc = (composites[k, 1], composites[k, 2], composites[k, 3])
        lin = add((m * v[0], m * v[1], m * v[2]), cross(w, mc))
        I_O = (
            (composites[k, 4], composites[k, 5], composites[k, 6]),
            (composites[k, 7], composites[k, 8], composites[k, 9]),
            (composites[k, 10], composites[k, 11], composites[k, 12]),
        )
        ang = add(cross(mc, v), matvec(I_O, w))
        i = k
        while i > 0:
            column = joints[i, 1]
            value = (
                J[0, column] * lin[0]
                + J[1, column] * lin[1]
                + J[2, column] * lin[2]
                + J[3, column] * ang[0]
                + J[4, column] * ang[1]
                + J[5, column] * ang[2]
            )
            M[column, slot] = value
            M[slot, column] = value
            i = joints[i, 0]
        parent = joints[k, 0]
        if parent > 0:
            for p in range(13):
                composites[parent, p] += composites[k, p]
    for i in range(armature.size):
        M[i, i] += armature[i]

"""The Pinocchio plant's compiled RK4: a whole servo period's steps in one call, no Pinocchio call inside.

:class:`~hipsim.closed_chain.plant.PinocchioPlant`'s ``"compiled"`` route.
A derivative is the tree's forward kinematics and joint-space inertia
(:mod:`~hipsim.closed_chain.tree_kernel`, in place of ``pin.crba``), then
the closure solver (:func:`~hipsim.closed_chain.plant_kernel.constrained_acceleration`:
Newton–Euler bias forces, the closures' Jacobian and drift, the exact
constrained solve), all on arrays the plant keeps; :func:`advance` runs
``substeps`` classic RK4 steps of them, with the generalised forces of each
stage (:func:`generalised_forces`, the friction laws of
:mod:`hipsim.physics.laws`) in between. The other routes step through the
same :func:`rk4_stage` between their Pinocchio calls, so every route takes
the same RK4 arithmetic, operation for operation.
"""

from __future__ import annotations

import math
from pathlib import Path

from ..physics import laws
from . import block_inverse, closure_kernel, plant_kernel, tree_kernel
from .plant_kernel import constrained_acceleration
from .tree_kernel import forward_kinematics, mass_matrix

__all__ = ["acceleration", "advance", "generalised_forces", "rk4_stage"]

#: The kernels call these modules' kernels: their sources are part of the cache key.
_DEPENDS_ON = (
    *laws.LAW_FILES,
    # Named one by one: a module's __file__ is typed str | None, a module named in the source str.
    Path(block_inverse.__file__),
    Path(closure_kernel.__file__),
    Path(plant_kernel.__file__),
    Path(tree_kernel.__file__),
)


@laws.jit(depends_on=_DEPENDS_ON)
def generalised_forces(buf, x, tau, Fe, friction, weight, gain, platforms, sliders, lifted):
    """Sᵀ(2π/p)·τ − Q_f into buf (the closed-form path, see :mod:`~hipsim.closed_chain.plant`).

    Args:
        buf: the tree's generalised forces, written at the platforms' and sliders' entries, (nv,).
        x: state [q, v], (2·nv,).
        tau: motor torques in [N·m], (3,).
        Fe: load in [N].
        friction: the friction coefficients as a plain tuple (:func:`hipsim.physics.laws.friction_record`).
        weight: the platform's weight m_m·g in [N].
        gain: 2π/p in [1/m].
        platforms: per platform, the state slots of q_rx, q_ry, q_rz, v_rx, v_ry, v_rz, (2, 6).
        sliders: per motor, the slots of the slider's q (= its force entry) and v, (3, 2).
        lifted: the slots where the load pushes down, −F_e: with a stack-up the spline's slide under m_1's centre
            (hipsim.machine.chains), (1,); else none, (0,).
    """
    F = laws.FrictionRecord(*friction)
    for j in range(platforms.shape[0]):
        slot = platforms[j]
        c = (math.cos(x[slot[0]]), math.cos(x[slot[1]]), math.cos(x[slot[2]]))
        s = (math.sin(x[slot[0]]), math.sin(x[slot[1]]), math.sin(x[slot[2]]))
        R = laws.rotation(c, s)
        omega = laws.t_times(c, s, (x[slot[3]], x[slot[4]], x[slot[5]]))
        Q = laws.t_transpose_times(
            c, s, laws.central_friction_moment(F, omega, (R[0][2], R[1][2], R[2][2]), Fe, weight)
        )
        buf[slot[0]], buf[slot[1]], buf[slot[2]] = -Q[0], -Q[1], -Q[2]
    for i in range(sliders.shape[0]):
        rate = x[sliders[i, 1]]
        speed = gain * rate
        # Two guides per carriage; the screw's torque on the motor shaft as a carriage force.
        friction_force = 2.0 * laws.guide_friction(F, rate, speed) + gain * laws.screw_friction(F, speed)
        buf[sliders[i, 0]] = gain * tau[i] - friction_force
    for slot in lifted:
        buf[slot] = -Fe
    return buf


@laws.jit(depends_on=_DEPENDS_ON)
def rk4_stage(s, x, y, stages, a, h, buf, tau, Fe, friction, weight, gain, platforms, sliders, lifted):
    """What a classic RK4 step of h [s] does between two evaluations of the acceleration, in place.

    Stage s = 0 starts a step at x: y = x. Stages 1, 2, 3 keep the derivative
    the previous stage gave, k_s = [v, a] (v read from y, a from the last evaluation),
    and move to y = x + (h/2, h/2, h)·k_s. Then the generalised forces at y
    (:func:`generalised_forces`, under motor torques tau [N·m] and load
    Fe [N]) go into buf, for the next evaluation. s = 4 keeps k₄
    and ends the step: x += h/6·(k₁ + 2k₂ + 2k₃ + k₄). The arithmetic is
    that of :func:`hipsim.control.simulation._rk4`, operation for operation.
    """
    n = x.size
    nq = n // 2
    if s >= 1:
        for i in range(nq):
            stages[s - 1, i] = y[nq + i]
            stages[s - 1, nq + i] = a[i]
    if s == 4:
        for i in range(n):
            x[i] = x[i] + h / 6 * (stages[0, i] + 2 * stages[1, i] + 2 * stages[2, i] + stages[3, i])
        return
    if s == 0:
        y[:] = x
    else:
        step = h if s == 3 else h / 2
        for i in range(n):
            y[i] = x[i] + step * stages[s - 1, i]
    generalised_forces(buf, y, tau, Fe, friction, weight, gain, platforms, sliders, lifted)


@laws.jit(depends_on=_DEPENDS_ON)
def acceleration(y, tau, tree, scratch, a):  # pragma: no cover - compiled
    """The tree acceleration a [m/s², rad/s²] at state y = [q, v] under generalised forces tau [N, N·m], the closures held; returns |d|² [m²].

    Args:
        y: the state [q, v], (2·nv,) (every joint has one coordinate and one velocity).
        tau: the generalised forces, (nv,).
        tree: (placements, motions) of :func:`~hipsim.closed_chain.tree_kernel.tree_geometry`, the armature (nv,),
            then ``bodies, joints, closures, placements, order, blocks, settings`` as
            :func:`~hipsim.closed_chain.plant_kernel.constrained_acceleration` takes them.
        scratch: (rotations (njoints, 3, 3), origins (njoints, 3), J (6, nv), M (nv, nv), composites (njoints, 13)).
        a: out, (nv,).
    """
    frames, motions, armature, bodies, joints, closures, placements, order, blocks, settings = tree
    rotations, origins, J, M, composites = scratch
    forward_kinematics(frames, motions, joints, y[: a.size], rotations, origins, J)
    mass_matrix(J, rotations, origins, bodies, joints, armature, composites, M)
    return constrained_acceleration(
        M, J, rotations, origins, y, tau, bodies, joints, closures, placements, order, blocks, settings, a
    )


@laws.jit(depends_on=_DEPENDS_ON)
def advance(x, tau, loads, h, substeps, forces, tree, scratch, y, stages, buf, a):  # pragma: no cover - compiled
    """``substeps`` classic RK4 steps of h [s] from x, in place, under motor torques tau [N·m] (3,).

    Args:
        x: the state [q, v], (2·nv,); the result overwrites it.
        loads: the loads F_e in [N] at every half step, (2·substeps + 1,).
        forces: (friction, weight, gain, platforms, sliders, lifted) as :func:`generalised_forces` takes them.
        tree, scratch: as :func:`acceleration` takes them.
        y, stages, buf, a: work arrays: a stage's state (2·nv,), k₁ … k₄ (4, 2·nv), its generalised
            forces (nv,) (only the actuated and friction entries are written) and acceleration (nv,).
    """
    friction, weight, gain, platforms, sliders, lifted = forces
    for step in range(substeps):
        for s in range(4):
            Fe = loads[2 * step + (s + 1) // 2]
            rk4_stage(s, x, y, stages, a, h, buf, tau, Fe, friction, weight, gain, platforms, sliders, lifted)
            acceleration(y, buf, tree, scratch, a)
        rk4_stage(4, x, y, stages, a, h, buf, tau, 0.0, friction, weight, gain, platforms, sliders, lifted)

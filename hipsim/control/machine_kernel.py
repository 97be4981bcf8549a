"""The loop of :func:`hipsim.control.machine_loop.run_machine` for the Pinocchio plant on its compiled route: chunks of servo periods in one compiled call.

The same period, operation for operation, as the Python loop: the plant's
readings, the feedback (encoders through the model's forward kinematics, or
the sensor's true attitude plus its precomputed noise and drift), the model's
PD plus the feed-forward row, the limit, then the plant's RK4 steps
(:func:`hipsim.closed_chain.plant_step.advance`). A module of its own,
imported only when such a run starts, because it imports the closed-chain
package (and so Pinocchio).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..closed_chain import block_inverse, plant_kernel, plant_step, tree_kernel
from ..physics import laws
from . import chain_kernel

__all__ = ["machine_loop"]

_DEPENDS_ON = (
    *laws.LAW_FILES,
    # Named one by one: a module's __file__ is typed str | None, a module named in the source str.
    Path(chain_kernel.__file__),
    Path(block_inverse.__file__),
    Path(plant_kernel.__file__),
    Path(plant_step.__file__),
    Path(tree_kernel.__file__),
)


@laws.jit(depends_on=_DEPENDS_ON)
def machine_loop(
    stepper,
    x,
    slots,
    signs,
    sensing,
    model,
    gains,
    control,
    start,
    stop,
    desired_q,
    desired_qd,
    feedforward,
    limit,
    loads,
    h,
    substeps,
    log,
):  # pragma: no cover - compiled
    """Run servo periods ``start`` … ``stop − 1`` from the plant's state x (overwritten with the state reached).

    Args:
        stepper: the plant's compiled RK4 (:meth:`hipsim.closed_chain.plant.PinocchioPlant.compiled_stepper`).
        x: the plant's state [q, v], (2·nv,).
        slots: (slider coordinates (3,), platform coordinates (2, 3), nq): where the plant's readings sit in x.
        signs: the plant's angle signs, (3,).
        sensing: (encoders: True to read the attitude from the encoders, False for the sensor; encoder step [m];
            the sensor's offsets [rad] (n, 3); the last attitude read [rad] (3,), updated).
        model: the controller's model (:func:`hipsim.control.chain_kernel.model_arrays`) and lead [m].
        gains: (K_p, K_d), each (3,).
        control: the controlled platform's index (0, 1).
        desired_q, desired_qd: (n, 3); feedforward: (n, 3) in [N·m]; limit: [N·m].
        loads, h, substeps: as :func:`hipsim.closed_chain.plant_step.advance` takes them, for the whole run.
        log: (carriages, attitudes, rates, speeds, measured, tau, tau_requested, saturated), filled at rows k.

    Returns:
        ``stop``, or the first period whose state is not finite or whose reading has no attitude (logged up to it).
    """
    forces, tree, scratch, y, stages, buf, a = stepper
    sliders, platforms, nq = slots
    encoders, step, offsets, last = sensing
    points, offsets_c, levers, model_signs, points2, offsets2, levers2, seat, lead = model
    kp, kd = gains
    carriages, attitudes, rates, speeds, measured, tau, tau_requested, saturated = log
    width = 2 * substeps
    L, Ld = np.empty(3), np.empty(3)
    for k in range(start, stop):
        for i in range(x.size):
            if not np.isfinite(x[i]):
                return k
        for i in range(3):
            L[i] = x[sliders[i]]
            Ld[i] = x[nq + sliders[i]]
            speeds[k, i] = Ld[i]
            for j in range(2):
                attitudes[k, j, i] = signs[i] * x[platforms[j, i]]
                rates[k, j, i] = signs[i] * x[nq + platforms[j, i]]
        reading = np.rint(L / step) * step if step > 0 else L.copy()
        carriages[k] = reading
        if encoders:
            q_seen = chain_kernel.model_attitude(
                points, offsets_c, levers, model_signs, points2, offsets2, levers2, seat, reading, last
            )
            if not (np.isfinite(q_seen[0]) and np.isfinite(q_seen[1]) and np.isfinite(q_seen[2])):
                return k
            last[:] = q_seen
            qd_seen = chain_kernel.model_rates(
                points, offsets_c, levers, model_signs, points2, offsets2, levers2, seat, q_seen, Ld
            )
        else:
            q_seen = attitudes[k, control] + offsets[k]
            qd_seen = rates[k, control].copy()
        measured[k] = q_seen
        pd = chain_kernel.model_pd(
            points,
            offsets_c,
            levers,
            model_signs,
            points2,
            offsets2,
            levers2,
            seat,
            lead,
            q_seen,
            qd_seen,
            desired_q[k],
            desired_qd[k],
            kp,
            kd,
        )
        over = False
        for i in range(3):
            wanted = feedforward[k, i] + pd[i]
            tau_requested[k, i] = wanted
            tau[k, i] = min(max(wanted, -limit), limit)
            over = over or abs(wanted) > limit
        saturated[k] = over
        plant_step.advance(
            x, tau[k], loads[width * k : width * (k + 1) + 1], h, substeps, forces, tree, scratch, y, stages, buf, a
        )
    return stop

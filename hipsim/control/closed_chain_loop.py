"""The servo loop of :func:`hipsim.control.simulate` for the Pinocchio plant on its compiled route: chunks of servo periods in one compiled call.

Why this module exists. With the plant's RK4 steps compiled whole
(:func:`hipsim.closed_chain.plant_step.advance`), what was left of a servo
period in Python (the call into the compiled control, the plant's
``advance`` with its checks, and the unboxing of some twenty arrays twice a
period) cost a third of the period. Here the period is
:func:`~hipsim.control.servo_kernel.control_period` (the same compiled
control as every compiled loop's) then the plant's steps, both compiled,
for a chunk of periods at a time: the same arithmetic, operation for
operation, as the loop in :mod:`hipsim.control.simulation` around
:meth:`~hipsim.closed_chain.plant.PinocchioPlant.advance`.

A module of its own, imported only when such a run starts, because it
imports the closed-chain package (and so Pinocchio), which the reduced
plant's compiled loop does not need.
"""

from __future__ import annotations

from pathlib import Path

from ..analytic import kernel
from ..closed_chain import block_inverse, closure_kernel, plant_kernel, plant_step, tree_kernel
from ..physics import laws
from . import servo_kernel
from .servo_kernel import control_period

__all__ = ["stepped_loop"]

_DEPENDS_ON = (
    *laws.LAW_FILES,
    # Named one by one: a module's __file__ is typed str | None, a module named in the source str.
    Path(kernel.__file__),
    Path(servo_kernel.__file__),
    Path(block_inverse.__file__),
    Path(closure_kernel.__file__),
    Path(plant_kernel.__file__),
    Path(plant_step.__file__),
    Path(tree_kernel.__file__),
)


@laws.jit(depends_on=_DEPENDS_ON)
def stepped_loop(
    stepper,
    x,
    angle_slots,
    rate_slots,
    signs,
    control,
    start,
    stop,
    desired_q,
    desired_qd,
    kp,
    kd,
    feedforward,
    rows,
    with_feedforward,
    limit,
    loads,
    h,
    substeps,
    q,
    qd,
    tau,
    tau_requested,
    saturated,
):  # pragma: no cover - compiled
    """Run servo periods ``start`` … ``stop − 1`` from the plant's state x (overwritten with the state reached).

    Args:
        stepper: the plant's compiled RK4 (:meth:`hipsim.closed_chain.plant.PinocchioPlant.compiled_stepper`):
            ``forces, tree, scratch, y, stages, buf, a`` as :func:`hipsim.closed_chain.plant_step.advance` takes them.
        x: the plant's state [q, v], (2·nv,).
        angle_slots, rate_slots, signs, control: as :func:`~hipsim.control.servo_kernel.control_period` takes them.
        The others: as :func:`~hipsim.control.servo_kernel.servo_loop` takes them.

    Returns:
        ``stop``, or the first period whose state is not finite (nothing logged from there on).
    """
    forces, tree, scratch, y, stages, buf, a = stepper
    step = 2 * substeps
    for k in range(start, stop):
        if not control_period(
            x,
            angle_slots,
            rate_slots,
            signs,
            control,
            k,
            desired_q,
            desired_qd,
            kp,
            kd,
            feedforward,
            rows,
            with_feedforward,
            limit,
            q,
            qd,
            tau,
            tau_requested,
            saturated,
        ):
            return k
        plant_step.advance(
            x, tau[k], loads[step * k : step * (k + 1) + 1], h, substeps, forces, tree, scratch, y, stages, buf, a
        )
    return stop

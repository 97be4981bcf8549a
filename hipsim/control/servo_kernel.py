"""The servo loop of :func:`hipsim.control.simulate`, compiled for hipsim's own controllers on the reduced plant.

Why this module exists. With the reduced plant's dynamics compiled
(:mod:`hipsim.analytic.kernel`), what was left of a servo period in Python —
the controller call, the zero-order hold, the saturation, the logging and
two crossings into the compiled code, each unboxing the machine's parameters
— cost about as much again as the two RK4 steps themselves. When the
controller is a :class:`~hipsim.control.controllers.WorkspacePD` or an
:class:`~hipsim.control.controllers.AugmentedPD` (whose feed-forward is a
table computed before the run), the whole loop is known in advance and runs
here in one compiled call per chunk of servo periods.

A plant that is integrated outside this module (the Pinocchio plant, whose
steps are Pinocchio's) still gets the control compiled: :func:`control_period`
does one servo period's logging, control law, clipping and counting in one
call, and the plant's ``advance`` does the rest.

It is the same loop, step for step, as the Python one in
:mod:`hipsim.control.simulation`: the same compiled control law
(:func:`hipsim.analytic.kernel._workspace_pd`) and RK4 steps
(:func:`hipsim.analytic.kernel._advance`), the same clipping and counting, so
the two give the same trajectories to round-off (``tests/control/test_simulation.py``
compares them).

Its numba cache is keyed on the kernel's and the laws' files too: the machine
code absorbs them (see :func:`hipsim.physics.laws.jit`).
"""

from __future__ import annotations

import math
from pathlib import Path

from ..analytic import kernel
from ..physics import laws

__all__ = ["control_period", "servo_loop"]


_DEPENDS_ON = (*laws.LAW_FILES, Path(kernel.__file__))


@laws.jit(depends_on=_DEPENDS_ON)
def servo_loop(
    plant,
    control,
    x,
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
):
    """Run servo periods ``start`` … ``stop − 1`` from state x, logging into the given arrays.

    Args:
        plant: the plant's machine (:func:`hipsim.analytic.kernel.kernel_parameters`).
        control: the controller's machine.
        x: state [q, q̇] at period ``start`` in [rad], [rad/s], (6,); overwritten with the state reached.
        start, stop: the servo periods to run.
        desired_q, desired_qd: desired angles [rad] and rates [rad/s] at every servo instant, (K, 3).
        kp: K_p per angle in [N·m/rad], (3,).
        kd: K_d per angle in [N·m·s/rad], (3,).
        feedforward: feed-forward torques in [N·m], (M, 3), read when ``with_feedforward``.
        rows: the feed-forward row of each period, (K,).
        with_feedforward: add the feed-forward (augmented PD) or not (workspace PD).
        limit: motor torque limit in [N·m] (inf: none).
        loads: the load F_e in [N] at every RK4 half step of the run, (2·substeps·K + 1,).
        h: RK4 step in [s].
        substeps: RK4 steps per servo period.
        q, qd: logged angles [rad] and rates [rad/s], (K, 3).
        tau, tau_requested: logged applied and requested torques in [N·m], (K, 3).
        saturated: logged saturation flags, (K,).

    Returns:
        ``stop``, or the first period whose state is not finite (nothing logged from there on).
    """
    y = (x[0], x[1], x[2], x[3], x[4], x[5])
    for k in range(start, stop):
        for i in range(3):
            q[k, i], qd[k, i] = y[i], y[3 + i]
        for i in range(6):
            if not math.isfinite(y[i]):
                for j in range(6):
                    x[j] = y[j]
                return k
        _control(
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
        )
        y = kernel._advance(plant, y, (tau[k, 0], tau[k, 1], tau[k, 2]), loads, 2 * substeps * k, h, substeps)
    for j in range(6):
        x[j] = y[j]
    return stop


@laws.jit(depends_on=_DEPENDS_ON)
def control_period(
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
    """Servo period k of a plant integrated outside this module (the Pinocchio plant): the same control as :func:`servo_loop`'s.

    Logs the measured angles q[k] = signs·x[angle_slots], in [rad], and rates
    qd[k] = signs·x[rate_slots], in [rad/s], then the torques. ``control`` is the
    controller's machine as :func:`hipsim.analytic.kernel.plain_parameters`
    gives it (called once a period: a named tuple would cost 2 µs more to
    pass); the other arguments are :func:`servo_loop`'s.

    Returns:
        False, logging nothing, when the state x is not finite.
    """
    for i in range(x.size):
        if not math.isfinite(x[i]):
            return False
    for i in range(3):
        q[k, i], qd[k, i] = signs[i] * x[angle_slots[i]], signs[i] * x[rate_slots[i]]
    _control(
        kernel.named_parameters(control),
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
    )
    return True


@laws.jit(depends_on=_DEPENDS_ON)
def _control(
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
    """The built-in controllers' torques at period k from the logged state q[k], qd[k], clipped to the limit and logged."""
    wanted = kernel._workspace_pd(
        control,
        (q[k, 0], q[k, 1], q[k, 2]),
        (qd[k, 0], qd[k, 1], qd[k, 2]),
        (desired_q[k, 0], desired_q[k, 1], desired_q[k, 2]),
        (desired_qd[k, 0], desired_qd[k, 1], desired_qd[k, 2]),
        (kp[0], kp[1], kp[2]),
        (kd[0], kd[1], kd[2]),
    )
    if with_feedforward:
        row = rows[k]
        wanted = (feedforward[row, 0] + wanted[0], feedforward[row, 1] + wanted[1], feedforward[row, 2] + wanted[2])
    saturated[k] = False
    for i in range(3):
        tau_requested[k, i] = wanted[i]
        # Written out so that NaN passes through, as through np.clip.
        tau[k, i] = -limit if wanted[i] < -limit else (limit if wanted[i] > limit else wanted[i])
        if abs(wanted[i]) > limit:
            saturated[k] = True

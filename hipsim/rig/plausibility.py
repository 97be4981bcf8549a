"""Plausibility of a rig log: each measured signal against what the machine can produce along the logged motion.

A unit slip in a log (torques in N·m under ``tau_i_Nmm``, the load in kN
under ``Fe_N``, radians under ``_deg``, a torque constant in N·mm/A) reads
as valid numbers, and a fit or a comparison on it gives a result that looks
like one. :func:`check_log` looks before any fit or comparison:

- the load's peak against a hip simulator's test loads (ISO 14242-1: 300 to
  3000 N, :data:`LOAD_PEAK_N`);
- the angles' ranges against a gait cycle's (a range of a degree or two
  that is a plausible cycle when read as radians is radians);
- each motor's RMS torque (or current × torque constant) against the
  model's along the logged motion and load, with the starting parameters.

A factor of about 1000 (or 57 for angles) is an error naming the column, the
factor and the unit it looks like; a factor beyond :data:`ERROR_FACTOR` is an
error too, one beyond :data:`WARNING_FACTOR` a warning (returned, one line
each). The check runs on the log's first window (:meth:`Log.windows`: the
first :data:`~hipsim.rig.logs.log.PIECE` samples of a log read in pieces), the
model on at most :data:`MODEL_SAMPLES` of them: a fraction of a second.
"""

from __future__ import annotations

import math

import numpy as np

from ..analytic.engine import AnalyticModel
from ..exceptions import PoseError, TrajectoryError
from ..machine.parameters import Parameters
from ..motion.trajectories import ANGLE_NAMES
from ..plausibility import ANGLE_RANGE_DEG, LOAD_PEAK_N, LOAD_WARNING_N, SMALL_RANGE_DEG, radians_slip
from .logs.log import Log
from .logs.reader import CURRENT_COLUMNS, TORQUE_COLUMNS

__all__ = [
    "ANGLE_RANGE_DEG",
    "CONSTANT_FACTOR",
    "ERROR_FACTOR",
    "LOAD_PEAK_N",
    "LOAD_WARNING_N",
    "MODEL_SAMPLES",
    "SMALL_RANGE_DEG",
    "WARNING_FACTOR",
    "check_log",
    "constant_factor",
    "far_from_priors",
]

#: Measured RMS torque against the model's: beyond this factor either way an error, beyond :data:`WARNING_FACTOR` a warning.
ERROR_FACTOR = 30.0
WARNING_FACTOR = 3.0
#: Three motors' factors within this relative spread of their median are one constant factor (a ratio, a unit) ...
CONSTANT_SPREAD = 0.15
#: ... named when it is beyond this either way (a 2:1 belt, a gear ratio; the model's own error is well within it).
CONSTANT_FACTOR = 1.5
#: An identified base parameter this many prior standard deviations from its prior has moved far ...
FAR_SHIFT = 3.0
#: ... and this many of them, all in one direction, are one cause rather than the machine's own spread.
FAR_COUNT = 2
#: Most samples of the first window the model runs on (every k-th).
MODEL_SAMPLES = 4000

_DEG_PER_RAD = 180.0 / math.pi


def check_log(params: Parameters, log: Log, lever_spin: bool = True, torque_constant: float | None = None) -> list[str]:
    """Check a log's load, angles and torques against the machine; raise on a unit slip, return the warnings.

    Args:
        params: the machine (the starting parameters of a fit).
        log: the log (:class:`~hipsim.rig.logs.log.LogPieces` names its columns and units;
            a :class:`~hipsim.rig.logs.log.MeasuredLog` built from arrays is checked by its values).
        lever_spin: as in :class:`hipsim.analytic.AnalyticModel`.
        torque_constant: the motors' torque constant in [N·m/A] the log's currents were turned into torques with, for messages
            (None: the log's own, when it knows it).

    Returns:
        One line per milder implausibility (a factor of :data:`WARNING_FACTOR` to :data:`ERROR_FACTOR`).

    Raises:
        TrajectoryError: naming the log and column: a factor of about 1000
            (or 57 for angles), or beyond :data:`ERROR_FACTOR`.
    """
    window, core, _ = next(iter(log.windows()))
    usable = log.usable  # the first window starts at the log's first sample: its indices are the log's
    part = slice(max(core.start, usable.start), min(core.stop, usable.stop))
    if part.stop - part.start < 2:
        return []
    trajectory = window.trajectory.slice(part)
    measured = window.tau[part]
    raw = getattr(log, "raw", None)  # the file's layout, for a log read from its file
    source = getattr(raw, "source", None) or log.name
    warnings = []
    warnings += _check_load(trajectory.Fe, source)
    if raw is not None and log.motion_from == "angles" and raw.angle_unit == "deg":
        _check_angles(np.degrees(trajectory.q), source)
    torque_from = getattr(raw, "torque_from", "torques")
    if torque_from == "currents" and torque_constant is None:
        torque_constant = getattr(raw, "torque_constant", None)
    warnings += _check_torques(params, trajectory, measured, lever_spin, source, torque_from, torque_constant)
    return warnings


def _check_load(load: np.ndarray, source: str) -> list[str]:
    peak = float(np.max(load)) if load.size else 0.0
    low, high = LOAD_PEAK_N
    if peak < LOAD_WARNING_N:
        if low <= peak * 1e3 <= high:
            raise TrajectoryError(
                f"Fe_N looks like kN: its peak is {peak:.4g}, 1/1000 of a hip simulator's test loads "
                f"(ISO 14242-1: {low:g} to 3000 N); give the load in N",
                source=source,
            )
        return [
            f"{source}: Fe_N peaks at {peak:.4g} N, far below a hip simulator's test loads (ISO 14242-1: {low:g} to 3000 N): "
            "is it in N?"
        ]
    return []


def _check_angles(degrees: np.ndarray, source: str) -> None:
    ranges = np.ptp(degrees, axis=0) if len(degrees) else np.zeros(3)
    k = int(np.argmax(ranges))
    as_radians = ranges[k] * _DEG_PER_RAD
    if radians_slip(ranges) is not None:
        raise TrajectoryError(
            f"{ANGLE_NAMES[k]}_deg looks like radians: its range is {ranges[k]:.3g}°, 1/57 of a gait cycle's "
            f"({as_radians:.3g}° if read as radians); label the angle columns _rad",
            source=source,
        )


def _slip(factor: float) -> float | None:
    """1000 or 1/1000 when ``factor`` is within a factor 2 of it, else None."""
    for slip in (1e3, 1e-3):
        if slip / 2 <= factor <= slip * 2:
            return slip
    return None


def _check_torques(params, trajectory, measured, lever_spin, source, torque_from, torque_constant) -> list[str]:
    stride = max(1, -(-len(trajectory) // MODEL_SAMPLES))
    try:
        run = AnalyticModel(params, lever_spin=lever_spin).run(trajectory.slice(slice(None, None, stride)))
    except PoseError:
        return []  # the comparison or fit names the pose and its line
    model = np.sqrt(np.nanmean(run.torques.total**2, axis=0))
    logged = np.sqrt(np.mean(measured[::stride] ** 2, axis=0))
    columns = CURRENT_COLUMNS if torque_from == "currents" else TORQUE_COLUMNS
    errors: dict[float | None, list[int]] = {}  # by the unit slip's factor, None for none
    warnings = []
    for i in range(3):
        if not (model[i] > 1e-6 and np.isfinite(model[i])):  # a motor the model says is idle: nothing to compare with
            continue
        factor = float(logged[i] / model[i])
        slip = _slip(factor)
        if slip is not None or not 1 / ERROR_FACTOR < factor < ERROR_FACTOR:
            errors.setdefault(slip, []).append(i)  # None: no unit's factor
        elif not 1 / WARNING_FACTOR < factor < WARNING_FACTOR:
            warnings.append(
                f"{source}: {columns[i]}: {_ratio(factor)} the model's with these parameters "
                f"({logged[i] * 1e3:.4g} against {model[i] * 1e3:.4g} N·mm): check its unit and the machine's parameters"
            )
    if not errors:
        common = constant_factor(logged / np.where(model > 1e-6, model, np.nan))
        if common is not None:  # one line naming the common factor, in place of one per motor
            return [
                f"{source}: {', '.join(columns)}: all three {_ratio(common)} the model's with these parameters (a constant "
                f"factor of {common:.3g}): a transmission ratio not in the parameters (a belt, a gearbox), a unit, or "
                "another machine; a fit on this log moves every parameter to absorb it"
            ]
        return warnings
    slip, motors = next(iter(errors.items()))
    names = ", ".join(columns[i] for i in motors)
    verb = "looks" if len(motors) == 1 else "look"
    i = motors[0]
    factor = slip if slip is not None else float(logged[i] / model[i])
    numbers = f"({logged[i] * 1e3:.4g} against {model[i] * 1e3:.4g} N·mm)"
    if torque_from == "currents":
        constant = f" {torque_constant:g} N·m/A" if torque_constant else ""
        if slip == 1e3:
            hint = (
                f": the torque constant looks like N·mm/A (give --torque-constant in N·m/A{f', {torque_constant / 1e3:g}' if torque_constant else ''}), "
                "or the currents like mA"
            )
        elif slip == 1e-3:
            hint = ": the torque constant looks like kN·m/A, or the currents like kA (give --torque-constant in N·m/A, currents in A)"
        else:
            hint = ": check --torque-constant (N·m/A) and the currents' unit (A)"
        message = f"{names} × --torque-constant{constant} {'gives' if len(motors) == 1 else 'give'} {_ratio(factor)} the model's torque {numbers}{hint}"
    elif slip == 1e-3:
        message = f"{names} {verb} like N·m: {'its' if len(motors) == 1 else 'their'} RMS is 1/1000 of the model's {numbers}; give torques in N·mm"
    elif slip == 1e3:
        message = f"{names} {verb} like µN·m: {'its' if len(motors) == 1 else 'their'} RMS is 1000 times the model's {numbers}; give torques in N·mm"
    else:
        message = (
            f"{names}: RMS {_ratio(factor)} the model's {numbers}: check the unit (N·mm), the load's (N) and the machine's "
            "parameters (--no-plausibility-check if the log is right)"
        )
    raise TrajectoryError(message, source=source)


def constant_factor(factors: np.ndarray) -> float | None:
    """The factor all three motors share (measured RMS over the model's), when it is one and beyond :data:`CONSTANT_FACTOR`; else None.

    Args:
        factors: per motor, measured RMS torque / model RMS torque, (3,) (NaN for a motor the model says is idle).
    """
    factors = np.asarray(factors, dtype=float)
    factors = factors[np.isfinite(factors) & (factors > 0)]
    if factors.size < 2:
        return None
    common = float(np.median(factors))
    if np.max(np.abs(factors / common - 1.0)) > CONSTANT_SPREAD:
        return None
    if 1.0 / CONSTANT_FACTOR < common < CONSTANT_FACTOR:
        return None
    return common


def far_from_priors(estimates) -> list[str]:
    """A warning when several identified base parameters moved beyond :data:`FAR_SHIFT` prior standard deviations, all one way.

    A machine's parameters differ from the published ones each its own way; all of them moving far in one
    direction is one cause scaling the torques: a transmission ratio the parameters do not have (a belt,
    a gearbox), a unit, or the logs of another machine.

    Args:
        estimates: the identification's base parameters (:class:`hipsim.rig.identification.BaseEstimate`:
            ``name``, ``shift`` in prior standard deviations, ``determined``).

    Returns:
        One line, or nothing.
    """
    far = [e for e in estimates if e.determined and abs(e.shift) > FAR_SHIFT]
    if len(far) < FAR_COUNT:
        return []
    signs = {e.shift > 0 for e in far}
    if len(signs) != 1:
        return []
    moved = ", ".join(f"{e.name} {e.shift:+.2g}" for e in sorted(far, key=lambda e: -abs(e.shift)))
    way = "up" if signs == {True} else "down"
    return [
        f"{len(far)} of {len(estimates)} base parameters moved more than {FAR_SHIFT:g} prior standard deviations, all {way} "
        f"({moved}): one cause scales the logged torques; a transmission ratio not in the parameters (a belt, a gearbox), "
        "a unit, or another machine's logs; check it before using the identified file"
    ]


def _ratio(factor: float) -> str:
    """'1000 times' or '1/1000 of'."""
    if factor >= 1:
        return f"{factor:.4g} times"
    return f"1/{1 / factor:.4g} of"

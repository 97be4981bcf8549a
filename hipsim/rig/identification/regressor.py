"""The identification regressor: motor torque τ = Y(q, q̇, q̈, F_e)·θ, and its rows along a log.

The analytic inverse dynamics (spec §4) is linear in the inertial parameters
of each body group and in the friction coefficients, θ the
:data:`~hipsim.rig.identification.quantities.QUANTITIES`. :func:`regressor` builds Y from that
linearity: the inverse dynamics of a machine whose parameters are all zero
but one, set to one, is that parameter's column. Each body group lands in its
own torque part (spec §4.4), so a column is that part alone
(:data:`hipsim.analytic.virtual_work.PARTS`) of its machine, evaluated on the
motion's terms (:func:`hipsim.analytic.virtual_work.motion_terms`: the
lever's spin, body components, J⁻ᵀ), which are the same for every column and
computed once, :data:`BLOCK` samples at a time so that the arithmetic runs in
the processor's cache. The numbers are those of the full inverse dynamics of
the ten machines that carry one parameter of every group each
(:func:`_regressor_by_unit_machines`, kept as the reference a test holds the
columns to, bit for bit). The levers' centre of mass stays at mid-length, as the
model has it; the hip-joint and thrust-bearing Coulomb terms scale with the
load, the screw and guide terms with the motor speed, the lever-joint terms
with their relative angular speeds, each through the same friction law the
model uses (the friction coefficient is what is identified; radii, the
platform mass and the smooth sign's ε are kept). The friction columns come
from one function, :func:`~hipsim.rig.identification.quantities.friction_unit`, so a
different bearing law changes them there and nowhere else.

Rows of a log (:func:`log_rows`): the regressor along the log's motion,
low-passed like the log and kept every D-th sample (decimation to four times
the cutoff), the samples around each motor's reversals
(:func:`~hipsim.rig.logs.reversals.reversal_mask`) marked out of that motor's rows,
chunk by chunk and window by window, so memory does not grow with the log.
"""

from __future__ import annotations

import math
from collections.abc import Iterator

import numpy as np

from ...analytic.inverse_kinematics import kinematics
from ...analytic.virtual_work import PARTS, inverse_dynamics, motion_terms
from ...machine.parameters import Parameters
from ...motion.trajectories import Trajectory
from ..logs.log import Log, MeasuredLog
from ..logs.reversals import reversal_mask
from ..logs.smoothing import lowpass, minimum_samples
from .quantities import FRICTION, QUANTITIES, friction_unit, with_values

__all__ = [
    "BLOCK",
    "CHUNK",
    "MODEL_ERROR_BANDWIDTH",
    "column_condition",
    "decimation",
    "inflation",
    "log_rows",
    "regressor",
    "regressor_from_kinematics",
    "rows_per_independent_row",
]


def column_condition(A: np.ndarray) -> float:
    """The condition number σ_max/σ_min of A (rows, k) with its columns scaled to unit norm, as identification judges it.

    Infinite when a column is zero or σ_min is exactly 0; dependent columns give σ_min of round-off and so a
    number of 1e15 and more: either way those values cannot be told apart.
    The excitations' design, the identification's report and the stations' calibration all use this one measure.
    """
    norms = np.linalg.norm(A, axis=0)
    if A.size == 0 or np.any(norms == 0):
        return math.inf
    s = np.linalg.svd(A / norms, compute_uv=False)
    return float(s[0] / s[-1]) if s[-1] > 0 else math.inf


#: Samples per chunk of the regressor (memory: ~2 kB per sample while a chunk is computed and filtered).
CHUNK = 50_000
#: Samples per block of the regressor's arithmetic: its working arrays (up to 9 numbers a sample, 0.6 MB) then stay
#: near the core; at a chunk's 50,000 samples they spill to memory and the same arithmetic runs 2-3x slower (CPU time
#: of a chunk's columns, 27 Nov, loaded machine: 1,024 samples 270 ms, 4,096 172 ms, 8,192 142-166 ms, 16,384 151 ms).
BLOCK = 8192
#: The bandwidth in [Hz] of the model error a residual carries besides the noise (sticking at reversals, the torque
#: sensor's timing, the motion's own harmonics): rows closer than 1/(2·this) are not independent evidence of it.
MODEL_ERROR_BANDWIDTH = 10.0


def _unit_machines(params: Parameters) -> list[tuple[Parameters, dict[str, int]]]:
    """Ten machines, each with one parameter per body group set to one, and where each part's column goes.

    Machine s has the s-th parameter of each torque part (:attr:`Quantity.part`) at one, every other at zero.
    """
    members: dict[str, list[int]] = {}
    for k, quantity in enumerate(QUANTITIES):
        members.setdefault(quantity.part, []).append(k)
    friction = members.pop("friction")
    machines = []
    for s in range(max(len(group) for group in (friction, *members.values()))):
        theta = np.zeros(len(QUANTITIES))
        columns: dict[str, int] = {}
        for part, group in members.items():
            if s < len(group):
                theta[group[s]] = 1.0
                columns[part] = group[s]
        machine = with_values(params, theta)
        if s < len(friction):
            machine = friction_unit(machine, FRICTION[s].name)
            columns["friction"] = friction[s]
        machines.append((machine, columns))
    return machines


def _column_machines(params: Parameters) -> list[tuple[str, Parameters]]:
    """Per column of Y: its torque part and the machine whose only dynamic parameter is that column's, at one."""
    zero = with_values(params, np.zeros(len(QUANTITIES)))
    machines = []
    for k, quantity in enumerate(QUANTITIES):
        if quantity.part == "friction":
            machines.append((quantity.part, friction_unit(zero, quantity.name)))
        else:
            machines.append((quantity.part, with_values(params, np.eye(len(QUANTITIES))[k])))
    return machines


def _regressor_by_unit_machines(params: Parameters, kin, Fe: np.ndarray, lever_spin: bool = True) -> np.ndarray:
    """Y, (N, 3, P), from the full inverse dynamics of the ten unit machines: the reference route the fast one equals."""
    Y = np.zeros((len(kin), 3, len(QUANTITIES)))
    for machine, columns in _unit_machines(params):
        torques = inverse_dynamics(machine, kin, Fe, lever_spin)
        for part, k in columns.items():
            Y[:, :, k] = getattr(torques, part)
    return Y


def _regressor_columns(
    params: Parameters, kin, Fe: np.ndarray, lever_spin: bool = True, machines=None, block: int = BLOCK
) -> np.ndarray:
    """Y components first, (P, 3, N): column k is part ``QUANTITIES[k].part`` of its machine, block by block.

    ``machines``: :func:`_column_machines` of ``params``, if already made.
    """
    machines = _column_machines(params) if machines is None else machines
    n = len(kin)
    Y = np.empty((len(machines), 3, n))
    for a in range(0, n, block):
        terms = motion_terms(params, kin, Fe, lever_spin, slice(a, a + block))
        for k, (name, machine) in enumerate(machines):
            Y[k, :, a : a + block] = PARTS[name](machine, terms)
    return Y


def regressor(params: Parameters, trajectory: Trajectory, lever_spin: bool = True) -> np.ndarray:
    """Y with motor torque τ = Y·θ along a trajectory (θ: :func:`standard_values`).

    Args:
        params: the machine (its geometry, friction radii, ε and platform mass
            are used; its dynamic parameters are not).
        trajectory: the motion and load, N samples.
        lever_spin: as in :func:`hipsim.analytic.inverse_dynamics`.

    Returns:
        Y in [N·m per SI unit of each parameter], (N, 3, P).

    Raises:
        PoseError: naming the time of a pose out of reach or singular.
    """
    return regressor_from_kinematics(params, kinematics(params, trajectory), trajectory.Fe, lever_spin)


def regressor_from_kinematics(params: Parameters, kin, Fe: np.ndarray, lever_spin: bool = True) -> np.ndarray:
    """:func:`regressor` from kinematics already computed (:func:`hipsim.analytic.kinematics`) and the load in [N], (N,)."""
    return np.ascontiguousarray(_regressor_columns(params, kin, Fe, lever_spin).transpose(2, 1, 0))


def decimation(log: Log) -> int:
    """Keep every D-th sample after the low-pass: four samples per period of the cutoff."""
    return 1 if log.cutoff is None else max(1, int(log.rate // (4.0 * log.cutoff)))


def inflation(log: Log) -> float:
    """Samples per independent sample after the low-pass and decimation (1 without a filter)."""
    if log.cutoff is None:
        return 1.0
    return max(1.0, log.rate / decimation(log) / (2.0 * log.cutoff))


def rows_per_independent_row(log: Log) -> float:
    """Rows per independent row of a log: the low-pass's ratio (:func:`inflation`), and at least the model error's.

    The floor every estimate from a log's rows divides its information by (identification, the monitor): the rows
    kept per second over twice the bandwidth of the model error (:data:`MODEL_ERROR_BANDWIDTH`, or the cutoff when
    that is lower), 4.2 at 1 kHz and a 20 Hz cutoff. The residual's autocorrelation cannot show the model error's
    share: the part of it in the regressor's span is absorbed by the fit, biasing the parameters without leaving a
    trace (measured on synthetic logs: a held-out prediction's 95 % band covered 88 % of the true torque with the
    filter's ratio alone, 98 % with this).

    Args:
        log: the log (its rate in [Hz] and cutoff in [Hz] are used).

    Returns:
        Rows per independent row, ≥ 1.
    """
    rate = log.rate / decimation(log)  # the rows kept per second
    bandwidth = MODEL_ERROR_BANDWIDTH if log.cutoff is None else min(log.cutoff, MODEL_ERROR_BANDWIDTH)
    return max(inflation(log), rate / (2.0 * bandwidth))


def _rows(
    params: Parameters, log: MeasuredLog, lever_spin: bool, chunk: int = CHUNK, span: tuple[int, int, int] | None = None
):
    """The log's regressor rows and torques, low-passed like the log and decimated, chunk by chunk.

    Args:
        span: (first, stop, origin): the rows of samples ``first`` … ``stop``−1
            a whole number of decimation steps after sample ``origin`` (a piece
            of a log: origin is where the whole log's usable samples start);
            None for the log's usable samples.

    Yields:
        Y (m, 3, P), τ (m, 3) and the rows to use per motor (m, 3) bool (False near that motor's reversals).
    """
    n = len(log)
    first, stop, origin = span if span is not None else (log.usable.start, log.usable.stop, log.usable.start)
    step = decimation(log)
    first += (origin - first) % step  # the first kept sample
    margin = 0 if log.cutoff is None else minimum_samples(log.rate, log.cutoff)
    trajectory = log.trajectory
    use = ~reversal_mask(params, log)
    machines = _column_machines(params)
    chunk = max(step, chunk - chunk % step)  # whole decimation steps, so the kept samples line up across chunks
    for a in range(first, stop, chunk):
        b = min(a + chunk, stop)
        lo, hi = max(0, a - margin), min(n, b + margin)
        piece = trajectory.slice(slice(lo, hi))
        Y = _regressor_columns(params, kinematics(params, piece), piece.Fe, lever_spin, machines)
        if log.cutoff is not None:
            # The filter's transient from the chunk's own ends dies out within the margin. Along the last axis,
            # each column's signal is contiguous (the same numbers as along the first axis of (N, 3, P), faster).
            Y = lowpass(Y, log.rate, log.cutoff, log.name, axis=-1)
        keep = np.arange(a, b, step)
        yield Y[:, :, keep - lo].transpose(2, 1, 0), log.tau[keep], use[keep]


def log_rows(params: Parameters, log: Log, lever_spin: bool) -> Iterator[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """:func:`_rows` of a log window by window (a log in memory is one window: the same rows, to round-off, either way)."""
    usable = log.usable
    for window, core, start in log.windows():
        first, stop = max(start, usable.start), min(start + core.stop - core.start, usable.stop)
        if first < stop:
            shift = core.start - start  # window index of a log index
            yield from _rows(params, window, lever_spin, span=(first + shift, stop + shift, usable.start + shift))

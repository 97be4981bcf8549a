"""From a table's numbers to a Trajectory: the steps every trajectory reader ends in (:func:`build_trajectory`).

A format's reader (:mod:`hipsim.motion.csv_table`, :mod:`hipsim.motion.parquet`,
:mod:`hipsim.motion.opensim`) hands over a :class:`Table`: the file's numbers
in their own units, with the file's line of each row. Then:

1. units to SI: time in s, ms or % of the cycle; angles in degrees or
   radians; the load in N, kN or % of body weight; a column's sign flipped
   on request;
2. the ISB hip joint chain (flexion, adduction, internal rotation) turned
   into the platform angles α, β, γ when the file gives the hip's angles
   (:mod:`hipsim.motion.hip_angles`);
3. time rescaled when a cycle frequency or period is asked for (the file is
   taken to hold one cycle, so its derivatives scale with it);
4. onto an even time grid when resampling is asked for; otherwise the times
   must be evenly spaced already (:func:`check_time`);
5. the load from a second file when one is given (:mod:`hipsim.motion.load_file`:
   interpolated onto the motion's times, which are cut to the overlap);
6. a zero-phase low-pass of the angles when a cutoff is asked for
   (:func:`hipsim.motion.filtering.lowpass_record`: wrapped around for a
   periodic file, odd extensions at the ends otherwise; the load, which is
   not differentiated, is not filtered); without one, a check of the
   differentiated motion for measurement noise
   (:mod:`hipsim.motion.noise_check`) that warns with the cutoff to use;
7. derivatives from an interpolating quintic spline (periodic when the last
   row repeats the first, which is then dropped), evaluated whole or a piece
   at a time (:class:`SampledMotion`).

Every problem is reported on one line naming the file, its line and column.

Derivative accuracy, measured on the ISO cycle written to CSV and read back
(``tests/motion/test_build.py``), relative to each angle's peak: at 1 kHz the
velocity is exact to 2e-13 and the acceleration to 1e-10 (round-off
dominates), 1e-12 and 1e-9 near the ends of a non-periodic file; at 200 Hz
the acceleration is exact to 1.4e-9 inside and 5e-7 near the ends of a
non-periodic file.
"""

from __future__ import annotations

import math
import warnings
from dataclasses import dataclass
from typing import Literal, Unpack, overload

import numpy as np
from scipy.interpolate import make_interp_spline

from ..exceptions import TrajectoryError
from ..plausibility import epoch_warning, load_slip, one_radians_slip, radians_slip, time_slip
from .columns import ColumnMap, stated_unit
from .filtering import lowpass_record
from .hip_angles import hip_to_machine
from .noise_check import check_noise
from .read_options import BuildOptions, check_options
from .trajectories import MIN_SAMPLES, Trajectory

__all__ = [
    "MAX_LOAD",
    "NoLoadWarning",
    "NoiseWarning",
    "SampledMotion",
    "Table",
    "TrajectoryWarning",
    "build_trajectory",
    "check_time",
    "check_time_unit",
    "relative_time",
]

#: Largest load a trajectory file may give, in [N]: far above any hip simulator, so only a unit slip reaches it.
MAX_LOAD = 1e9


class TrajectoryWarning(UserWarning):
    """A trajectory file that reads, but looks wrong (e.g. radians under a degree header)."""


class NoLoadWarning(TrajectoryWarning):
    """A trajectory with no load: F_e = 0, so the load's friction is missing from its torques."""


class NoiseWarning(TrajectoryWarning):
    """A trajectory whose angles carry measurement noise that differentiation amplifies (:mod:`hipsim.motion.noise_check`)."""


@dataclass(frozen=True, eq=False)
class Table:
    """A file's numbers before units, chains and derivatives: what a format's reader hands to :func:`build_trajectory`.

    Attributes:
        source: the file as the user named it.
        lines: the file's 1-based line of each row, (N,).
        time: the time column's values in its own unit, (N,).
        angles: the three angle columns' values in their units, (N, 3).
        load: the load column's values in its unit, (N,), or None.
        columns: which column each came from, with units and signs.
        time_quantum: the resolution the times are printed with, in the time
            column's unit (0 when not known): times that are even to within it
            are taken as even.
    """

    source: str
    lines: np.ndarray
    time: np.ndarray
    angles: np.ndarray
    load: np.ndarray | None
    columns: ColumnMap
    time_quantum: float = 0.0


@overload
def build_trajectory(table: Table, *, lazy: Literal[False] = False, **options: Unpack[BuildOptions]) -> Trajectory: ...
@overload
def build_trajectory(table: Table, *, lazy: Literal[True], **options: Unpack[BuildOptions]) -> SampledMotion: ...
@overload
def build_trajectory(table: Table, *, lazy: bool, **options: Unpack[BuildOptions]) -> Trajectory | SampledMotion: ...
def build_trajectory(
    table: Table, *, lazy: bool = False, **options: Unpack[BuildOptions]
) -> Trajectory | SampledMotion:
    """Units, hip chain, time scaling, resampling and derivatives: the steps every reader shares (module docstring).

    Args:
        table: the file's numbers.
        lazy: return the :class:`SampledMotion` (the samples and their
            spline, evaluated piece by piece) instead of the whole Trajectory.
        options: :class:`hipsim.motion.read_options.BuildOptions` (periodic, frequency, period,
            resample, body_weight, cutoff, load_curve).

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    check_options(options, BuildOptions, "build_trajectory")
    source, lines, columns = table.source, np.asarray(table.lines), table.columns
    periodic, frequency, period = options.get("periodic"), options.get("frequency"), options.get("period")
    resample, body_weight, cutoff = options.get("resample"), options.get("body_weight"), options.get("cutoff")
    load_curve = options.get("load_curve")
    cycle = _cycle_period(frequency, period, source)
    rate = _positive(resample, "resample rate", "Hz", source) if resample is not None else None
    time_column = columns.time
    unit = time_column.unit or "s"
    if unit == "%":
        if cycle is None:
            raise TrajectoryError(
                "time is in % of the cycle: give the cycle's period or frequency",
                source=source,
                column=time_column.name,
            )
        t, quantum = table.time / 100.0 * cycle, table.time_quantum / 100.0 * cycle
        offset = 0.0
    else:
        scale = {"s": 1.0, "ms": 1e-3}[unit]
        relative = relative_time(table.time, source, time_column.name, stacklevel=3)
        offset = (
            float(table.time[0] - relative[0]) * scale if relative.size else 0.0
        )  # the epoch, for a load file's clock
        t, quantum = relative * scale, table.time_quantum * scale
        check_time_unit(t, unit, source, time_column.name)
    t = check_time(t, quantum, source, lines, time_column.name, even=rate is None)
    q = _angles(table, source, lines)
    load = _load(table, body_weight, source, lines)
    if load_curve is not None:
        if table.columns.load is not None:
            raise TrajectoryError(
                "a load column and a load file are both given: which is the load?",
                source=source,
                column=table.columns.load.name,
            )
        keep, load = load_curve.onto(t + offset if offset else t, source)
        if not keep.all():
            t, q, lines = t[keep], q[keep], lines[keep]
    elif table.columns.load is None:
        warnings.warn(
            f"{source}: no load column: F_e = 0 N, so the friction parts are those of an unloaded machine "
            "(give the load: a Fe_N column, --load-column or --load)",
            NoLoadWarning,
            stacklevel=2,
        )
    closes = _closes_on_itself(q, load)
    if cycle is not None:
        _warn_if_not_one_stride(t, q, closes, source)
    if cycle is not None and unit != "%":
        recorded = t[-1] - t[0] + (0.0 if closes else float(np.median(np.diff(t))))
        t = t[0] + (t - t[0]) * (cycle / recorded)
    if periodic is None:
        periodic = closes
    elif periodic and not closes:
        raise TrajectoryError(
            "periodic was asked for, but the last row does not repeat the first (angles, load and slope)",
            source=source,
            line=int(lines[-1]),
        )
    on_file_lines = True  # the samples are the file's rows (not resampled onto a grid)
    if cutoff is not None:
        if rate is not None:  # the filter needs even samples: resample first
            t, q, load = _on_grid(_resampled(t, q, load, rate, periodic, source), periodic)
            rate, on_file_lines = None, False
        step = (t[-1] - t[0]) / (t.size - 1)
        q = lowpass_record(q, 1.0 / step, cutoff, bool(periodic), source)
    else:
        _warn_if_noisy(t, q, source)
    motion = (
        _resampled(t, q, load, rate, periodic, source)
        if rate is not None
        else SampledMotion(t, load, lines if on_file_lines else None, _spline(t, q, periodic), source, bool(periodic))
    )
    return motion if lazy else motion.trajectory()


def _warn_if_noisy(t: np.ndarray, q: np.ndarray, source: str) -> None:
    """One TrajectoryWarning when the angles carry noise that differentiation would amplify (:mod:`hipsim.motion.noise_check`)."""
    message = check_noise(t, q).warning(source)
    if message is not None:
        warnings.warn(message, NoiseWarning, stacklevel=4)


def check_time_unit(t: np.ndarray, unit: str, source: str, column: str) -> None:
    """Refuse times that are in another unit than their label (:func:`hipsim.plausibility.time_slip`).

    Args:
        t: the times in [s] as read and converted from ``unit``, (N,).
        unit: the unit they were read in, "s" or "ms".
        source, column: the file and column, for the message.

    Raises:
        TrajectoryError: milliseconds read as seconds, or seconds as milliseconds.
    """
    if t.size > 1 and t[-1] > t[0]:
        slip = time_slip(t, unit)
        if slip is not None:
            raise TrajectoryError(slip, source=source, column=column)


def relative_time(time: np.ndarray, source: str, column: str, stacklevel: int = 2) -> np.ndarray:
    """Times as read, or, for Unix epoch time stamps, relative to the first (a warning says so).

    The subtraction is exact in floating point (the stamps lie within a factor 2 of
    each other), so the times keep every digit they were read with, and the
    spline and the output work on small numbers (10 significant digits of an
    epoch stamp are whole seconds).
    """
    time = np.asarray(time, dtype=float)
    note = epoch_warning(float(time[0])) if time.size else None
    if note is None:
        return time
    warnings.warn(f"{source}: column '{column}': {note}", TrajectoryWarning, stacklevel=stacklevel + 1)
    return time - time[0]


#: Flexion crossings of its mid-level, with this hysteresis as a fraction of its range, count strides.
_STRIDE_HYSTERESIS = 0.25


def stride_count(t: np.ndarray, angle: np.ndarray) -> tuple[int, float | None]:
    """How many strides an angle's samples hold: (upward crossings of its mid-level, their median interval in [s] or None).

    A crossing counts once the angle has been below ``mid − 25 %`` of its range and rises above ``mid + 25 %``:
    noise near the middle cannot count twice.
    """
    low, high = float(np.min(angle)), float(np.max(angle))
    if not high > low:
        return 0, None
    mid, band = 0.5 * (low + high), _STRIDE_HYSTERESIS * (high - low)
    rising, armed = [], False
    for k, value in enumerate(angle):
        if value < mid - band:
            armed = True
        elif armed and value > mid + band:
            rising.append(k)
            armed = False
    period = float(np.median(np.diff(t[rising]))) if len(rising) > 1 else None
    return len(rising), period


def _warn_if_not_one_stride(t: np.ndarray, q: np.ndarray, closes: bool, source: str) -> None:
    """Warn when a file rescaled as one cycle holds several strides, or only part of one (by the widest angle: flexion)."""
    k = int(np.argmax(np.ptp(q, axis=0)))
    count, period = stride_count(t, q[:, k])
    span = float(t[-1] - t[0])
    if count >= 2 and period is not None and period < 0.75 * span:
        warnings.warn(
            f"{source}: the file holds about {span / period:.2g} strides (one {('alpha', 'beta', 'gamma')[k]} cycle every "
            f"{period:.4g} s of its time, over {span:.4g} s), but --frequency/--period rescale the whole file as one cycle: "
            "each stride then runs that much faster; cut one stride out, or scale the period by the stride count",
            TrajectoryWarning,
            stacklevel=3,
        )
        return
    rng = float(np.ptp(q[:, k]))
    gap = abs(float(q[-1, k] - q[0, k]))
    if not closes and rng > 0 and gap > 0.25 * rng:
        warnings.warn(
            f"{source}: the motion does not come back to its start ({('alpha', 'beta', 'gamma')[k]} starts at "
            f"{math.degrees(q[0, k]):.3g}° and ends at {math.degrees(q[-1, k]):.3g}°, {100 * gap / rng:.0f} % of its range "
            "away): part of a stride, rescaled as a whole cycle by --frequency/--period",
            TrajectoryWarning,
            stacklevel=3,
        )


def _on_grid(motion: SampledMotion, periodic: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A resampled motion's grid samples (t, q, load), a periodic one closed by its first sample again."""
    t, q, load = motion.t, motion.spline(motion.t), np.interp(motion.t, motion.knots, motion.load)
    if periodic:
        t = np.append(t, motion.knots[-1])
        q, load = np.vstack([q, q[:1]]), np.append(load, load[0])
    return t, q, load


class SampledMotion:
    """A file's samples and the quintic spline through them: the trajectory, evaluated whole or a piece at a time.

    The derivatives at a sample come from the one spline of the whole file,
    so a piece is the same, to the last digit, as that part of the whole
    :class:`Trajectory` (a long file runs in constant memory beyond its samples).

    Args:
        t: the file's times in [s], (N,) (a periodic file's repeated last row included).
        load: the load in [N] at ``t``, (N,).
        lines: the file's line of each sample, (N,), or None.
        spline: the angles' spline, a function of time in [s].
        source: the file as named.
        periodic: the last sample repeats the first (and is dropped).
        grid: times in [s] to evaluate at, when resampled (the load then linearly); None for the samples' own times.
    """

    def __init__(self, t, load, lines, spline, source: str, periodic: bool, grid: np.ndarray | None = None):
        self.knots, self.load, self.spline, self.source, self.periodic, self.grid = (
            t,
            load,
            spline,
            source,
            periodic,
            grid,
        )
        self.lines = None if lines is None or grid is not None else np.asarray(lines)
        self.t = grid if grid is not None else (t[:-1] if periodic else t)

    def __len__(self) -> int:
        return self.t.size

    def piece(self, start: int, stop: int) -> Trajectory:
        """Samples ``start`` to ``stop`` (0-based, stop excluded) as a non-periodic Trajectory."""
        t = self.t[start:stop]
        load = self.load[start:stop] if self.grid is None else np.interp(t, self.knots, self.load)
        lines = None if self.lines is None else self.lines[start:stop]
        return Trajectory(t, self.spline(t), self.spline(t, 1), self.spline(t, 2), load, name=self.source, lines=lines)

    def trajectory(self) -> Trajectory:
        """The whole trajectory (periodic as the file is)."""
        whole = self.piece(0, len(self))
        return Trajectory(whole.t, whole.q, whole.qd, whole.qdd, whole.Fe, self.source, self.periodic, whole.lines)


def _positive(value, what: str, unit: str, source: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (math.isfinite(value) and value > 0):
        raise TrajectoryError(f"{what} must be a positive number of {unit}, got {value!r}", source=source)
    return float(value)


def _cycle_period(frequency, period, source: str) -> float | None:
    if frequency is not None and period is not None:
        raise TrajectoryError("give the cycle's frequency or its period, not both", source=source)
    if frequency is not None:
        return 1.0 / _positive(frequency, "cycle frequency", "Hz", source)
    if period is not None:
        return _positive(period, "cycle period", "s", source)
    return None


def check_time(t: np.ndarray, quantum: float, source: str, lines: np.ndarray, column: str, even: bool) -> np.ndarray:
    """Increasing times; with ``even``, evenly spaced (to print resolution), then returned exactly even."""
    # Frugal with memory (an hour's log at 1 kHz has 3.6 M times): one array of steps, worked on in place.
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0)) + 1
        raise TrajectoryError(
            f"time {t[k]:g} s does not increase (previous {t[k - 1]:g} s)",
            source=source,
            line=int(lines[k]),
            column=column,
        )
    if not even:
        return t
    # The median, not the mean: one dropped sample moves the mean off every step, not the median.
    step = float(np.median(dt))
    # A thousandth of a step, or the times' printed resolution (never a quarter step): a dropped
    # or repeated sample is a whole step off, jitter of a motion-capture clock a good part of one.
    tolerance = max(1e-3 * step, min(1.001 * quantum, 0.25 * step))
    dt -= step
    off = np.abs(dt, out=dt) > tolerance
    del dt
    if np.any(off):
        k = int(np.argmax(off)) + 1
        raise TrajectoryError(
            f"uneven time step: {t[k] - t[k - 1]:g} s here, {step:g} s elsewhere "
            "(a dropped or repeated sample, or clock jitter): resample the data onto an even grid",
            source=source,
            line=int(lines[k]),
            column=column,
        )
    spacing = (t[-1] - t[0]) / (t.size - 1)
    block = 1 << 16
    deviation = max(
        float(np.abs(t[0] + np.arange(a, min(a + block, t.size)) * spacing - t[a : a + block]).max())
        for a in range(0, t.size, block)
    )
    # Times printed to fewer digits than they have: the even grid they round from.
    return t if deviation <= 1e-6 * step else t[0] + np.arange(t.size) * spacing


def _angles(table: Table, source: str, lines: np.ndarray) -> np.ndarray:
    """The three angles in [rad] as α, β, γ (the hip chain turned into them), signs applied."""
    columns = table.columns
    values = np.asarray(table.angles, dtype=float)
    out = np.empty_like(values)
    in_degrees = []
    for c, column in enumerate(columns.angles):
        unit = column.unit or "deg"
        x = values[:, c]
        k = int(np.argmax(np.abs(x)))
        if unit == "rad" and abs(x[k]) > math.pi:
            raise TrajectoryError(
                f"{x[k]:g} rad is more than half a turn: these look like degrees",
                source=source,
                line=int(lines[k]),
                column=column.name,
            )
        if unit == "deg" and abs(x[k]) > 360.0:
            raise TrajectoryError(
                f"{x[k]:g}° is more than a full turn", source=source, line=int(lines[k]), column=column.name
            )
        if unit == "deg":
            in_degrees.append(c)
        out[:, c] = column.sign * (np.radians(x) if unit == "deg" else x)
    if in_degrees:
        spans = np.ptp(values[:, in_degrees], axis=0)
        widest = int(np.argmax(spans))
        slip = radians_slip(spans) if len(in_degrees) == 3 else None
        if slip is not None:
            raise TrajectoryError(
                f"the angles look like radians: the widest spans {spans[widest]:.3g}°, a gait's {slip[1]:.3g}° if read "
                "as radians; label them in rad (_rad, or :rad in --columns)",
                source=source,
                column=columns.angles[in_degrees[widest]].name,
            )
        for k, as_radians in one_radians_slip(spans):  # one column in radians among degrees (issue 48)
            warnings.warn(
                f"{source}: '{columns.angles[in_degrees[k]].name}' spans {spans[k]:.3g}° beside "
                f"{spans[widest]:.3g}° in '{columns.angles[in_degrees[widest]].name}': radians under a degree label "
                f"(as radians it would span {as_radians:.3g}°; label it :rad in --columns), or a scale?",
                TrajectoryWarning,
                stacklevel=3,
            )
        if 0.0 < spans[widest] < 1.0:
            warnings.warn(
                f"{source}: the angles span less than a degree (at most {spans[widest]:.3g}° in "
                f"'{columns.angles[in_degrees[widest]].name}'): if they are radians, label them so",
                TrajectoryWarning,
                stacklevel=3,
            )
    if columns.hip_chain:
        out = np.unwrap(hip_to_machine(out), axis=0)
    return out


def _load(table: Table, body_weight: float | None, source: str, lines: np.ndarray) -> np.ndarray:
    """The load in [N], checked to be a plausible magnitude."""
    column = table.columns.load
    if body_weight is not None:
        body_weight = _positive(body_weight, "body weight", "N", source)
    if column is None:
        if body_weight is not None:
            raise TrajectoryError("a body weight was given, but no load column", source=source)
        return np.zeros(table.time.size)
    if column.unit is None and body_weight is None and stated_unit(column.name, "load") in ("%BW", "kN"):
        stated = stated_unit(column.name, "load")
        hint = (
            "give the body weight (--body-weight, in kg or N)"
            if stated == "%BW"
            else f"map it with its unit, load={column.name}:kN"
        )
        raise TrajectoryError(
            f"the load column's name says {stated}, but it would be read as N: {hint}",
            source=source,
            column=column.name,
        )
    unit = column.unit or ("%BW" if body_weight is not None else "N")
    if unit == "%BW":
        if body_weight is None:
            raise TrajectoryError(
                "the load is in % body weight: give the body weight (--body-weight, in kg or N)",
                source=source,
                column=column.name,
            )
        scale = body_weight / 100.0
    else:
        if body_weight is not None:
            raise TrajectoryError(
                f"a body weight was given, but the load is in {unit}", source=source, column=column.name
            )
        scale = {"N": 1.0, "kN": 1e3}[unit]
    load = column.sign * np.asarray(table.load, dtype=float) * scale
    if np.any(load < 0):
        k = int(np.argmax(load < 0))
        raise TrajectoryError(
            f"load {load[k]:g} N is negative (F_e is a magnitude: flip the column's sign if it is a compressive component)",
            source=source,
            line=int(lines[k]),
            column=column.name,
        )
    error, doubt = load_slip(float(load.max()) if load.size else 0.0, unit)
    if error is not None:
        raise TrajectoryError(error, source=source, column=column.name)
    if doubt is not None:
        warnings.warn(f"{source}: column '{column.name}': {doubt}", TrajectoryWarning, stacklevel=3)
    if np.any(load > MAX_LOAD):
        k = int(np.argmax(load > MAX_LOAD))
        raise TrajectoryError(
            f"load {load[k]:g} N is beyond {MAX_LOAD:g} N (a unit slip?)",
            source=source,
            line=int(lines[k]),
            column=column.name,
        )
    return load


def _closes_on_itself(angles: np.ndarray, load: np.ndarray) -> bool:
    """True when the last row repeats the first and the motion leaves the first row as it reaches the last.

    Matching values alone are not enough (a motion out and back has them):
    the one-sided differences across the wrap must also agree to within the
    size of the file's own second differences.
    """
    scale = max(1.0, float(np.abs(angles).max()))
    same_values = np.allclose(angles[0], angles[-1], rtol=0, atol=1e-9 * scale) and abs(
        load[0] - load[-1]
    ) <= 1e-9 * max(1.0, load.max())
    leaving, arriving = angles[1] - angles[0], angles[-1] - angles[-2]
    curvature = np.abs(np.diff(angles, 2, axis=0)).max(axis=0)
    same_slope = np.all(np.abs(leaving - arriving) <= 10.0 * curvature + 1e-12 * scale)
    return bool(same_values and same_slope)


def _spline(t: np.ndarray, angles: np.ndarray, periodic: bool):
    """The interpolating quintic spline through the samples (periodic: exact closure at the ends)."""
    if periodic:
        angles = angles.copy()
        angles[-1] = angles[0]
    return make_interp_spline(t, angles, k=5, bc_type="periodic" if periodic else None, axis=0)


def _resampled(
    t: np.ndarray, q: np.ndarray, load: np.ndarray, rate: float, periodic: bool, source: str
) -> SampledMotion:
    """The samples' quintic spline (and the load, linearly) on an even grid of ``rate`` samples per second.

    A periodic file keeps a whole period: the grid's step is the period over
    round(period·rate) samples, which may differ slightly from 1/rate.
    """
    span = t[-1] - t[0]
    if periodic:
        n = int(round(span * rate))
        grid = t[0] + np.arange(n) * (span / max(n, 1))
    else:
        n = int(math.floor(span * rate + 1e-9)) + 1
        grid = t[0] + np.arange(n) / rate
    if n < MIN_SAMPLES:
        raise TrajectoryError(
            f"resampling {span:g} s at {rate:g} Hz gives {n} samples; at least {MIN_SAMPLES} are needed", source=source
        )
    return SampledMotion(t, load, None, _spline(t, q, periodic), source, bool(periodic), grid=grid)

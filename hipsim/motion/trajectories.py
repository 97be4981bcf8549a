"""Platform trajectories: the built-in ISO 14242-1 cycle and user CSV files.

A :class:`Trajectory` holds the platform orientation q = [α, β, γ] in [rad]
(flexion/extension, abduction/adduction, internal/external rotation), its
first and second time derivatives, and the hydraulic load F_e in [N], all
sampled at the times t in [s].

The built-in cycle (spec §7.2) has exact derivatives. A CSV trajectory is
differentiated with an interpolating quintic B-spline (periodic boundary
conditions when the file closes on itself, not-a-knot otherwise). Measured on
the ISO cycle written to CSV and read back (``tests/test_trajectories.py``),
relative to each angle's peak: at 1 kHz the velocity is exact to 2e-13 and the
acceleration to 1e-10 (round-off dominates), 1e-12 and 1e-9 near the ends of a
non-periodic file; at 200 Hz the acceleration is exact to 1.4e-9 inside and
5e-7 near the ends of a non-periodic file.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy.interpolate import PchipInterpolator, make_interp_spline

from ..exceptions import TrajectoryError

__all__ = [
    "ANGLE_NAMES",
    "ISO_LOAD_KNOTS",
    "Trajectory",
    "interpolator",
    "iso14242",
    "iso14242_at",
    "iso14242_load",
    "load_trajectory_csv",
]

#: The three platform angles, in the order of q.
ANGLE_NAMES = ("alpha", "beta", "gamma")

#: Knots (cycle fraction, load in [N]) of the ISO 14242-1 twin-peak load, spec §7.2.
ISO_LOAD_KNOTS = ((0.0, 300.0), (0.12, 3000.0), (0.32, 1500.0), (0.50, 3000.0), (0.62, 300.0), (1.0, 300.0))

#: Fewest samples a CSV trajectory may have (a quintic spline needs six).
MIN_SAMPLES = 6
#: Largest load a trajectory file may give, in [N]: far above any hip simulator, so only a unit slip reaches it.
MAX_LOAD = 1e9

#: Most samples a built-in cycle may have: the kinematics of 10⁷ samples take some 10 GB.
MAX_SAMPLES = 10_000_000


@dataclass(frozen=True, eq=False)
class Trajectory:
    """A platform orientation trajectory with its load.

    Attributes:
        t: sample times in [s], shape (N,), increasing.
        q: orientation [α, β, γ] in [rad], shape (N, 3).
        qd: its time derivative in [rad/s], shape (N, 3).
        qdd: its second time derivative in [rad/s²], shape (N, 3).
        Fe: hydraulic load magnitude in [N], shape (N,), pushing down on the hip joints.
        name: where the trajectory came from, for messages and reports.
        periodic: True when the samples cover whole periods (the last sample is
            followed by the first), so RMS values and plots may wrap around.
    """

    t: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    Fe: np.ndarray
    name: str = "trajectory"
    periodic: bool = False

    def __post_init__(self):
        t = np.asarray(self.t, dtype=float)
        if t.ndim != 1 or t.size < 1:
            raise TrajectoryError(f"t must be a non-empty 1-D array, got shape {t.shape}", source=self.name)
        n = t.size
        for attr, shape in (("q", (n, 3)), ("qd", (n, 3)), ("qdd", (n, 3)), ("Fe", (n,))):
            value = np.asarray(getattr(self, attr), dtype=float)
            if value.shape != shape:
                raise TrajectoryError(f"{attr} must have shape {shape}, got {value.shape}", source=self.name)
            if not np.all(np.isfinite(value)):
                k = int(np.argwhere(~np.isfinite(value))[0][0])
                raise TrajectoryError(f"{attr} is not finite at t = {t[k]:.6g} s", source=self.name)
            value.setflags(write=False)
            object.__setattr__(self, attr, value)
        t.setflags(write=False)
        object.__setattr__(self, "t", t)

    def __len__(self) -> int:
        return self.t.size

    def slice(self, index) -> "Trajectory":
        """The samples selected by ``index`` (a slice, mask or index array)."""
        return Trajectory(self.t[index], self.q[index], self.qd[index], self.qdd[index], self.Fe[index], self.name, False)


def iso14242_angles(t: np.ndarray, frequency: float = 1.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The gait angles of the built-in cycle and their exact derivatives.

    Args:
        t: times in [s], shape (N,).
        frequency: cycle frequency f in [Hz].

    Returns:
        q, qd, qdd, each of shape (N, 3), in [rad], [rad/s], [rad/s²].
    """
    deg = math.pi / 180.0
    # (mean, amplitude, phase) of each angle: x(s) = mean + amplitude·cos(2πs − phase).
    mean = np.array([3.5, 1.5, -4.0]) * deg
    amplitude = np.array([21.5, 5.5, 6.0]) * deg
    phase = np.array([0.0, 40.0 * deg, math.pi])
    w = 2.0 * math.pi * frequency
    arg = w * np.asarray(t, dtype=float)[:, None] - phase
    q = mean + amplitude * np.cos(arg)
    qd = -amplitude * w * np.sin(arg)
    qdd = -amplitude * w**2 * np.cos(arg)
    return q, qd, qdd


def iso14242_load(t: np.ndarray, frequency: float = 1.0) -> np.ndarray:
    """The built-in twin-peak load F_e in [N] at times t in [s] (periodic PCHIP, spec §7.2)."""
    s, load = np.array(ISO_LOAD_KNOTS).T
    # The knots at s = 0 and s = 1 are the same point of the periodic curve:
    # repeat one period before and after so the end slopes see their neighbours.
    s_inner, load_inner = s[:-1], load[:-1]
    s_ext = np.concatenate([s_inner - 1.0, s_inner, s_inner + 1.0, [2.0]])
    load_ext = np.concatenate([load_inner, load_inner, load_inner, [load[-1]]])
    curve = PchipInterpolator(s_ext, load_ext)
    return curve(np.mod(np.asarray(t, dtype=float) * frequency, 1.0))


def iso14242(rate: float = 1000.0, cycles: float = 1, frequency: float = 1.0) -> Trajectory:
    """The built-in ISO 14242-1 gait cycle of spec §7.2.

    Args:
        rate: sample rate in [Hz].
        cycles: number of cycles (whole or not).
        frequency: cycle frequency f in [Hz] (1 Hz in the standard).

    Returns:
        The trajectory sampled at t = k/rate for k = 0 … N−1 with N = cycles·rate/f,
        the end of the last cycle left out so that whole cycles tile.
    """
    for name, value in (("rate", rate), ("cycles", cycles), ("frequency", frequency)):
        if isinstance(value, bool) or not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
            raise TrajectoryError(f"{name} must be a positive number, got {value!r}", source="ISO 14242-1")
    n = int(round(cycles * rate / frequency))
    if n < 2:
        raise TrajectoryError(
            f"{cycles} cycle(s) of {frequency} Hz sampled at {rate} Hz give fewer than 2 samples", source="ISO 14242-1"
        )
    if n > MAX_SAMPLES:
        raise TrajectoryError(f"{cycles} cycle(s) at {rate} Hz gives {n:,} samples; at most {MAX_SAMPLES:,} fit in memory", source="ISO 14242-1")
    t = np.arange(n) / rate
    q, qd, qdd = iso14242_angles(t, frequency)
    whole = abs(cycles - round(cycles)) < 1e-12 and abs(n - cycles * rate / frequency) < 1e-9
    return Trajectory(t, q, qd, qdd, iso14242_load(t, frequency), name="ISO 14242-1", periodic=whole)


def iso14242_at(t: np.ndarray, frequency: float = 1.0) -> Trajectory:
    """The built-in cycle evaluated at any times t in [s] (exact, like :func:`iso14242`)."""
    t = np.atleast_1d(np.asarray(t, dtype=float))
    q, qd, qdd = iso14242_angles(t, frequency)
    return Trajectory(t, q, qd, qdd, iso14242_load(t, frequency), name="ISO 14242-1", periodic=False)


def interpolator(trajectory: Trajectory):
    """A function of time giving the trajectory between (and, if periodic, beyond) its samples.

    Angles through a quintic spline of the samples (periodic if the trajectory
    is), so velocity and acceleration stay smooth; the load linearly.

    Args:
        trajectory: the sampled trajectory.

    Returns:
        ``at(times)`` returning a :class:`Trajectory` at the times in [s].

    Raises:
        TrajectoryError: (from ``at``) for times outside a non-periodic trajectory.
    """
    t, q, load = trajectory.t, trajectory.q, trajectory.Fe
    if t.size < MIN_SAMPLES:
        raise TrajectoryError(f"{t.size} samples; at least {MIN_SAMPLES} are needed to interpolate", source=trajectory.name)
    if trajectory.periodic:
        dt = (t[-1] - t[0]) / (t.size - 1)
        period = t[-1] - t[0] + dt
        t, q, load = np.append(t, t[0] + period), np.vstack([q, q[:1]]), np.append(load, load[0])
    spline = make_interp_spline(t, q, k=5, bc_type="periodic" if trajectory.periodic else None, axis=0)

    def at(times) -> Trajectory:
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if trajectory.periodic:
            local = t[0] + np.mod(times - t[0], period)
        else:
            if times.min() < t[0] - 1e-12 or times.max() > t[-1] + 1e-12:
                raise TrajectoryError(
                    f"times {times.min():g} to {times.max():g} s reach outside the trajectory ({t[0]:g} to {t[-1]:g} s)",
                    source=trajectory.name,
                )
            local = np.clip(times, t[0], t[-1])
        return Trajectory(times, spline(local), spline(local, 1), spline(local, 2), np.interp(local, t, load), trajectory.name)

    return at


def load_trajectory_csv(path: str | Path, periodic: bool | None = None) -> Trajectory:
    """Read a trajectory from a CSV file and differentiate it.

    The header names the columns with their unit: ``t_s``, then ``alpha_deg``,
    ``beta_deg``, ``gamma_deg`` (or ``_rad`` for all three), optionally
    ``Fe_N`` (the load; 0 N when absent). Times must be evenly spaced.

    Args:
        path: the CSV file.
        periodic: True if the motion repeats with the period of the file (its
            last row equals its first); None to decide from the data.

    Returns:
        The trajectory with derivatives from an interpolating quintic spline.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    source = str(path)
    try:
        # utf-8-sig: spreadsheets often start a "CSV UTF-8" file with a byte-order mark.
        with open(path, newline="", encoding="utf-8-sig") as stream:
            rows = [row for row in csv.reader(stream)]
    except FileNotFoundError:
        raise TrajectoryError("no such trajectory file", source=source) from None
    except IsADirectoryError:
        raise TrajectoryError("is a folder, not a trajectory file", source=source) from None
    except OSError as error:
        raise TrajectoryError(f"cannot read ({error.strerror})", source=source) from None
    except UnicodeDecodeError:
        raise TrajectoryError("not a text (UTF-8) CSV file", source=source) from None
    # Blank lines are skipped, but keep the file's line numbers for messages.
    numbered = [(number, row) for number, row in enumerate(rows, start=1) if any(cell.strip() for cell in row)]
    if not numbered:
        raise TrajectoryError("the file is empty", source=source)
    header_line, header = numbered[0]
    header = [cell.strip() for cell in header]
    columns, unit = _check_header(header, source, header_line)
    data = numbered[1:]
    if len(data) < MIN_SAMPLES:
        raise TrajectoryError(f"{len(data)} samples; at least {MIN_SAMPLES} are needed", source=source)
    values = np.empty((len(data), len(header)))
    for k, (number, row) in enumerate(data):
        if len(row) != len(header):
            raise TrajectoryError(f"{len(row)} cells, the header has {len(header)}", source=source, line=number)
        for c, cell in enumerate(row):
            try:
                if "_" in cell:  # Python's float() reads "1_0" as 10; a CSV writer would not mean that
                    raise ValueError(cell)
                values[k, c] = float(cell)
            except ValueError:
                raise TrajectoryError(f"'{cell.strip()}' is not a number", source=source, line=number, column=header[c]) from None
            if not math.isfinite(values[k, c]):
                raise TrajectoryError(f"'{cell.strip()}' is not finite", source=source, line=number, column=header[c])
    lines = [number for number, _ in data]
    t = values[:, header.index("t_s")]
    _check_time(t, source, lines)
    angles = np.stack([values[:, header.index(f"{a}_{unit}")] for a in ANGLE_NAMES], axis=1)
    if unit == "rad":
        worst = np.unravel_index(np.argmax(np.abs(angles)), angles.shape)
        if abs(angles[worst]) > math.pi:
            raise TrajectoryError(
                f"{angles[worst]:g} rad is more than half a turn: these look like degrees; label the columns _deg",
                source=source, line=lines[worst[0]], column=f"{ANGLE_NAMES[worst[1]]}_rad",
            )
    else:
        worst = np.unravel_index(np.argmax(np.abs(angles)), angles.shape)
        if abs(angles[worst]) > 360.0:
            raise TrajectoryError(
                f"{angles[worst]:g}° is more than a full turn", source=source, line=lines[worst[0]], column=f"{ANGLE_NAMES[worst[1]]}_deg"
            )
        angles = np.radians(angles)
    if "Fe_N" in columns:
        load = values[:, header.index("Fe_N")]
        if np.any(load < 0):
            k = int(np.argmax(load < 0))
            raise TrajectoryError(f"load {load[k]:g} N is negative (F_e is a magnitude)", source=source, line=lines[k], column="Fe_N")
        if np.any(load > MAX_LOAD):
            k = int(np.argmax(load > MAX_LOAD))
            raise TrajectoryError(f"load {load[k]:g} N is beyond {MAX_LOAD:g} N (a unit slip?)", source=source, line=lines[k], column="Fe_N")
    else:
        load = np.zeros_like(t)
    closes = _closes_on_itself(angles, load)
    if periodic is None:
        periodic = closes
    elif periodic and not closes:
        raise TrajectoryError(
            "periodic was asked for, but the last row does not repeat the first (angles, load and slope)",
            source=source, line=lines[-1],
        )
    q, qd, qdd = _differentiate(t, angles, periodic)
    if periodic:  # the last row repeats the first: keep one copy
        t, q, qd, qdd, load = t[:-1], q[:-1], qd[:-1], qdd[:-1], load[:-1]
    return Trajectory(t, q, qd, qdd, load, name=Path(source).name, periodic=periodic)


def _closes_on_itself(angles: np.ndarray, load: np.ndarray) -> bool:
    """True when the last row repeats the first and the motion leaves the first row as it reaches the last.

    Matching values alone are not enough (a motion out and back has them):
    the one-sided differences across the wrap must also agree to within the
    size of the file's own second differences.
    """
    scale = max(1.0, float(np.abs(angles).max()))
    same_values = np.allclose(angles[0], angles[-1], rtol=0, atol=1e-9 * scale) and abs(load[0] - load[-1]) <= 1e-9 * max(1.0, load.max())
    leaving, arriving = angles[1] - angles[0], angles[-1] - angles[-2]
    curvature = np.abs(np.diff(angles, 2, axis=0)).max(axis=0)
    same_slope = np.all(np.abs(leaving - arriving) <= 10.0 * curvature + 1e-12 * scale)
    return bool(same_values and same_slope)


def _check_header(header: list[str], source: str, line: int) -> tuple[set[str], str]:
    columns = set(header)
    if len(columns) != len(header):
        dup = next(c for c in header if header.count(c) > 1)
        raise TrajectoryError(f"column '{dup}' appears twice", source=source, line=line, column=dup)
    if "t_s" not in columns:
        raise TrajectoryError("missing time column 't_s'", source=source, line=line)
    units = {u for u in ("deg", "rad") if any(f"{a}_{u}" in columns for a in ANGLE_NAMES)}
    if len(units) != 1:
        raise TrajectoryError(
            "expected angle columns alpha_deg, beta_deg, gamma_deg (or all three in _rad)"
            + (", not a mix of _deg and _rad" if len(units) == 2 else ""),
            source=source, line=line,
        )
    unit = units.pop()
    for a in ANGLE_NAMES:
        if f"{a}_{unit}" not in columns:
            raise TrajectoryError(f"missing angle column '{a}_{unit}'", source=source, line=line)
    known = {"t_s", "Fe_N", *(f"{a}_{unit}" for a in ANGLE_NAMES)}
    for c in header:
        if c not in known:
            raise TrajectoryError(
                f"unknown column (expected t_s, {', '.join(f'{a}_{unit}' for a in ANGLE_NAMES)}, optionally Fe_N)",
                source=source, line=line, column=c,
            )
    return columns, unit


def _check_time(t: np.ndarray, source: str, lines: list[int]) -> None:
    dt = np.diff(t)
    if np.any(dt <= 0):
        k = int(np.argmax(dt <= 0)) + 1
        raise TrajectoryError(f"time {t[k]:g} s does not increase (previous {t[k - 1]:g} s)", source=source, line=lines[k], column="t_s")
    step = (t[-1] - t[0]) / (t.size - 1)
    # A thousandth of a step allows times printed with few decimals; real gaps are far larger.
    off = np.abs(dt - step) > 1e-3 * step
    if np.any(off):
        k = int(np.argmax(off)) + 1
        raise TrajectoryError(
            f"uneven time step: {dt[k - 1]:g} s here, {step:g} s on average (resample the file evenly)",
            source=source, line=lines[k], column="t_s",
        )


def _differentiate(t: np.ndarray, angles: np.ndarray, periodic: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quintic interpolating spline through the samples, and its first two derivatives."""
    if periodic:
        angles = angles.copy()
        angles[-1] = angles[0]  # exact closure for the periodic boundary condition
    spline = make_interp_spline(t, angles, k=5, bc_type="periodic" if periodic else None, axis=0)
    return spline(t), spline(t, 1), spline(t, 2)

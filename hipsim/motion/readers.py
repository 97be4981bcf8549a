"""Readers of trajectory files: hipsim's CSV, any lab's table through a column mapping, OpenSim .mot/.sto.

:func:`read_trajectory` reads any of them (by the file's suffix);
:func:`load_trajectory_csv` reads a CSV table, :func:`hipsim.motion.opensim.load_opensim`
an OpenSim file. Every reader ends in the same steps (:func:`build_trajectory`):

1. units to SI: time in s, ms or % of the cycle; angles in degrees or
   radians; the load in N, kN or % of body weight; a column's sign flipped
   on request;
2. the ISB hip joint chain (flexion, adduction, internal rotation) turned
   into the platform angles α, β, γ when the file gives the hip's angles
   (:mod:`hipsim.motion.hip_angles`);
3. time rescaled when a cycle frequency or period is asked for (the file is
   taken to hold one cycle, so its derivatives scale with it);
4. onto an even time grid when resampling is asked for; otherwise the times
   must be evenly spaced already;
5. derivatives from an interpolating quintic spline (periodic when the last
   row repeats the first, which is then dropped).

A CSV table may be separated by commas, semicolons or tabs (read from the
header and the first row) and, when not by commas, may use decimal commas.
Lines starting with ``#`` are comments. Every problem is reported on one line
naming the file, its line and column.

Derivative accuracy, measured on the ISO cycle written to CSV and read back
(``tests/test_readers.py``), relative to each angle's peak: at 1 kHz the
velocity is exact to 2e-13 and the acceleration to 1e-10 (round-off
dominates), 1e-12 and 1e-9 near the ends of a non-periodic file; at 200 Hz
the acceleration is exact to 1.4e-9 inside and 5e-7 near the ends of a
non-periodic file.
"""

from __future__ import annotations

import csv
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path
from typing import Mapping

import numpy as np
from scipy.interpolate import make_interp_spline

from ..exceptions import TrajectoryError
from .hip_angles import hip_to_machine
from .trajectories import ANGLE_NAMES, MIN_SAMPLES, Trajectory

__all__ = [
    "Column",
    "ColumnMap",
    "HIP_ANGLE_NAMES",
    "MAX_LOAD",
    "STANDARD_GRAVITY",
    "TrajectoryWarning",
    "load_trajectory_csv",
    "parse_columns",
    "read_trajectory",
]

#: Largest load a trajectory file may give, in [N]: far above any hip simulator, so only a unit slip reaches it.
MAX_LOAD = 1e9
#: g in [m/s²] that turns a body mass in kg into a body weight in N (the kilogram-force).
STANDARD_GRAVITY = 9.80665
#: The ISB hip chain's angles, in the order of the chain (Z, X, Y).
HIP_ANGLE_NAMES = ("flexion", "adduction", "rotation")
#: Units each quantity of a column mapping may be given in; the first is the default.
UNITS = {
    "time": ("s", "ms", "%"),
    **{name: ("deg", "rad") for name in ANGLE_NAMES + HIP_ANGLE_NAMES},
    "load": ("N", "kN", "%BW"),
}
_UNIT_SPELLINGS = {unit.lower(): unit for units in UNITS.values() for unit in units}
#: Files read as OpenSim storage files rather than CSV tables.
OPENSIM_SUFFIXES = (".mot", ".sto")
#: Files read as Apache Parquet tables.
PARQUET_SUFFIX = ".parquet"


class TrajectoryWarning(UserWarning):
    """A trajectory file that reads, but looks wrong (e.g. radians under a degree header)."""


# --------------------------------------------------------------------------- column mappings


@dataclass(frozen=True)
class Column:
    """Where one quantity sits in a file.

    Attributes:
        name: the column's name in the header, as written there.
        unit: one of the quantity's units (:data:`UNITS`); None for its default.
        sign: +1, or −1 to flip the column's sign.
    """

    name: str
    unit: str | None = None
    sign: float = 1.0

    def __post_init__(self):
        if not isinstance(self.name, str) or not self.name.strip():
            raise TrajectoryError(f"a column needs a name, got {self.name!r}", source="column mapping")
        if self.sign not in (1.0, -1.0):
            raise TrajectoryError(f"column '{self.name}': sign must be +1 or -1, got {self.sign!r}", source="column mapping")

    @classmethod
    def parse(cls, text: str, key: str) -> "Column":
        """``[-]NAME[:UNIT]`` → Column; ``key`` (time, alpha, …, load) says which units are allowed."""
        text = text.strip()
        sign = -1.0 if text.startswith("-") else 1.0
        text = text[1:].strip() if sign < 0 else text
        unit = None
        if ":" in text:
            text, _, given = text.rpartition(":")
            unit = _UNIT_SPELLINGS.get(given.strip().lower())
            if unit not in UNITS[key]:
                raise TrajectoryError(
                    f"'{given.strip()}' is not a unit of {key} (expected {', '.join(UNITS[key])})", source="column mapping"
                )
        if not text.strip():
            raise TrajectoryError(f"no column name given for {key}", source="column mapping")
        return cls(text.strip(), unit, sign)

    def text(self) -> str:
        """Back to ``[-]NAME[:UNIT]``."""
        return ("-" if self.sign < 0 else "") + self.name + (f":{self.unit}" if self.unit else "")


@dataclass(frozen=True)
class ColumnMap:
    """Which columns of a table hold the time, the three angles and the load.

    Attributes:
        time: the time column (s, ms, or % of the cycle).
        angles: the three angle columns (degrees or radians): α, β, γ, or with
            ``hip_chain`` the ISB hip's flexion, adduction, internal rotation.
        hip_chain: the angles are the hip joint chain's (see
            :mod:`hipsim.motion.hip_angles`), to be turned into α, β, γ.
        load: the load column (N, kN or % body weight), or None for 0 N.
    """

    time: Column
    angles: tuple[Column, Column, Column]
    hip_chain: bool = False
    load: Column | None = None

    @property
    def angle_keys(self) -> tuple[str, str, str]:
        return HIP_ANGLE_NAMES if self.hip_chain else ANGLE_NAMES

    def items(self) -> list[tuple[str, Column]]:
        """(key, column) of every quantity mapped, time first."""
        out = [("time", self.time), *zip(self.angle_keys, self.angles)]
        return out + ([("load", self.load)] if self.load is not None else [])

    def text(self) -> str:
        """The mapping as ``key=[-]NAME[:UNIT],…`` (what :func:`parse_columns` reads)."""
        return ",".join(f"{key}={column.text()}" for key, column in self.items())

    @classmethod
    def from_mapping(cls, mapping: Mapping[str, str | Column]) -> "ColumnMap":
        """From ``{"time": "Time", "alpha": "FE", "beta": "-AA:rad", …}`` (values Column or ``[-]NAME[:UNIT]``)."""
        known = ("time", *ANGLE_NAMES, *HIP_ANGLE_NAMES, "load")
        columns = {}
        for key, value in mapping.items():
            key = str(key).strip().lower()
            if key not in known:
                raise TrajectoryError(
                    f"unknown quantity '{key}' (expected time; alpha, beta, gamma or flexion, adduction, rotation; optionally load)",
                    source="column mapping",
                )
            if key in columns:
                raise TrajectoryError(f"{key} is mapped twice", source="column mapping")
            column = value if isinstance(value, Column) else Column.parse(str(value), key)
            if column.unit is not None and column.unit not in UNITS[key]:
                raise TrajectoryError(f"'{column.unit}' is not a unit of {key} (expected {', '.join(UNITS[key])})", source="column mapping")
            columns[key] = column
        machine = [a for a in ANGLE_NAMES if a in columns]
        hip = [a for a in HIP_ANGLE_NAMES if a in columns]
        if machine and hip:
            raise TrajectoryError(
                "map either the platform angles alpha, beta, gamma or the hip's flexion, adduction, rotation, not both",
                source="column mapping",
            )
        names = HIP_ANGLE_NAMES if hip else ANGLE_NAMES
        missing = [k for k in ("time", *names) if k not in columns]
        if missing:
            raise TrajectoryError(f"{', '.join(missing)} not mapped (time and all three angles are needed)", source="column mapping")
        if "time" in columns and columns["time"].sign < 0:
            raise TrajectoryError("the time column cannot have its sign flipped", source="column mapping")
        return cls(columns["time"], tuple(columns[k] for k in names), bool(hip), columns.get("load"))


def parse_columns(text: str) -> ColumnMap:
    """A column mapping from text: ``time=Time,alpha=FE,beta=-AA,gamma=IE:rad,load=Fz:%BW``.

    Each entry is ``QUANTITY=[-]COLUMN[:UNIT]``: the quantity (time; alpha,
    beta, gamma for the platform angles or flexion, adduction, rotation for
    the ISB hip chain; load), the column's name in the header, an optional
    leading ``-`` that flips its sign and an optional unit (time: s, ms, %;
    angles: deg, rad; load: N, kN, %BW). Defaults: s, deg, N.

    Raises:
        TrajectoryError: naming the entry that is wrong.
    """
    if not isinstance(text, str) or not text.strip():
        raise TrajectoryError("empty column mapping (expected e.g. time=Time,alpha=FE,beta=AA,gamma=IE)", source="column mapping")
    mapping: dict[str, str] = {}
    for entry in text.split(","):
        key, sep, value = entry.partition("=")
        if not sep or not key.strip():
            raise TrajectoryError(f"'{entry.strip()}' is not QUANTITY=COLUMN", source="column mapping")
        if key.strip().lower() in mapping:
            raise TrajectoryError(f"{key.strip()} is mapped twice", source="column mapping")
        mapping[key.strip().lower()] = value
    return ColumnMap.from_mapping(mapping)


def _as_column_map(columns) -> ColumnMap | None:
    if columns is None or isinstance(columns, ColumnMap):
        return columns
    if isinstance(columns, str):
        return parse_columns(columns)
    if isinstance(columns, Mapping):
        return ColumnMap.from_mapping(columns)
    raise TypeError(f"columns must be a ColumnMap, a mapping or text, got {type(columns).__name__}")


def _as_load_column(load_column) -> Column | None:
    if load_column is None or isinstance(load_column, Column):
        return load_column
    return Column.parse(str(load_column), "load")


# --------------------------------------------------------------------------- what every reader produces


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


def build_trajectory(
    table: Table,
    *,
    periodic: bool | None = None,
    frequency: float | None = None,
    period: float | None = None,
    resample: float | None = None,
    body_weight: float | None = None,
    lazy: bool = False,
) -> "Trajectory | SampledMotion":
    """Units, hip chain, time scaling, resampling and derivatives: the steps every reader shares (module docstring).

    Args:
        table: the file's numbers.
        periodic: True if the motion repeats with the file's period (its last
            row equals its first); None to decide from the data.
        frequency: cycle frequency in [Hz] to rescale the recorded cycle to.
        period: cycle period in [s] (instead of ``frequency``).
        resample: sample rate in [Hz] of an even grid to resample onto.
        body_weight: the subject's body weight in [N], for a load in % body weight.
        lazy: return the :class:`SampledMotion` (the samples and their
            spline, evaluated piece by piece) instead of the whole Trajectory.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    source, lines, columns = table.source, np.asarray(table.lines), table.columns
    cycle = _cycle_period(frequency, period, source)
    rate = _positive(resample, "resample rate", "Hz", source) if resample is not None else None
    time_column = columns.time
    unit = time_column.unit or "s"
    if unit == "%":
        if cycle is None:
            raise TrajectoryError(
                "time is in % of the cycle: give the cycle's period or frequency", source=source, column=time_column.name
            )
        t, quantum = table.time / 100.0 * cycle, table.time_quantum / 100.0 * cycle
    else:
        scale = {"s": 1.0, "ms": 1e-3}[unit]
        t, quantum = table.time * scale, table.time_quantum * scale
    t = check_time(t, quantum, source, lines, time_column.name, even=rate is None)
    q = _angles(table, source, lines)
    load = _load(table, body_weight, source, lines)
    closes = _closes_on_itself(q, load)
    if cycle is not None and unit != "%":
        recorded = t[-1] - t[0] + (0.0 if closes else float(np.median(np.diff(t))))
        t = t[0] + (t - t[0]) * (cycle / recorded)
    if periodic is None:
        periodic = closes
    elif periodic and not closes:
        raise TrajectoryError(
            "periodic was asked for, but the last row does not repeat the first (angles, load and slope)",
            source=source, line=int(lines[-1]),
        )
    motion = _resampled(t, q, load, rate, periodic, source) if rate is not None else SampledMotion(t, load, lines, _spline(t, q, periodic), source, bool(periodic))
    return motion if lazy else motion.trajectory()


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
        self.knots, self.load, self.spline, self.source, self.periodic, self.grid = t, load, spline, source, periodic, grid
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
            f"time {t[k]:g} s does not increase (previous {t[k - 1]:g} s)", source=source, line=int(lines[k]), column=column
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
            source=source, line=int(lines[k]), column=column,
        )
    spacing = (t[-1] - t[0]) / (t.size - 1)
    block = 1 << 16
    deviation = max(float(np.abs(t[0] + np.arange(a, min(a + block, t.size)) * spacing - t[a:a + block]).max())
                    for a in range(0, t.size, block))
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
                f"{x[k]:g} rad is more than half a turn: these look like degrees", source=source, line=int(lines[k]), column=column.name
            )
        if unit == "deg" and abs(x[k]) > 360.0:
            raise TrajectoryError(f"{x[k]:g}° is more than a full turn", source=source, line=int(lines[k]), column=column.name)
        if unit == "deg":
            in_degrees.append(c)
        out[:, c] = column.sign * (np.radians(x) if unit == "deg" else x)
    if in_degrees:
        spans = np.ptp(values[:, in_degrees], axis=0)
        widest = int(np.argmax(spans))
        if 0.0 < spans[widest] < 1.0:
            warnings.warn(
                f"{source}: the angles span less than a degree (at most {spans[widest]:.3g}° in "
                f"'{columns.angles[in_degrees[widest]].name}'): if they are radians, label them so",
                TrajectoryWarning, stacklevel=3,
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
    unit = column.unit or ("%BW" if body_weight is not None else "N")
    if unit == "%BW":
        if body_weight is None:
            raise TrajectoryError("the load is in % body weight: give the body weight", source=source, column=column.name)
        scale = body_weight / 100.0
    else:
        if body_weight is not None:
            raise TrajectoryError(f"a body weight was given, but the load is in {unit}", source=source, column=column.name)
        scale = {"N": 1.0, "kN": 1e3}[unit]
    load = column.sign * np.asarray(table.load, dtype=float) * scale
    if np.any(load < 0):
        k = int(np.argmax(load < 0))
        raise TrajectoryError(
            f"load {load[k]:g} N is negative (F_e is a magnitude: flip the column's sign if it is a compressive component)",
            source=source, line=int(lines[k]), column=column.name,
        )
    if np.any(load > MAX_LOAD):
        k = int(np.argmax(load > MAX_LOAD))
        raise TrajectoryError(
            f"load {load[k]:g} N is beyond {MAX_LOAD:g} N (a unit slip?)", source=source, line=int(lines[k]), column=column.name
        )
    return load


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


def _spline(t: np.ndarray, angles: np.ndarray, periodic: bool):
    """The interpolating quintic spline through the samples (periodic: exact closure at the ends)."""
    if periodic:
        angles = angles.copy()
        angles[-1] = angles[0]
    return make_interp_spline(t, angles, k=5, bc_type="periodic" if periodic else None, axis=0)


def _resampled(t: np.ndarray, q: np.ndarray, load: np.ndarray, rate: float, periodic: bool, source: str) -> SampledMotion:
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
        raise TrajectoryError(f"resampling {span:g} s at {rate:g} Hz gives {n} samples; at least {MIN_SAMPLES} are needed", source=source)
    return SampledMotion(t, load, None, _spline(t, q, periodic), source, bool(periodic), grid=grid)


# --------------------------------------------------------------------------- CSV tables


def read_text_lines(path: str | Path, what: str = "trajectory file") -> list[str]:
    """A text file's lines (UTF-8, a byte-order mark skipped), or a one-line error naming it."""
    source = str(path)
    try:
        # utf-8-sig: spreadsheets often start a "CSV UTF-8" file with a byte-order mark.
        text = Path(path).read_text(encoding="utf-8-sig")
    except FileNotFoundError:
        raise TrajectoryError(f"no such {what}", source=source) from None
    except IsADirectoryError:
        raise TrajectoryError(f"is a folder, not a {what}", source=source) from None
    except OSError as error:
        raise TrajectoryError(f"cannot read ({error.strerror})", source=source) from None
    except UnicodeDecodeError:
        raise TrajectoryError(f"not a text (UTF-8) {what}", source=source) from None
    return text.split("\n")


def number(cell: str, decimal_comma: bool = False) -> float:
    """A cell's number; ValueError if it is not one (as a CSV writer would have written it)."""
    text = cell.strip()
    if "_" in text:  # Python's float() reads "1_0" as 10; a CSV writer would not mean that
        raise ValueError(cell)
    if decimal_comma and "." not in text and text.count(",") == 1:
        text = text.replace(",", ".")
    return float(text)


def decimals(cell: str) -> int | None:
    """Digits after the decimal mark of a plainly written number (None with an exponent)."""
    text = cell.strip()
    if "e" in text.lower():
        return None
    for mark in (".", ","):
        if mark in text:
            return len(text) - text.index(mark) - 1
    return 0


def _cells(line: str, separator: str, width: int = 0) -> list[str]:
    """The line's cells; blank cells at the end are dropped down to ``width`` (a spreadsheet's trailing separator)."""
    cells = next(csv.reader([line], delimiter=separator))
    while len(cells) > width and not cells[-1].strip():
        cells.pop()
    return cells


def _separator(header: str, first_row: str | None) -> str:
    """Tab, semicolon or comma: the first that splits the header into columns, and the first row into as many."""
    fallback = None
    for separator in ("\t", ";", ","):
        n = len(_cells(header, separator))
        if n < 2:
            continue
        if first_row is None or len(_cells(first_row, separator)) == n:
            return separator
        fallback = fallback or separator
    return fallback or ","


def _blank(line: str) -> bool:
    return not line.strip(" \t,;\r")


def load_trajectory_csv(
    path: str | Path,
    periodic: bool | None = None,
    *,
    columns: ColumnMap | Mapping | str | None = None,
    load_column: Column | str | None = None,
    body_weight: float | None = None,
    frequency: float | None = None,
    period: float | None = None,
    resample: float | None = None,
    lazy: bool = False,
) -> Trajectory:
    """Read a trajectory from a CSV table and differentiate it.

    Without ``columns`` the header names hipsim's columns with their unit:
    ``t_s``, then ``alpha_deg``, ``beta_deg``, ``gamma_deg`` (or ``_rad`` for
    all three), optionally ``Fe_N`` (the load; 0 N when absent), and no
    others. With ``columns`` any header: the mapping names the columns to
    read, and the others are ignored.

    Args:
        path: the CSV file (comma, semicolon or tab separated).
        periodic: True if the motion repeats with the period of the file (its
            last row equals its first); None to decide from the data.
        columns: a column mapping (:func:`parse_columns` text, a mapping
            ``{"time": "Time", "alpha": "FE", …}`` or a :class:`ColumnMap`).
        load_column: the load's column (``[-]NAME[:UNIT]`` or a Column), in
            place of ``Fe_N`` or of the mapping's load.
        body_weight: body weight in [N], for a load in % body weight (the
            default unit of the load when a body weight is given).
        frequency: cycle frequency in [Hz]: the file holds one cycle, rescaled in time to it.
        period: cycle period in [s], instead of ``frequency``.
        resample: rate in [Hz] of an even grid to resample uneven data onto
            (the quintic spline of the samples; the load linearly).
        lazy: return a :class:`SampledMotion` to evaluate piece by piece instead.

    Returns:
        The trajectory, named by the path as given.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    source = str(path)
    mapping, load = column_options(columns, load_column, source)
    table = _read_csv_table(source, path, mapping, load)
    return build_trajectory(
        table, periodic=periodic, frequency=frequency, period=period, resample=resample, body_weight=body_weight, lazy=lazy
    )


def column_options(columns, load_column, source: str) -> tuple[ColumnMap | None, Column | None]:
    """The column mapping and load column a reader was given, merged (refused when both name the load)."""
    mapping, load = _as_column_map(columns), _as_load_column(load_column)
    if mapping is not None and load is not None:
        if mapping.load is not None:
            raise TrajectoryError("the load column is named twice (in the column mapping and on its own)", source=source)
        mapping = ColumnMap(mapping.time, mapping.angles, mapping.hip_chain, load)
    return mapping, load


def table_columns(header: list[str], mapping: ColumnMap | None, load: Column | None, source: str, line: int) -> tuple[ColumnMap, dict[str, int]]:
    """The mapping (hipsim's own header checked when none is given) and where each mapped column sits in the header."""
    if mapping is None:
        mapping = _canonical_columns(header, source, line, load)
    return mapping, _column_indices(header, mapping, source, line)


def _read_csv_table(source: str, path, mapping: ColumnMap | None, load: Column | None) -> Table:
    numbered = [(k, line) for k, line in enumerate(read_text_lines(path), start=1) if not _blank(line) and not line.lstrip().startswith("#")]
    if not numbered:
        raise TrajectoryError("the file is empty", source=source)
    header_line, header_text = numbered[0]
    separator = _separator(header_text, numbered[1][1] if len(numbered) > 1 else None)
    header = [cell.strip() for cell in _cells(header_text, separator)]
    mapping, index = table_columns(header, mapping, load, source, header_line)
    data = numbered[1:]
    if len(data) < MIN_SAMPLES:
        raise TrajectoryError(f"{len(data)} samples; at least {MIN_SAMPLES} are needed", source=source)
    decimal_comma = separator != ","
    used = sorted(set(index.values()))
    values = np.empty((len(data), len(header)))
    time_decimals = 0
    for k, (number_of_line, line) in enumerate(data):
        row = _cells(line, separator, len(header))
        if len(row) != len(header):
            hint = " (decimal commas? a comma-separated file needs decimal points)" if separator == "," and len(row) > len(header) else ""
            raise TrajectoryError(f"{len(row)} cells, the header has {len(header)}{hint}", source=source, line=number_of_line)
        for c in used:
            try:
                values[k, c] = number(row[c], decimal_comma)
            except ValueError:
                raise TrajectoryError(f"'{row[c].strip()}' is not a number", source=source, line=number_of_line, column=header[c]) from None
            if not math.isfinite(values[k, c]):
                raise TrajectoryError(f"'{row[c].strip()}' is not finite", source=source, line=number_of_line, column=header[c])
        places = decimals(row[index["time"]])
        time_decimals = max(time_decimals, places) if places is not None and time_decimals is not None else None
    return Table(
        source=source,
        lines=np.array([n for n, _ in data]),
        time=values[:, index["time"]],
        angles=values[:, [index[key] for key in mapping.angle_keys]],
        load=values[:, index["load"]] if "load" in index else None,
        columns=mapping,
        time_quantum=10.0 ** -time_decimals if time_decimals is not None else 0.0,
    )


def _column_indices(header: list[str], mapping: ColumnMap, source: str, line: int) -> dict[str, int]:
    """Where each mapped column is in the header (exactly, else ignoring case and spaces if that is unique)."""
    index = {}
    for key, column in mapping.items():
        exact = [c for c, name in enumerate(header) if name == column.name]
        loose = [c for c, name in enumerate(header) if _loose(name) == _loose(column.name)]
        found = exact or loose
        if len(found) > 1:
            raise TrajectoryError(f"column '{column.name}' appears {len(found)} times", source=source, line=line, column=column.name)
        if not found:
            raise TrajectoryError(
                f"no column '{column.name}' (mapped to {key}); the header has {_listing(header)}", source=source, line=line
            )
        index[key] = found[0]
    return index


def _loose(name: str) -> str:
    return re.sub(r"\s+", "", name).lower()


def _listing(header: list[str]) -> str:
    shown = ", ".join(f"'{name}'" for name in header[:12])
    return shown + (f" and {len(header) - 12} more" if len(header) > 12 else "")


#: Words in a lab's column names that suggest each quantity, for the mapping an error suggests.
_HINTS = {
    "time": (r"^t$", r"time", r"zeit", r"^t[ _(\[]", r"cycle", r"percent", r"\[%\]", r"^%"),
    "alpha": (r"flex", r"^fe\b", r"\bfe\b", r"alpha", r"sagit"),
    "beta": (r"abd", r"add", r"^aa\b", r"\baa\b", r"beta", r"frontal", r"coronal"),
    "gamma": (r"rot", r"^ie\b", r"\bie\b", r"gamma", r"transv", r"int.*ext"),
    "load": (r"^f$", r"force", r"load", r"^fz", r"f_?res", r"kraft", r"^f[ _(\[]"),
}


def suggest_mapping(header: list[str]) -> str:
    """A column mapping for a header, guessed from its names (``<column>`` where nothing fits)."""
    taken: set[int] = set()
    parts = []
    for key, patterns in _HINTS.items():
        choice = next(
            (c for pattern in patterns for c, name in enumerate(header) if c not in taken and re.search(pattern, name.strip().lower())),
            None,
        )
        if choice is None:
            if key != "load":
                parts.append(f"{key}=<column>")
            continue
        taken.add(choice)
        parts.append(f"{key}={header[choice]}{_unit_hint(key, header[choice])}")
    names = [part.split("=", 1)[1] for part in parts[1:4]]
    if all("hip" in name.lower() for name in names):  # a hip's joint angles, not the platform's: the ISB chain's keys
        parts[1:4] = [f"{key}={name}" for key, name in zip(HIP_ANGLE_NAMES, names)]
    return ",".join(parts)


def _unit_hint(key: str, name: str) -> str:
    """``:UNIT`` for a column whose name states a unit other than the default (``Fz [kN]`` → ``:kN``), else ''."""
    match = re.search(r"[\[(]\s*([^\])]+?)\s*[\])]", name)
    spelled = re.sub(r"\s+", "", match.group(1)).lower() if match else ("%" if "%" in name and key == "time" else "")
    unit = {"%bw": "%BW", "bw%": "%BW", "%body weight": "%BW", "°": "deg"}.get(spelled, _UNIT_SPELLINGS.get(spelled))
    return f":{unit}" if unit in UNITS[key][1:] else ""


def _canonical_columns(header: list[str], source: str, line: int, load: Column | None) -> ColumnMap:
    """hipsim's own header (t_s, alpha_deg, …): checked strictly, an unknown column refused."""
    columns = set(header)
    if len(columns) != len(header):
        duplicate = next(c for c in header if header.count(c) > 1)
        raise TrajectoryError(f"column '{duplicate}' appears twice", source=source, line=line, column=duplicate)

    def mismatch(problem: str) -> TrajectoryError:
        return TrajectoryError(
            f"{problem}; the header has {_listing(header)}: map the columns to read, e.g. {suggest_mapping(header)}",
            source=source, line=line,
        )

    if "t_s" not in columns:
        raise mismatch("no time column 't_s'")
    units = {u for u in ("deg", "rad") if any(f"{a}_{u}" in columns for a in ANGLE_NAMES)}
    if len(units) != 1:
        raise mismatch(
            "expected angle columns alpha_deg, beta_deg, gamma_deg (or all three in _rad)"
            + (", not a mix of _deg and _rad" if len(units) == 2 else "")
        )
    unit = units.pop()
    for a in ANGLE_NAMES:
        if f"{a}_{unit}" not in columns:
            raise mismatch(f"missing angle column '{a}_{unit}'")
    if load is not None and "Fe_N" in columns:
        raise TrajectoryError(f"both 'Fe_N' and the load column '{load.name}' are given: which is the load?", source=source, line=line)
    load = load if load is not None else (Column("Fe_N", "N") if "Fe_N" in columns else None)
    known = {"t_s", *(f"{a}_{unit}" for a in ANGLE_NAMES)} | ({load.name} if load is not None else set())
    for c in header:
        if c not in known:
            raise TrajectoryError(
                f"unknown column (expected t_s, {', '.join(f'{a}_{unit}' for a in ANGLE_NAMES)}, optionally Fe_N; "
                "map the columns to read any others)",
                source=source, line=line, column=c,
            )
    return ColumnMap(Column("t_s", "s"), tuple(Column(f"{a}_{unit}", unit) for a in ANGLE_NAMES), False, load)


# --------------------------------------------------------------------------- any file


def read_trajectory(
    path: str | Path,
    *,
    periodic: bool | None = None,
    columns: ColumnMap | Mapping | str | None = None,
    side: str | None = None,
    load_column: Column | str | None = None,
    body_weight: float | None = None,
    frequency: float | None = None,
    period: float | None = None,
    resample: float | None = None,
    lazy: bool = False,
) -> Trajectory:
    """Read a trajectory file of any format hipsim knows, by its suffix.

    ``.mot`` and ``.sto``: OpenSim (:func:`hipsim.motion.opensim.load_opensim`,
    which takes ``side``); ``.parquet``: an Apache Parquet table with the
    CSV's columns (:func:`hipsim.motion.parquet.load_trajectory_parquet`);
    anything else: a CSV table (:func:`load_trajectory_csv`; these two take
    ``columns``). The other arguments are as those functions have them;
    ``lazy`` returns a :class:`SampledMotion` to evaluate piece by piece.

    Raises:
        TrajectoryError: an argument that does not apply to the format, or
            the file's first problem.
    """
    source = str(path)
    if Path(source).suffix.lower() in OPENSIM_SUFFIXES:
        if columns is not None:
            raise TrajectoryError(
                "a column mapping applies to CSV tables; an OpenSim file is read by its hip coordinates' names", source=source
            )
        from .opensim import load_opensim

        return load_opensim(
            path, side="right" if side is None else side, periodic=periodic, load_column=load_column, body_weight=body_weight,
            frequency=frequency, period=period, resample=resample, lazy=lazy,
        )
    if side is not None:
        raise TrajectoryError("the side (left or right hip) applies to OpenSim .mot/.sto files", source=source)
    load = load_trajectory_csv
    if Path(source).suffix.lower() == PARQUET_SUFFIX:
        from .parquet import load_trajectory_parquet as load
    return load(
        path, periodic, columns=columns, load_column=load_column, body_weight=body_weight, frequency=frequency, period=period,
        resample=resample, lazy=lazy,
    )

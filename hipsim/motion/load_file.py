"""The load from a second file: a hip contact force or load-cell export, resampled onto the motion's times.

Gait labs keep the load apart from the kinematics: OpenSim's JointReaction
analysis writes the hip contact force to its own ``.sto``, a force plate or a
load cell to its own CSV. :func:`read_load_curve` reads one such file:

- **Formats.** OpenSim ``.sto``/``.mot`` (header up to ``endheader``, then
  labels and rows) or a CSV table (:mod:`hipsim.tables`' rules: comma,
  semicolon or tab separated, ``#`` comments).
- **Time.** The column named ``time``, ``t_s`` or ``t`` (any case), else the
  first column; in seconds, on the same clock as the motion file (the
  motion's times before any ``--frequency`` rescaling).
- **The load.** A column by name (``[-]NAME[:UNIT]``: a leading ``-`` flips a
  compressive component, units N, kN or %BW with a body weight); or, when the
  file has no column ``NAME`` but has ``NAME_fx``, ``NAME_fy``, ``NAME_fz``
  (OpenSim's JointReaction labels), the resultant √(fx² + fy² + fz²). A name
  that is in neither form is answered with the nearest label.
- **Scaling** (:class:`LoadScale`): a factor (``2.5``), or ``MIN:MAX`` to map the
  file's load range linearly onto the machine's, e.g. a contact force in % body
  weight onto 300–3000 N: the file's lowest load goes to MIN, its highest to MAX.

:meth:`LoadCurve.onto` puts the curve on the motion's sample times by linear
interpolation, over the times both files cover only: motion samples outside
the load file's span are left out (with a warning), no overlap at all is an
error, and so is a gap in the load file (a step over :data:`GAP_STEPS` times
its median step) inside the overlap.
"""

from __future__ import annotations

import difflib
import math
import re
import warnings
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..exceptions import TrajectoryError
from ..tables import cells, data_lines, detect_separator, number, read_text_lines
from .build import TrajectoryWarning, check_time_unit
from .columns import Column
from .trajectories import MIN_SAMPLES

__all__ = ["GAP_STEPS", "LoadCurve", "LoadScale", "parse_load_scale", "read_load_curve"]

#: A step between two load samples this many times the file's median step is a gap.
GAP_STEPS = 5.0
#: The labels a time column may have, compared case-blind.
TIME_NAMES = ("time", "t_s", "t")
_RESULTANT = ("_fx", "_fy", "_fz")


@dataclass(frozen=True)
class LoadScale:
    """How a load file's values become the machine's load: ``factor`` times, or its range mapped onto ``low``–``high`` N.

    Attributes:
        factor: multiply by this (when ``low``/``high`` are None).
        low, high: in [N]: the file's lowest load maps to ``low``, its highest to ``high``, linearly.
    """

    factor: float = 1.0
    low: float | None = None
    high: float | None = None

    def apply(self, load: np.ndarray) -> np.ndarray:
        """The scaled load in [N]."""
        if self.low is None or self.high is None:  # set together (parse_load_scale)
            return load * self.factor
        lo, hi = float(load.min()), float(load.max())
        if hi - lo <= 0.0:
            return np.full_like(load, self.low)
        # As a blend of the two ends, so the file's extremes land on low and high exactly (a sum with a
        # rescaled difference rounds 3000 N to 3000.0000000000005 N, past the machine's load limit).
        u = (load - lo) / (hi - lo)
        return self.low * (1.0 - u) + self.high * u


def parse_load_scale(text: str) -> LoadScale:
    """``2.5`` (a factor) or ``300:3000`` (the file's range onto that range in N) → :class:`LoadScale`.

    Raises:
        TrajectoryError: text that is neither, a factor not positive, or MIN not below MAX.
    """
    parts = str(text).split(":")
    try:
        values = [float(p) for p in parts if "_" not in p]
    except ValueError:
        values = []
    if len(values) != len(parts) or len(parts) not in (1, 2) or not all(math.isfinite(v) for v in values):
        raise TrajectoryError(
            f"expected a factor (2.5) or a range MIN:MAX in N (300:3000), got '{text}'", source="--load-scale"
        )
    if len(values) == 1:
        if values[0] <= 0:
            raise TrajectoryError(f"the factor must be positive, got '{text}'", source="--load-scale")
        return LoadScale(values[0])
    low, high = values
    if not 0 <= low < high:
        raise TrajectoryError(f"the range must be 0 ≤ MIN < MAX in N, got '{text}'", source="--load-scale")
    return LoadScale(1.0, low, high)


@dataclass(frozen=True, eq=False)
class LoadCurve:
    """A load read from its own file.

    Attributes:
        t: times in [s], (M,), increasing.
        load: the load in [N], (M,), scaled.
        lines: the file line of each sample, (M,).
        source: the file as named.
        column: what was read (a label, or ``NAME_fx/_fy/_fz`` resultant).
    """

    t: np.ndarray
    load: np.ndarray
    lines: np.ndarray
    source: str
    column: str

    def onto(self, t: np.ndarray, motion: str) -> tuple[np.ndarray, np.ndarray]:
        """The load at the motion's times ``t`` in [s] that the file covers: (mask of the motion's samples kept, load there in [N]).

        Raises:
            TrajectoryError: no overlapping time, fewer than the samples a trajectory needs, or a gap in the load inside the overlap.
        """
        first, last = max(t[0], self.t[0]), min(t[-1], self.t[-1])
        keep = (t >= first - 1e-9 * abs(first)) & (t <= last + 1e-9 * abs(last))
        if last < first or keep.sum() < MIN_SAMPLES:
            raise TrajectoryError(
                f"no overlapping time: the motion {motion} covers {t[0]:g} to {t[-1]:g} s, the load {self.t[0]:g} to {self.t[-1]:g} s",
                source=self.source,
                column=self.column,
            )
        steps = np.diff(self.t)
        # The steps that reach into the overlap: from the one that starts at or before its first time to the last
        # that starts before its last (one step when the overlap lies between two load samples).
        span = slice(int(np.searchsorted(self.t, first, side="right")) - 1, int(np.searchsorted(self.t, last)))
        typical = float(np.median(steps))
        gap = np.flatnonzero(steps[span] > GAP_STEPS * typical)
        if gap.size:
            j = span.start + int(gap[0])
            raise TrajectoryError(
                f"a gap in the load from {self.t[j]:g} to {self.t[j + 1]:g} s ({steps[j] / typical:.3g} steps of {typical:g} s)",
                source=self.source,
                line=int(self.lines[j + 1]),
                column=self.column,
            )
        dropped = int((~keep).sum())
        if dropped:
            warnings.warn(
                f"{self.source}: the load covers {self.t[0]:g} to {self.t[-1]:g} s, the motion {t[0]:g} to {t[-1]:g} s: "
                f"{dropped} motion samples outside the overlap left out",
                TrajectoryWarning,
                stacklevel=3,
            )
        return keep, np.interp(t[keep], self.t, self.load)


def read_load_curve(
    path: str | Path, column: Column | str, *, scale: LoadScale | None = None, body_weight: float | None = None
) -> LoadCurve:
    """Read the load from its own file (module docstring).

    Args:
        path: a ``.sto``, ``.mot`` or CSV file.
        column: the load's column, ``[-]NAME[:UNIT]`` (or a Column); ``NAME`` alone finds ``NAME_fx/_fy/_fz`` too.
        scale: how to scale the values; None for as they are.
        body_weight: body weight in [N], for a load in % body weight.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem (a missing column with the nearest label).
    """
    source = str(path)
    column = column if isinstance(column, Column) else Column.parse(str(column), "load")
    labels, label_line, rows, separator = _table(path, source)
    time = next((c for c, label in enumerate(labels) if label.strip().lower() in TIME_NAMES), 0)
    picked, name = _load_columns(labels, column.name, source, label_line)
    if len(rows) < MIN_SAMPLES:
        raise TrajectoryError(f"{len(rows)} samples; at least {MIN_SAMPLES} are needed", source=source)
    used = [time, *picked]
    values = np.empty((len(rows), len(used)))
    for k, (line_number, line) in enumerate(rows):
        row = cells(line, separator) if separator else line.split()
        if len(row) < len(labels):
            raise TrajectoryError(f"{len(row)} values, the labels are {len(labels)}", source=source, line=line_number)
        for j, c in enumerate(used):
            try:
                values[k, j] = number(row[c], separator not in ("", ","))
            except ValueError:
                raise TrajectoryError(
                    f"'{row[c].strip()}' is not a number", source=source, line=line_number, column=labels[c]
                ) from None
            if not math.isfinite(values[k, j]):
                raise TrajectoryError(
                    f"'{row[c].strip()}' is not finite", source=source, line=line_number, column=labels[c]
                )
    lines = np.array([n for n, _ in rows])
    t = values[:, 0]
    steps = np.diff(t)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0)) + 1
        raise TrajectoryError(
            f"time {t[k]:g} s does not increase (previous {t[k - 1]:g} s)",
            source=source,
            line=int(lines[k]),
            column=labels[time],
        )
    check_time_unit(t, "s", source, labels[time])  # a load logged in ms on the motion's clock in s (issue 38)
    raw = np.sqrt((values[:, 1:] ** 2).sum(axis=1)) if len(picked) == 3 else column.sign * values[:, 1]
    load = raw * _unit_scale(column, body_weight, source, name)
    if scale is not None:
        load = scale.apply(load)
    if np.any(load < 0):
        k = int(np.argmax(load < 0))
        raise TrajectoryError(
            f"load {load[k]:g} N is negative (F_e is a magnitude: flip the column's sign with a leading '-' if it is a compressive component)",
            source=source,
            line=int(lines[k]),
            column=name,
        )
    return LoadCurve(t, load, lines, source, name)


def _unit_scale(column: Column, body_weight: float | None, source: str, name: str) -> float:
    unit = column.unit or ("%BW" if body_weight is not None else "N")
    if unit == "%BW":
        if body_weight is None:
            raise TrajectoryError("the load is in % body weight: give the body weight", source=source, column=name)
        return body_weight / 100.0
    return {"N": 1.0, "kN": 1e3}[unit]


def _table(path, source: str) -> tuple[list[str], int, list[tuple[int, str]], str]:
    """(labels, their line, (line, text) of each data row, separator or '' for whitespace)."""
    lines = read_text_lines(path, "load file", TrajectoryError)
    if Path(source).suffix.lower() in (".mot", ".sto"):
        end = next((k for k, line in enumerate(lines) if line.strip().lower() == "endheader"), None)
        if end is None:
            raise TrajectoryError("no 'endheader' line: not an OpenSim .mot/.sto file", source=source)
        body = [(k, line) for k, line in enumerate(lines[end + 1 :], start=end + 2) if line.strip()]
        if not body:
            raise TrajectoryError("no column labels after 'endheader'", source=source, line=end + 1)
        label_line, text = body[0]
        labels = [label.strip() for label in (text.split("\t") if "\t" in text else text.split())]
        while labels and not labels[-1]:
            labels.pop()
        return labels, label_line, body[1:], ""
    numbered = data_lines(lines)
    if not numbered:
        raise TrajectoryError("the file is empty", source=source)
    label_line, text = numbered[0]
    separator = detect_separator(text, numbered[1][1] if len(numbered) > 1 else None)
    return [cell.strip() for cell in cells(text, separator)], label_line, numbered[1:], separator


def _load_columns(labels: list[str], name: str, source: str, line: int) -> tuple[list[int], str]:
    """The column(s) of the load: [one] by name (exactly, else case-blind), or [fx, fy, fz] of ``name``'s resultant."""
    for match in (lambda a, b: a == b, lambda a, b: a.lower() == b.lower()):
        found = [c for c, label in enumerate(labels) if match(label, name)]
        if len(found) == 1:
            return found, labels[found[0]]
        parts = [[c for c, label in enumerate(labels) if match(label, name + suffix)] for suffix in _RESULTANT]
        if all(len(p) == 1 for p in parts):
            return [p[0] for p in parts], f"{name}_fx/_fy/_fz resultant"
    bases = sorted(
        {
            re.sub(r"_f[xyz]$", "", label, flags=re.IGNORECASE)
            for label in labels
            if re.search(r"_f[xyz]$", label, re.IGNORECASE)
        }
    )
    near = difflib.get_close_matches(name, labels + bases, n=1, cutoff=0.0)
    hint = f"; did you mean '{near[0]}'?" if near else ""
    raise TrajectoryError(
        f"no load column '{name}' (nor '{name}_fx', '_fy', '_fz' for a resultant){hint}", source=source, line=line
    )

"""The snapshots of a long wear test: finding their files, reading their cycle counters, cutting a long log into windows, and the checks.

A lab logs a snapshot every so often (say 3 cycles at 1 kHz every 250,000
cycles): a rig log (:mod:`hipsim.rig.logs.reader`'s columns) with one more column,
``cycle``, the machine's cycle counter (a whole number, non-decreasing within
the file). :func:`find_snapshots` takes files, folders (their ``*.csv``) and
glob patterns in any order, scans each file's ``t_s`` and ``cycle`` once (a
few bytes a sample kept, the file read line by line), and returns
:class:`Snapshot` records sorted by their first cycle. With ``window=N`` every
file is instead one long log cut into windows of N cycles (whole windows
only: a last, incomplete window waits for the next run), each window located
by its byte offsets in the file, so a worker reads just its window
(:func:`snapshot_text`).

Everything is checked before any estimate is made, each problem one line
naming the file: no ``cycle`` column, a counter that is not a whole number
or decreases (with the line), two snapshots covering the same cycles, a
snapshot too short for the low-pass filter.
"""

from __future__ import annotations

import glob
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...exceptions import ArgumentError, TrajectoryError
from ..logs.smoothing import edge_samples, minimum_samples

__all__ = ["CYCLE_COLUMN", "STATION_LOADS", "Snapshot", "find_snapshots", "read_columns", "snapshot_text"]

#: The cycle counter's column.
CYCLE_COLUMN = "cycle"
#: Per-station load columns in [N], when the rig logs them.
STATION_LOADS = ("Fe_1_N", "Fe_2_N")


@dataclass(frozen=True)
class Snapshot:
    """One snapshot: a whole file, or a window of a long log.

    Attributes:
        path: the file.
        first_cycle: the counter's value at its first sample.
        last_cycle: the counter's value at its last sample.
        samples: its samples.
        rate: sample rate in [Hz].
        span: (first byte, stop byte, first line) of a window of a long log; None for a whole file.
    """

    path: str
    first_cycle: int
    last_cycle: int
    samples: int
    rate: float
    span: tuple[int, int, int] | None = None

    @property
    def name(self) -> str:
        """The file's name, with the window's cycles for a window."""
        base = Path(self.path).name
        return base if self.span is None else f"{base}[{self.first_cycle}-{self.last_cycle}]"

    @property
    def cycles(self) -> int:
        """Cycles it spans (counter values it holds)."""
        return self.last_cycle - self.first_cycle + 1


def _paths(logs: str | Path | Iterable[str | Path]) -> list[str]:
    """Files of the given files, folders (their *.csv) and glob patterns, each once, in sorted order."""
    items = [logs] if isinstance(logs, (str, Path)) else list(logs)
    found: list[str] = []
    for item in items:
        text = str(item)
        if os.path.isdir(text):
            found += sorted(str(p) for p in Path(text).glob("*.csv") if p.is_file())
        elif glob.has_magic(text):
            matches = sorted(p for p in glob.glob(text) if os.path.isfile(p))
            if not matches:
                raise TrajectoryError("no file matches this pattern", source=text)
            found += matches
        elif os.path.isfile(text):
            found.append(text)
        else:
            raise TrajectoryError("no such log file or folder", source=text)
    unique = list(dict.fromkeys(os.path.normpath(p) for p in found))
    if not unique:
        raise TrajectoryError("no rig logs (*.csv) found", source=", ".join(str(i) for i in items))
    return unique


def _header(stream, source: str) -> tuple[list[str], int, int]:
    """(column names, line number, byte offset after it) of the first line with anything on it."""
    number = 0
    for raw in iter(stream.readline, b""):
        number += 1
        text = raw.decode("utf-8-sig" if number == 1 else "utf-8", errors="replace")
        if text.strip(" \t\r\n,"):
            return [cell.strip() for cell in text.rstrip("\r\n").split(",")], number, stream.tell()
    raise TrajectoryError("the file is empty", source=source)


def _number(cell: bytes, source: str, line: int, column: str) -> float:
    try:
        return float(cell)
    except ValueError:
        raise TrajectoryError(
            f"'{cell.decode('utf-8', 'replace').strip()}' is not a number", source=source, line=line, column=column
        ) from None


@dataclass
class _Scan:
    """What the scan of one file keeps: per sample its cycle, time, byte offset and line."""

    cycle: np.ndarray
    t: np.ndarray
    offset: np.ndarray
    line: np.ndarray
    end: int  # byte offset of the file's end


def _scan(path: str) -> _Scan:
    """Read a file's ``cycle`` and ``t_s`` columns, checking the counter."""
    with open(path, "rb") as stream:
        header, number, position = _header(stream, path)
        if CYCLE_COLUMN not in header:
            raise TrajectoryError(
                f"no '{CYCLE_COLUMN}' column: a snapshot needs the machine's cycle counter", source=path, line=number
            )
        if "t_s" not in header:
            raise TrajectoryError("missing time column 't_s'", source=path, line=number)
        c, k = header.index(CYCLE_COLUMN), header.index("t_s")
        cycles, times, offsets, lines = [], [], [], []
        previous = -math.inf
        for raw in iter(stream.readline, b""):
            number += 1
            start, position = position, position + len(raw)
            if not raw.strip(b" \t\r\n,"):
                continue
            cells = raw.split(b",")
            if len(cells) != len(header):
                raise TrajectoryError(f"{len(cells)} cells, the header has {len(header)}", source=path, line=number)
            value = _number(cells[c], path, number, CYCLE_COLUMN)
            if not (math.isfinite(value) and value == int(value) and value >= 0):
                raise TrajectoryError(
                    f"the cycle counter must be a whole number ≥ 0, got '{cells[c].decode().strip()}'",
                    source=path,
                    line=number,
                    column=CYCLE_COLUMN,
                )
            if value < previous:
                raise TrajectoryError(
                    f"the cycle counter decreases ({previous:.0f} → {value:.0f}): one snapshot a file, its counter non-decreasing",
                    source=path,
                    line=number,
                    column=CYCLE_COLUMN,
                )
            previous = value
            cycles.append(int(value))
            times.append(_number(cells[k], path, number, "t_s"))
            offsets.append(start)
            lines.append(number)
    if len(cycles) < 2:
        raise TrajectoryError(f"{len(cycles)} samples; a snapshot needs many", source=path)
    return _Scan(
        np.array(cycles, dtype=np.int64),
        np.array(times),
        np.array(offsets, dtype=np.int64),
        np.array(lines, dtype=np.int64),
        position,
    )


def _check_length(path: str, samples: int, rate: float, cutoff: float | None, what: str) -> None:
    """A snapshot must be long enough for the filter, and leave samples between its edges."""
    if not (math.isfinite(rate) and rate > 0):
        raise TrajectoryError(f"{what}: its times do not increase", source=path)
    if cutoff is None:
        return
    need = max(minimum_samples(rate, cutoff), 2 * edge_samples(rate, cutoff) + 8)
    if samples < need:
        raise TrajectoryError(
            f"{what} has {samples} samples, too short for the {cutoff:g} Hz low-pass at {rate:.6g} Hz (at least {need}, "
            f"{need / rate:.3g} s): log longer snapshots or give a higher cutoff",
            source=path,
        )


def find_snapshots(logs, window: int | None = None, cutoff: float | None = 20.0) -> list[Snapshot]:
    """The snapshots of the given logs, checked, sorted by first cycle.

    Args:
        logs: a file, folder (its ``*.csv``) or glob pattern, or a list of them.
        window: cycles per window to cut each file into (a long log); None: one snapshot a file.
        cutoff: the low-pass cutoff in [Hz] the snapshots will get (None: none), for the length check.

    Returns:
        The snapshots, by first cycle.

    Raises:
        TrajectoryError: naming the file (and line): see the module docstring.
        ArgumentError: a window that is not a positive whole number of cycles.
    """
    if window is not None and (isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1):
        raise ArgumentError("window", window, "a positive whole number of cycles")
    snapshots: list[Snapshot] = []
    for path in _paths(logs):
        scan = _scan(path)
        if window is None:
            n = scan.cycle.size
            rate = (n - 1) / (scan.t[-1] - scan.t[0]) if scan.t[-1] != scan.t[0] else math.nan
            _check_length(path, n, rate, cutoff, "the snapshot")
            snapshots.append(Snapshot(path, int(scan.cycle[0]), int(scan.cycle[-1]), n, float(rate)))
            continue
        snapshots += _windows(path, scan, int(window), cutoff)
    _check_overlaps(snapshots)
    return sorted(snapshots, key=lambda s: (s.first_cycle, s.path))


def _windows(path: str, scan: _Scan, window: int, cutoff: float | None) -> list[Snapshot]:
    """Whole windows of ``window`` cycles of one long log (the first starting at its first cycle)."""
    first = int(scan.cycle[0])
    index = (scan.cycle - first) // window
    n = scan.cycle.size
    rate = (n - 1) / (scan.t[-1] - scan.t[0]) if scan.t[-1] != scan.t[0] else math.nan
    out = []
    bounds = np.flatnonzero(np.diff(index)) + 1
    starts, stops = np.concatenate([[0], bounds]), np.concatenate([bounds, [n]])
    for a, b in zip(starts, stops):
        if index[a] == index[-1] and scan.cycle[-1] < first + (index[a] + 1) * window - 1:
            break  # the last window is not complete yet
        stop_byte = int(scan.offset[b]) if b < n else scan.end
        _check_length(path, int(b - a), rate, cutoff, f"the window of cycles {scan.cycle[a]}-{scan.cycle[b - 1]}")
        out.append(
            Snapshot(
                path,
                int(scan.cycle[a]),
                int(scan.cycle[b - 1]),
                int(b - a),
                float(rate),
                (int(scan.offset[a]), stop_byte, int(scan.line[a])),
            )
        )
    if not out:
        raise TrajectoryError(
            f"holds no whole window of {window} cycles (cycles {scan.cycle[0]}-{scan.cycle[-1]})", source=path
        )
    return out


def _check_overlaps(snapshots: Sequence[Snapshot]) -> None:
    """Two snapshots may not cover the same cycles (the same snapshot twice, or a copy)."""
    ordered = sorted(snapshots, key=lambda s: (s.first_cycle, s.last_cycle))
    for before, after in zip(ordered, ordered[1:]):
        if after.first_cycle <= before.last_cycle and after.path != before.path:
            raise TrajectoryError(
                f"covers cycles {after.first_cycle}-{after.last_cycle}, as does {before.path} ({before.first_cycle}-{before.last_cycle}): "
                "each cycle in one snapshot only (a copied file?)",
                source=after.path,
            )


def snapshot_text(snapshot: Snapshot) -> bytes | None:
    """A window's CSV text (the file's header and the window's lines); None for a whole file (read it by its path)."""
    if snapshot.span is None:
        return None
    start, stop, _ = snapshot.span
    with open(snapshot.path, "rb") as stream:
        header = b""
        for raw in iter(stream.readline, b""):
            if raw.strip(b" \t\r\n,"):
                header = raw
                break
        stream.seek(start)
        return header + stream.read(stop - start)


def read_columns(path: str | Path, names: Sequence[str]) -> dict[str, np.ndarray] | None:
    """The named columns of a CSV file as floats (blank lines skipped); None when any is missing.

    Only for files the rig-log reader has already checked (every cell a number).
    """
    with open(path, "rb") as stream:
        header, _, _ = _header(stream, str(path))
        if any(name not in header for name in names):
            return None
        where = [header.index(name) for name in names]
        values: list[list[float]] = [[] for _ in names]
        for raw in iter(stream.readline, b""):
            if not raw.strip(b" \t\r\n,"):
                continue
            cells = raw.split(b",")
            for column, k in zip(values, where):
                column.append(float(cells[k]))
    return {name: np.array(column) for name, column in zip(names, values)}

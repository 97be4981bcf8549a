"""The snapshots of a long wear test: their files, which are complete, each file's identity, and a long log cut into windows.

A lab logs a snapshot every so often (say 3 cycles at 1 kHz every 250,000
cycles): a rig log (the rig-log reader's columns, :mod:`hipsim.rig.logs.reader`:
comments, ``;`` or tab separators, decimal commas as everywhere) with one more
column, ``cycle``, the machine's cycle counter. :func:`find_snapshots` takes
files, folders (their ``*.csv``) and glob patterns in any order and lists each
file with its size and SHA-256, without reading its values: a snapshot is read
once, by the rig-log reader, where it is estimated
(:mod:`~hipsim.rig.monitoring.snapshot_log`), so a file the reader refuses is
a skipped snapshot with the reader's reason, not a stopped test.

A file changed less than ``settle`` seconds ago is taken as still being
written: it waits for the next run (listed, not read). With ``window=N`` every
file is one long log, scanned once by the reader for its cycle counter and cut
into windows of N cycles (whole windows only: a last, incomplete window waits
for the next run), each window its file lines, which a worker reads alone.
"""

from __future__ import annotations

import glob
import hashlib
import math
import os
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ...channels import CHANNEL_SUFFIXES, channel_kind, read_channels
from ...clock import SYSTEM_CLOCK, Clock
from ...exceptions import ArgumentError, HipsimError, TrajectoryError
from ..logs.reader import RigLogFile

__all__ = [
    "COMMANDED_LOAD",
    "CYCLE_COLUMN",
    "STATION_LOADS",
    "Skipped",
    "Snapshot",
    "check_counter",
    "find_snapshots",
    "settled",
    "skipped",
]

#: The cycle counter's column.
CYCLE_COLUMN = "cycle"
#: Per-station load columns in [N], when the rig logs them.
STATION_LOADS = ("Fe_1_N", "Fe_2_N")
#: The commanded load in [N], when the rig logs it (compared with the measured ``Fe_N``: a load-cell drift).
COMMANDED_LOAD = "Fe_cmd_N"
_HASH_BLOCK = 1 << 20
#: A folder's files read as snapshots: CSV and the channel files (TDMS, HDF5: :mod:`hipsim.channels`).
LOG_SUFFIXES = (".csv", *CHANNEL_SUFFIXES)


@dataclass(frozen=True)
class Snapshot:
    """One snapshot: a whole file, or a window of a long log.

    Attributes:
        path: the file.
        size: its bytes (a window's: its lines').
        sha256: the SHA-256 of those bytes, hex.
        lines: (first, stop) file lines of a window of a long log; None for a whole file.
        first_cycle: a window's first cycle (None for a whole file until it is read).
        last_cycle: a window's last cycle (likewise).
        ends_with_newline: whether the file's last line has its line end (a file cut mid-line has none).
    """

    path: str
    size: int
    sha256: str
    lines: tuple[int, int] | None = None
    first_cycle: int | None = None
    last_cycle: int | None = None
    ends_with_newline: bool = True

    @property
    def name(self) -> str:
        """The file's name, with the window's cycles for a window."""
        base = Path(self.path).name
        return base if self.lines is None else f"{base}[{self.first_cycle}-{self.last_cycle}]"


@dataclass(frozen=True)
class Skipped:
    """A snapshot that is not in the chart, and why.

    Attributes:
        name: the snapshot's name (its file; a window's cycles).
        path: the file.
        reason: the reason, as the error said it (file, line, column).
        kind: "unreadable" (the reader or a check refused it), "waiting" (still being written),
            or "duplicate" (its cycles are another snapshot's).
        line: the file line the reason names, or None.
        size: the file's (a window's) bytes when it was looked at, or None when it could not be read.
        sha256: the SHA-256 of those bytes (hex), or "" when it could not be read.
    """

    name: str
    path: str
    reason: str
    kind: str = "unreadable"
    line: int | None = None
    size: int | None = None
    sha256: str = ""


def skipped(snapshot: Snapshot, error: HipsimError, kind: str = "unreadable") -> Skipped:
    """The skipped snapshot an error makes: its message is the reason, its line (when it names one) kept."""
    line = getattr(error, "line", None)
    reason = str(error)
    if getattr(error, "column", None) == "t_s" or "'t_s'" in reason and "increase" in reason:
        reason += " (time stamps too coarse for the rate? give --rate HZ to read the times from the sample index)"
    return Skipped(
        snapshot.name,
        snapshot.path,
        reason,
        kind,
        line if isinstance(line, int) else None,
        snapshot.size,
        snapshot.sha256,
    )


def _paths(logs: str | Path | Iterable[str | Path]) -> list[str]:
    """Files of the given files, folders (their *.csv, *.tdms, *.h5, *.hdf5, *.hdf) and glob patterns, each once, in
    sorted order."""
    items = [logs] if isinstance(logs, (str, Path)) else list(logs)
    found: list[str] = []
    for item in items:
        text = str(item)
        if os.path.isdir(text):
            found += sorted(str(p) for p in Path(text).iterdir() if p.suffix.lower() in LOG_SUFFIXES and p.is_file())
        elif glob.has_magic(text):
            found += sorted(p for p in glob.glob(text) if os.path.isfile(p))
        elif os.path.isfile(text):
            found.append(text)
        else:
            raise TrajectoryError("no such log file or folder", source=text)
    return list(dict.fromkeys(os.path.normpath(p) for p in found))


def _identity(path: str, cache: dict | None) -> tuple[int, str, bool]:
    """(bytes, SHA-256, ends with a line end) of a file; ``cache`` keyed by (path, size, mtime) spares a rehash."""
    status = os.stat(path)
    key = (path, status.st_size, status.st_mtime_ns)
    if cache is not None and key in cache:
        return cache[key]
    digest = hashlib.sha256()
    last = b"\n"
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(_HASH_BLOCK), b""):
            digest.update(block)
            last = block[-1:]
    # A line end is a text file's: a TDMS or HDF5 file is never "cut mid-line".
    ended = last == b"\n" or status.st_size == 0 or channel_kind(path) is not None
    found = (status.st_size, digest.hexdigest(), ended)
    if cache is not None:
        cache[key] = found
    return found


def check_counter(cycles: np.ndarray, lines: np.ndarray, source: str) -> np.ndarray:
    """The cycle counter as whole numbers, checked: ≥ 0, whole, non-decreasing (naming the line of the first that is not).

    Raises:
        TrajectoryError: naming the file, line and column.
    """
    bad = ~(np.isfinite(cycles) & (cycles >= 0) & (cycles == np.floor(cycles)))
    if bad.any():
        k = int(np.argmax(bad))
        raise TrajectoryError(
            f"the cycle counter must be a whole number ≥ 0, got {cycles[k]:g}",
            source=source,
            line=int(lines[k]),
            column=CYCLE_COLUMN,
        )
    down = np.flatnonzero(np.diff(cycles) < 0)
    if down.size:
        k = int(down[0]) + 1
        raise TrajectoryError(
            f"the cycle counter decreases ({cycles[k - 1]:.0f} → {cycles[k]:.0f}): one snapshot a file, its counter "
            "non-decreasing",
            source=source,
            line=int(lines[k]),
            column=CYCLE_COLUMN,
        )
    return cycles.astype(np.int64)


def find_snapshots(
    logs,
    window: int | None = None,
    settle: float = 0.0,
    torque_constant: float | None = None,
    rate: float | None = None,
    cache: dict | None = None,
    wait: bool = False,
    columns: str | None = None,
    clock: Clock = SYSTEM_CLOCK,
) -> tuple[list[Snapshot], list[Skipped]]:
    """The snapshots of the given logs, and those left out (still being written; with windows, a file the reader refuses).

    Args:
        logs: a file, folder (its ``*.csv``) or glob pattern, or a list of them.
        window: cycles per window to cut each file into (a long log); None: one snapshot a file.
        settle: a file changed less than this many seconds ago is still being written: it waits (for the next round
            of a watch; with ``wait``, here).
        torque_constant: the motors' torque constant in [N·m/A] (a window's scan reads the log: logs of currents need it).
        rate: sample rate in [Hz] to read the times from the sample index (time stamps too coarse), or None.
        cache: identities already computed, (path, size, mtime) → (bytes, SHA-256, line end), filled in.
        wait: a batch run's rule: sleep until every file has been unchanged for ``settle`` seconds, at most ``settle``
            seconds in all, then read them all (one still changing then is read as it is: a shorter snapshot is
            marked incomplete, a line cut short is skipped with its reason).
        columns: a TDMS or HDF5 log's column map (:mod:`hipsim.channels`), for a window's scan.
        clock: whose wall time a file's age is measured against (:mod:`hipsim.clock`; a test passes its own).

    Returns:
        The snapshots (in file order; whole files' cycles are known once read), and the skipped.

    Raises:
        TrajectoryError: a name that is no file, folder or matching pattern.
        ArgumentError: a window that is not a positive whole number of cycles, a negative settle time.
    """
    if window is not None and (isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1):
        raise ArgumentError("window", window, "a positive whole number of cycles")
    if not (math.isfinite(settle) and settle >= 0):
        raise ArgumentError("settle", settle, "seconds ≥ 0")
    snapshots: list[Snapshot] = []
    left: list[Skipped] = []
    paths = _paths(logs)
    if wait:
        settled(paths, settle, clock=clock.time, sleep=clock.sleep)
    now = clock.time()
    for path in paths:
        name = Path(path).name
        try:
            status = os.stat(path)
            age = now - status.st_mtime
            if age < settle and not wait:
                size, sha, _ = _identity(path, cache)
                left.append(
                    Skipped(
                        name,
                        path,
                        f"{path}: changed {max(age, 0.0):.3g} s ago: still being written? read once unchanged for "
                        f"{settle:g} s",
                        "waiting",
                        size=size,
                        sha256=sha,
                    )
                )
                continue
            if window is None:
                size, sha, newline = _identity(path, cache)
                snapshots.append(Snapshot(path, size, sha, ends_with_newline=newline))
                continue
        except OSError as error:  # gone between the listing and now
            left.append(Skipped(name, path, f"{path}: cannot read ({error.strerror})"))
            continue
        try:
            snapshots += _windows(path, int(window), torque_constant, rate, columns)
        except HipsimError as error:
            size, sha, _ = _identity(path, cache)
            left.append(skipped(Snapshot(path, size, sha), error))
    return snapshots, left


def settled(paths: Sequence[str], settle: float, clock=SYSTEM_CLOCK.time, sleep=SYSTEM_CLOCK.sleep) -> float:
    """Sleep until every file has been unchanged for ``settle`` seconds, at most ``settle`` seconds in all; the time slept.

    A file that changes while waited for is waited for again, within the same bound: a file still being written after
    it is read as it is (a batch run's rule; a watch waits for its next round instead).
    """
    start = clock()
    while True:
        youngest = 0.0
        for path in paths:
            try:
                youngest = max(youngest, settle - (clock() - os.stat(path).st_mtime))
            except OSError:
                continue  # gone: said when it is read
        left = settle - (clock() - start)
        if youngest <= 0 or left <= 0:
            return clock() - start
        sleep(min(youngest, left))


def _windows(
    path: str, window: int, torque_constant: float | None, rate: float | None, columns: str | None = None
) -> list[Snapshot]:
    """Whole windows of ``window`` cycles of one long log (the first starting at its first cycle), each its lines (a
    TDMS or HDF5 log's: its sample numbers)."""
    raw = RigLogFile(path, torque_constant, keep=(CYCLE_COLUMN,), rate=rate, columns=columns)
    try:
        if CYCLE_COLUMN not in raw.kept:
            raise TrajectoryError(
                f"no '{CYCLE_COLUMN}' column: a snapshot needs the machine's cycle counter", source=path
            )
        cycles = check_counter(raw.kept[CYCLE_COLUMN], raw.lines, path)
        lines = raw.lines
    finally:
        raw.close()
    first = int(cycles[0])
    index = (cycles - first) // window
    n = cycles.size
    bounds = np.flatnonzero(np.diff(index)) + 1
    starts, stops = np.concatenate([[0], bounds]), np.concatenate([bounds, [n]])
    spans = []
    for a, b in zip(starts, stops):
        if index[a] == index[-1] and cycles[-1] < first + (index[a] + 1) * window - 1:
            break  # the last window is not complete yet
        stop_line = int(lines[b]) if b < n else int(lines[-1]) + 1
        spans.append((int(lines[a]), stop_line, int(cycles[a]), int(cycles[b - 1])))
    if not spans:
        raise TrajectoryError(
            f"holds no whole window of {window} cycles (cycles {cycles[0]}-{cycles[-1]})", source=path
        )
    if channel_kind(path) is not None:
        identities = _sample_identities(path, [(a, b) for a, b, _, _ in spans], columns)
    else:
        identities = _line_identities(path, [(a, b) for a, b, _, _ in spans])
    return [Snapshot(path, size, sha, (a, b), c0, c1) for (a, b, c0, c1), (size, sha) in zip(spans, identities)]


def _line_identities(path: str, spans: Sequence[tuple[int, int]]) -> list[tuple[int, str]]:
    """(bytes, SHA-256) of each span of file lines [first, stop), in one pass over the file."""
    digests = [hashlib.sha256() for _ in spans]
    sizes = [0] * len(spans)
    k = 0
    with open(path, "rb") as stream:
        for number, raw in enumerate(stream, start=1):
            while k < len(spans) and number >= spans[k][1]:
                k += 1
            if k == len(spans):
                break
            if number >= spans[k][0]:
                digests[k].update(raw)
                sizes[k] += len(raw)
    return [(size, digest.hexdigest()) for size, digest in zip(sizes, digests)]


def _sample_identities(path: str, spans: Sequence[tuple[int, int]], columns: str | None) -> list[tuple[int, str]]:
    """(bytes, SHA-256) of each span of a channel file's samples [first, stop) (numbered from 1): of the float64 values
    of its rows, every column read, in the table's order."""
    table = read_channels(path, columns, "log file", TrajectoryError)
    found = []
    for first, stop in spans:
        data = np.ascontiguousarray(table.values[first - 1 : stop - 1]).tobytes()
        found.append((len(data), hashlib.sha256(data).hexdigest()))
    return found

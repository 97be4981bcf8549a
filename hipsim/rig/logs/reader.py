"""The rig-log reader: a CSV file scanned once, every value checked, its samples in SI units.

A rig log is a table read with the rules of trajectory files (:mod:`hipsim.tables`: comma, tab or
``;`` separated, decimal commas in tab- or ``;``-separated files, ``#`` comments and blank lines skipped; header with
units, evenly spaced ``t_s``, a clear error naming the file, line and column):

- ``t_s`` and ``Fe_N`` (the measured load);
- the motor torques ``tau_1_Nmm, tau_2_Nmm, tau_3_Nmm``, or the motor
  currents ``current_1_A, current_2_A, current_3_A`` and the motors' torque
  constant in N·m/A (torque = constant × current; with both, the torques are used);
- the motion as the platform angles ``alpha_deg, beta_deg, gamma_deg`` (or
  all three ``_rad``, as from an attitude sensor), or platform 1's slider
  heights ``L_11_mm, L_12_mm, L_13_mm`` (the motor encoders), or both.

Other columns (temperatures, set points …) are ignored and listed in
:attr:`RigLog.ignored`. :func:`read_rig_log` returns the samples as they are,
in SI units; turning encoder heights into angles needs the machine, so that
is done a layer up (:func:`hipsim.rig.load_log`).

The reader's :class:`RigLog` is the samples as the file has them; the log the
models take, filtered and differentiated, is :mod:`hipsim.rig.logs.log`'.
"""

from __future__ import annotations

import difflib
import io
import math
import tempfile
from collections.abc import Mapping
from dataclasses import dataclass
from itertools import chain
from pathlib import Path

import numpy as np

from ...arrays import check_shapes
from ...channels import channel_kind, read_channels
from ...exceptions import TrajectoryError
from ...motion.build import MAX_LOAD, check_time, check_time_unit, relative_time
from ...motion.trajectories import ANGLE_NAMES
from ...tables import blank, open_text
from .blocks import Hashed, Reread, line_blocks, text_blocks
from .text_rows import header_of, parse_block, parse_lines

__all__ = ["CURRENT_COLUMNS", "HEIGHT_COLUMNS", "TORQUE_COLUMNS", "RigLog", "RigLogFile", "read_rig_log"]

TORQUE_COLUMNS = tuple(f"tau_{i}_Nmm" for i in (1, 2, 3))
CURRENT_COLUMNS = tuple(f"current_{i}_A" for i in (1, 2, 3))
HEIGHT_COLUMNS = tuple(f"L_1{i}_mm" for i in (1, 2, 3))
#: Lines per block of the reader's scan: some 10 MB of values at a time.
SCAN_LINES = 100_000
#: Largest torque in [N·mm] and slider height in [mm] a log may give: beyond, a unit slip.
MAX_TORQUE_NMM = 1e9
MAX_HEIGHT_MM = 1e5


@dataclass(frozen=True, eq=False)
class RigLog:
    """A rig log as read, SI units, one row per sample.

    Attributes:
        t: sample times in [s], (N,), evenly spaced.
        Fe: measured load in [N], (N,).
        tau: motor torques in [N·m], (N, 3) (from the currents when the log has no torques).
        angles: platform gait angles [α, β, γ] in [rad], (N, 3), or None when the log has none.
        heights: platform 1's slider heights L_11, L_12, L_13 in [m], (N, 3), or None.
        lines: the file line of each sample, (N,), for messages.
        source: the file's path.
        torque_from: "torques" or "currents".
        ignored: columns the reader does not use.
        angle_unit: "deg" or "rad", the unit of the file's angle columns (None without angles).
    """

    t: np.ndarray
    Fe: np.ndarray
    tau: np.ndarray
    angles: np.ndarray | None
    heights: np.ndarray | None
    lines: np.ndarray
    source: str
    torque_from: str = "torques"
    ignored: tuple[str, ...] = ()
    angle_unit: str | None = None

    def __post_init__(self):
        shapes = {"t": ("N",), "Fe": ("N",), "tau": ("N", 3), "lines": ("N",)}
        shapes |= {name: ("N", 3) for name in ("angles", "heights") if getattr(self, name) is not None}
        check_shapes(self, shapes)

    def __len__(self) -> int:
        return self.t.size

    @property
    def rate(self) -> float:
        """Sample rate in [Hz]."""
        return (self.t.size - 1) / (self.t[-1] - self.t[0])


# --- The reader -----------------------------------------------------------------------------


def _missing(name: str, header: list[str], what: str, source: str, line: int | None) -> TrajectoryError:
    close = difflib.get_close_matches(name, header, n=1, cutoff=0.7)
    hint = f" (the file has '{close[0]}': check the name and its unit)" if close else ""
    return TrajectoryError(f"missing {what} column '{name}'{hint}", source=source, line=line)


def _group(names: tuple[str, ...], header: list[str], what: str, source: str, line: int | None) -> bool:
    """True if all of ``names`` are columns, False if none is; a partial group is an error naming the first missing."""
    present = [name in header for name in names]
    if all(present):
        return True
    if any(present):
        raise _missing(names[present.index(False)], header, what, source, line)
    return False


class _Worst:
    """The largest |value| of a column group seen so far, its first occurrence: (value, line, column name)."""

    def __init__(self):
        self.value, self.line, self.column = 0.0, 0, ""

    def add(self, values: np.ndarray, lines: np.ndarray, names: tuple[str, ...]) -> None:
        if values.size == 0:
            return
        k, c = np.unravel_index(np.argmax(np.abs(values)), values.shape)
        if abs(values[k, c]) > abs(self.value):  # strictly: an equal later one is not the first
            self.value, self.line, self.column = float(values[k, c]), int(lines[k]), names[c]


class RigLogFile:
    """A rig log scanned once in blocks, every value checked, its samples then read back a piece at a time.

    The scan keeps the times and file lines in memory (16 bytes a sample) and
    the rest, in SI units, in a temporary binary file; :meth:`piece` reads
    samples back from it, :meth:`read` all of them. The checks and their
    messages are :func:`read_rig_log`'s (which is this, read whole).

    Args:
        path: the CSV file (columns in the module docstring), or a TDMS or HDF5 file of those channels
            (:mod:`hipsim.channels`).
        torque_constant: the motors' torque constant in [N·m/A], for logs of motor currents.
        block: lines parsed at a time (and some hundred bytes a line read at a time, 4 MiB at most).
        keep: other columns to keep as they are (numbers, checked finite like every cell), in :attr:`kept` by name
            when the file has them (e.g. a wear test's ``cycle`` counter).
        rate: the sample rate in [Hz] to take the times from the sample index (t₀ + k/rate) when the file's time
            stamps are too coarse to order the samples (too few significant digits); they must still not decrease
            and span the same time to 1 %. None: the file's times, checked evenly spaced.
        lines: (first, stop): read only the data lines first ≤ line < stop (a window of a long log; the header is
            the file's), or None for all. The file is read no further than the block holding line stop − 1, and
            nothing after the window is parsed; :attr:`sha256` is then of the bytes read, not the file's. (A TDMS or
            HDF5 file's "lines" are its samples' numbers from 1; :attr:`sha256` is the whole file's.)
        columns: a TDMS or HDF5 file's column map (:func:`hipsim.channels.read_channels`: ``NAME=GROUP/CHANNEL,…``,
            a bare ``GROUP`` read by its names), or None for its one group by its names; refused for a CSV.

    Raises:
        TrajectoryError: as :func:`read_rig_log`.
    """

    def __init__(
        self,
        path: str | Path,
        torque_constant: float | None = None,
        block: int = SCAN_LINES,
        keep: tuple[str, ...] = (),
        rate: float | None = None,
        lines: tuple[int, int] | None = None,
        columns: str | Mapping[str, str] | None = None,
    ):
        self.source = str(path)
        try:
            window = (1, math.inf) if lines is None else lines
            self._read(path, torque_constant, block, keep, rate, window, columns)
        except BaseException:  # a refused file leaves no temporary store open until the garbage collector's turn
            if hasattr(self, "_store"):
                self._store.close()
            raise

    def _read(
        self, path, torque_constant, block: int, keep: tuple[str, ...], rate, window: tuple[int, float], columns
    ) -> None:
        """Scan the file (see the class's arguments), storing its lines and setting the attributes."""
        source = self.source
        if channel_kind(path) is not None:
            times, numbers, state = self._channels(path, columns, torque_constant, block, keep, window)
        else:
            if columns is not None:
                raise TrajectoryError(
                    "a column map of channels (--columns GROUP/CHANNEL) applies to TDMS and HDF5 logs; a CSV log "
                    "is read by its header's names",
                    source=source,
                )
            times, numbers, state = self._text(path, torque_constant, block, keep, window)
        worst, low, high, bad, kept = state
        if not times:
            raise TrajectoryError("no samples below the header", source=source)
        if bad is not None:
            raise TrajectoryError(bad[0], source=source, line=bad[1], column=bad[2])
        self.t = np.concatenate(times)
        del times  # one copy at a time: an hour's log has 3.6 M of each
        self.lines = np.concatenate(numbers)
        del numbers
        #: The columns asked for with ``keep`` that the file has, by name, (N,) each.
        self.kept = {name: np.concatenate(parts) for name, parts in kept.items()}
        self._check(worst, low, high, rate)

    def _channels(self, path, columns, torque_constant, block: int, keep: tuple[str, ...], window):
        """A TDMS or HDF5 file's channels (:func:`hipsim.channels.read_channels`) stored as a CSV's rows would be;
        its "lines" are the samples' numbers, from 1."""
        table = read_channels(path, columns, "log file", TrajectoryError)
        #: The file's SHA-256 (hex) and size in [bytes] (of the whole file, a window's too).
        self.sha256, self.size = table.sha256, table.size
        first, stop = window
        n = table.values.shape[0]
        lo, hi = max(0, int(first) - 1), int(min(n, stop - 1))

        def parsed():
            for a in range(lo, hi, block):
                b = min(a + block, hi)
                yield table.values[a:b], np.arange(a + 1, b + 1, dtype=np.int64)

        return self._store_blocks(list(table.names), None, parsed, torque_constant, keep)

    def _text(self, path, torque_constant, block: int, keep: tuple[str, ...], window):
        """A CSV (or ``;``/tab-separated) log scanned in blocks of lines."""
        source = self.source
        with open_text(path, "log file", TrajectoryError) as opened:
            hashed = Hashed(opened)
            size = min(max(block * 100, 1 << 16), 1 << 22)  # bytes read at a time: some ``block`` lines, 4 MiB at most
            stream = io.BufferedReader(hashed, min(size, 1 << 20))
            try:
                blocks = text_blocks(stream, source, size)
                times, numbers, state = self._scan(blocks, torque_constant, block, keep, window)
            except Reread:  # not UTF-8, or a line too long: again line by line from the start, for the exact line
                if hasattr(self, "_store"):  # the first try's store
                    self._store.close()
                opened.seek(0)
                hashed = Hashed(opened)
                stream = io.BufferedReader(hashed, 1 << 20)
                blocks = line_blocks(stream, source, block, window[1])
                times, numbers, state = self._scan(blocks, torque_constant, block, keep, window)
            # Read whole, the scan has reached the file's end (hashed to its last byte); a window's read stops after it.
        #: The file's SHA-256 (hex) and size in [bytes], of the bytes this one read parsed.
        self.sha256, self.size = hashed.digest.hexdigest(), hashed.size
        return times, numbers, state

    def _scan(self, blocks, torque_constant, block: int, keep: tuple[str, ...], window: tuple[int, float]):
        """Parse the blocks: the header, then every data line's values checked and stored; the times and lines kept.

        Only the data lines first ≤ line < stop of ``window`` are parsed; the blocks are not read past stop.
        """
        source = self.source
        found: list[tuple[int, str]] = []  # the header and the first row, line by line
        after: tuple[int, list[str]] = (1, [])  # the lines after them in their block
        for number, lines in blocks:
            for k, line in enumerate(lines):
                if not blank(line) and not line.lstrip().startswith("#"):
                    found.append((number + k, line))
                    if len(found) == 2:
                        after = (number + k + 1, lines[k + 1 :])
                        break
            if len(found) == 2:
                break
        rows = iter(found)
        header, header_line, separator, first_row = header_of(rows, source)
        first, stop = window

        def parsed():
            if first_row is not None and first <= first_row[0] < stop:
                yield parse_block([first_row], header, separator, source)
            # The rest of the header's block, then the blocks after it (a comment or blank line: line by line);
            # of a window, only its lines, and no block read after the one that holds its last.
            for number, lines in chain([after], blocks):
                lo = max(0, first - number)
                hi = len(lines) if number + len(lines) <= stop else max(0, int(stop - number))
                for a in range(lo, hi, block):
                    yield parse_lines(number + a, lines[a : min(a + block, hi)], header, separator, source)
                if number + len(lines) >= stop:
                    return

        return self._store_blocks(header, header_line, parsed, torque_constant, keep)

    def _store_blocks(self, header: list[str], header_line: int | None, parsed, torque_constant, keep: tuple[str, ...]):
        """Check and store the values of ``parsed()``'s blocks ((values (M, C), their lines (M,))) under ``header``."""
        self._layout(header, header_line, torque_constant)
        kept_index = {name: header.index(name) for name in keep if name in header}
        kept: dict[str, list[np.ndarray]] = {name: [] for name in kept_index}
        self._store = tempfile.TemporaryFile()
        times, numbers = [], []
        worst = {"torque": _Worst(), "angle": _Worst(), "height": _Worst()}
        low = high = None  # (load, line) of the least and largest load, first occurrences
        bad = None

        for values, at in parsed():
            if bad is None and not np.all(np.isfinite(values)):
                k, c = np.argwhere(~np.isfinite(values))[0]
                bad = (f"'{values[k, c]}' is not finite", int(at[k]), header[c])
            if len(values) == 0:
                continue
            columns = self._columns(values)
            worst["torque"].add(values[:, self._torque_index], at, self._torque_names)
            if self.angle_unit:
                worst["angle"].add(values[:, self._angle_index], at, self._angle_names)
            if self._height_index:
                worst["height"].add(values[:, self._height_index], at, HEIGHT_COLUMNS)
            load = columns[:, 1]
            k, j = int(np.argmin(load)), int(np.argmax(load))
            if low is None or load[k] < low[0]:
                low = (float(load[k]), int(at[k]))
            if high is None or load[j] > high[0]:
                high = (float(load[j]), int(at[j]))
            for name, c in kept_index.items():
                kept[name].append(values[:, c].copy())
            times.append(columns[:, 0].copy())
            numbers.append(at)
            columns.tofile(self._store)
        return times, numbers, (worst, low, high, bad, kept)

    # The columns of the store, in SI: t, Fe, τ (3), then the angles (3) and the heights (3) when the log has them.
    def _layout(self, header: list[str], header_line: int | None, torque_constant) -> None:
        source = self.source
        column = {name: k for k, name in enumerate(header)}
        for name in ("t_s", "Fe_N"):
            if name not in column:
                raise _missing(name, header, "time" if name == "t_s" else "load", source, header_line)
        has_torques = _group(TORQUE_COLUMNS, header, "torque", source, header_line)
        has_currents = _group(CURRENT_COLUMNS, header, "current", source, header_line)
        if has_torques:
            self._torque_names, self._scale, self.torque_from = TORQUE_COLUMNS, 1e-3, "torques"
            self.torque_constant = None
        elif has_currents:
            if torque_constant is None:
                raise TrajectoryError(
                    "the log gives motor currents (current_1_A …) but no torque constant in N·m/A was given to turn them into torques: "
                    "give --torque-constant NM_PER_A (torque_constant= in Python)",
                    source=source,
                )
            if isinstance(torque_constant, bool) or not (
                isinstance(torque_constant, (int, float)) and math.isfinite(torque_constant) and torque_constant > 0
            ):
                raise TrajectoryError(
                    f"the torque constant must be a positive number in N·m/A, got {torque_constant!r}", source=source
                )
            self._torque_names, self._scale, self.torque_from = CURRENT_COLUMNS, float(torque_constant), "currents"
            self.torque_constant = float(torque_constant)
        else:
            close = [
                c for c in header if difflib.get_close_matches(c, TORQUE_COLUMNS + CURRENT_COLUMNS, n=1, cutoff=0.7)
            ]
            hint = f" (the file has {', '.join(repr(c) for c in close)}: check the names and units)" if close else ""
            raise TrajectoryError(
                f"missing torque columns: expected tau_1_Nmm, tau_2_Nmm, tau_3_Nmm, or current_1_A … with a torque constant{hint}",
                source=source,
                line=header_line,
            )
        self._torque_index = [column[name] for name in self._torque_names]
        self.angle_unit = None
        self._angle_names: tuple[str, ...] = ()
        units = [unit for unit in ("deg", "rad") if any(f"{a}_{unit}" in column for a in ANGLE_NAMES)]
        if len(units) == 2:
            raise TrajectoryError(
                "angle columns mix _deg and _rad: give all three in one unit", source=source, line=header_line
            )
        if units:
            self.angle_unit = units[0]
            self._angle_names = tuple(f"{a}_{self.angle_unit}" for a in ANGLE_NAMES)
            _group(self._angle_names, header, "angle", source, header_line)
        self._angle_index = [column[name] for name in self._angle_names]
        has_heights = _group(HEIGHT_COLUMNS, header, "slider height", source, header_line)
        self._height_index = [column[name] for name in HEIGHT_COLUMNS] if has_heights else []
        if not self.angle_unit and not has_heights:
            raise TrajectoryError(
                "no motion: expected the platform angles alpha_deg, beta_deg, gamma_deg (attitude sensor) "
                "or platform 1's slider heights L_11_mm, L_12_mm, L_13_mm (motor encoders)",
                source=source,
                line=header_line,
            )
        self._time_index, self._load_index = column["t_s"], column["Fe_N"]
        self.width = 5 + 3 * bool(self.angle_unit) + 3 * has_heights
        used = {"t_s", "Fe_N", *TORQUE_COLUMNS, *CURRENT_COLUMNS, *HEIGHT_COLUMNS}
        used |= {f"{a}_{u}" for a in ANGLE_NAMES for u in ("deg", "rad")}
        self.ignored = tuple(name for name in header if name not in used)
        if has_torques and has_currents:
            self.ignored += CURRENT_COLUMNS

    def _columns(self, values: np.ndarray) -> np.ndarray:
        """The store's columns of a block, in SI."""
        parts = [values[:, [self._time_index, self._load_index]], values[:, self._torque_index] * self._scale]
        if self.angle_unit:
            angles = values[:, self._angle_index]
            parts.append(np.radians(angles) if self.angle_unit == "deg" else angles)
        if self._height_index:
            parts.append(values[:, self._height_index] * 1e-3)
        return np.ascontiguousarray(np.column_stack(parts))

    def _check(self, worst: dict[str, _Worst], low, high, rate: float | None = None) -> None:
        source = self.source
        torque = worst["torque"]
        if abs(torque.value) * self._scale * 1e3 > MAX_TORQUE_NMM:
            raise TrajectoryError(
                f"{torque.value:g} is beyond any motor of this machine ({MAX_TORQUE_NMM:g} N·mm): a unit slip?",
                source=source,
                line=torque.line,
                column=torque.column,
            )
        angle = worst["angle"]
        if self.angle_unit:
            largest = math.pi if self.angle_unit == "rad" else 360.0
            if abs(angle.value) > largest:
                message = (
                    "is more than half a turn: these look like degrees; label the columns _deg"
                    if self.angle_unit == "rad"
                    else "is more than a full turn"
                )
                raise TrajectoryError(
                    f"{angle.value:g} {self.angle_unit} {message}", source=source, line=angle.line, column=angle.column
                )
        height = worst["height"]
        if abs(height.value) > MAX_HEIGHT_MM:
            raise TrajectoryError(
                f"{height.value:g} mm is beyond any machine of this kind: a unit slip?",
                source=source,
                line=height.line,
                column=height.column,
            )
        if self.t.size < 2:
            raise TrajectoryError(f"{self.t.size} sample; a log needs many", source=source)
        self.t = relative_time(
            self.t, source, "t_s", stacklevel=4
        )  # Unix epoch stamps: from the first, every digit kept
        if rate is None:
            check_time(self.t, 0.0, source, self.lines, "t_s", even=True)
        else:
            self._times_from_index(rate)
        check_time_unit(self.t, "s", source, "t_s")  # issue 38: milliseconds under t_s (hipsim/plausibility.py)
        for load, line in (low, high):
            if load < 0:
                raise TrajectoryError(
                    f"load {load:g} N is negative (F_e is a magnitude)", source=source, line=line, column="Fe_N"
                )
            if load > MAX_LOAD:
                raise TrajectoryError(
                    f"load {load:g} N is beyond {MAX_LOAD:g} N (a unit slip?)", source=source, line=line, column="Fe_N"
                )

    def _times_from_index(self, rate: float) -> None:
        """t₀ + k/rate in place of time stamps too coarse to order the samples; they must not decrease and must span
        the same time to 1 % (else the rate is not the log's)."""
        source = self.source
        if isinstance(rate, bool) or not (isinstance(rate, (int, float)) and math.isfinite(rate) and rate > 0):
            raise TrajectoryError(f"the sample rate must be a positive number in Hz, got {rate!r}", source=source)
        down = np.flatnonzero(np.diff(self.t) < 0)
        if down.size:
            k = int(down[0]) + 1
            raise TrajectoryError(
                f"time {self.t[k]:g} s decreases (previous {self.t[k - 1]:g} s)",
                source=source,
                line=int(self.lines[k]),
                column="t_s",
            )
        span, expected = float(self.t[-1] - self.t[0]), (self.t.size - 1) / rate
        if abs(span - expected) > 0.01 * expected:
            raise TrajectoryError(
                f"the times span {span:.6g} s, the {self.t.size} samples at {rate:g} Hz {expected:.6g} s: "
                "is the sample rate the log's?",
                source=source,
                column="t_s",
            )
        self.t = self.t[0] + np.arange(self.t.size) / rate

    def __len__(self) -> int:
        return self.t.size

    @property
    def rate(self) -> float:
        """Sample rate in [Hz]."""
        return (self.t.size - 1) / (self.t[-1] - self.t[0])

    @property
    def has_heights(self) -> bool:
        """Whether the log gives platform 1's slider heights."""
        return bool(self._height_index)

    def piece(self, start: int, stop: int) -> RigLog:
        """Samples ``start`` … ``stop``−1 as a :class:`RigLog`."""
        start, stop = max(0, start), min(len(self), stop)
        self._store.seek(start * self.width * 8)
        values = np.fromfile(self._store, dtype=float, count=(stop - start) * self.width).reshape(-1, self.width)
        angles = values[:, 5:8] if self.angle_unit else None
        heights = values[:, -3:] if self._height_index else None
        return RigLog(
            self.t[start:stop],
            values[:, 1],
            values[:, 2:5],
            angles,
            heights,
            self.lines[start:stop],
            self.source,
            self.torque_from,
            self.ignored,
            self.angle_unit,
        )

    def read(self) -> RigLog:
        """All samples."""
        return self.piece(0, len(self))

    def close(self) -> None:
        """Drop the temporary store."""
        self._store.close()


def read_rig_log(path: str | Path, torque_constant: float | None = None) -> RigLog:
    """Read a rig log (columns in the module docstring) into SI units, checking every value.

    Args:
        path: the CSV file.
        torque_constant: the motors' torque constant in [N·m/A], needed when the
            log gives motor currents instead of torques.

    Returns:
        The samples as they are in the file (no filtering).

    Raises:
        TrajectoryError: naming the file, line and column of the first problem:
            missing torque or motion columns, currents without a torque
            constant, uneven times, negative loads, values beyond any machine.
    """
    scanned = RigLogFile(path, torque_constant)
    try:
        return scanned.read()
    finally:
        scanned.close()

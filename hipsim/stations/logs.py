"""Calibration logs read from their files: the carriage encoders and the two platforms' attitude sensors.

A calibration log is a table (CSV, ``;``- or tab-separated, with ``#``
comments and blank lines skipped, Parquet, or a TDMS or HDF5 file of channels by these names,
:mod:`hipsim.channels`) with the columns

- ``t_s``, evenly or unevenly spaced but increasing;
- the carriages: ``L_11_mm, L_12_mm, L_13_mm`` (the encoders' reading, as the
  rig logs have it), or the motor angles ``motor_1_deg, motor_2_deg,
  motor_3_deg`` (read as L_i = p·angle/360°, the carriage's zero where the
  motor's is);
- both attitude sensors: ``alpha_1_deg, beta_1_deg, gamma_1_deg`` (platform 1)
  and ``alpha_2_deg, beta_2_deg, gamma_2_deg`` (platform 2), in the spec's
  angles (R = Rz(γ)·Ry(β)·Rx(α));
- optionally, a fixture's rows: ``known_alpha_j_deg, known_beta_j_deg,
  known_gamma_j_deg`` (platform j = 1, 2), the attitude a fixture holds platform
  j at, empty (or ``nan``) on the rows where it moves freely. They pin the log's
  sensor offsets (``calibrate --sensor-offset per-log``).

Other columns are ignored. A missing column, a cell that is no finite number,
or time that does not increase is refused by file, line and column.
"""

from __future__ import annotations

import math
from collections.abc import Collection
from pathlib import Path

import numpy as np

from ..channels import channel_kind, read_channels
from ..exceptions import TrajectoryError
from ..tables import cells, data_lines, detect_separator, number, open_parquet, read_text_lines
from .calibration import CalibrationLog

__all__ = [
    "CARRIAGE_COLUMNS",
    "COMMAND_COLUMNS",
    "KNOWN_COLUMNS",
    "MOTOR_COLUMNS",
    "SENSOR_COLUMNS",
    "read_calibration_log",
    "read_carriage_log",
    "read_desired",
    "read_run_log",
    "read_slider_log",
]

CARRIAGE_COLUMNS = tuple(f"L_1{i}_mm" for i in (1, 2, 3))
#: The carriage commands that produced a run, when the acquisition logs them (``hipsim learn``).
COMMAND_COLUMNS = tuple(f"L_1{i}_cmd_mm" for i in (1, 2, 3))
MOTOR_COLUMNS = tuple(f"motor_{i}_deg" for i in (1, 2, 3))
#: The sensors' columns, platform by platform.
SENSOR_COLUMNS = tuple(tuple(f"{a}_{j}_deg" for a in ("alpha", "beta", "gamma")) for j in (1, 2))
#: A fixture's known attitude, platform by platform (optional; empty cells where the platform is free).
KNOWN_COLUMNS = tuple(tuple(f"known_{a}_{j}_deg" for a in ("alpha", "beta", "gamma")) for j in (1, 2))
WHAT = "calibration log"
#: The desired motion's columns a run of ``hipsim simulate`` carries (the controlled platform's), read when present.
DESIRED_COLUMNS = ("alpha_des_deg", "beta_des_deg", "gamma_des_deg")


def _table(
    path: str | Path, map: str | None, needed: Collection[str]
) -> tuple[list[str], dict[str, np.ndarray], np.ndarray | None]:
    """(header, columns by name as float arrays, the file line of each row, or for a TDMS or HDF5 file its sample
    numbers from 1, or None for Parquet).

    ``needed``: the columns whose cells must be numbers (a text cell, or a Parquet column of text, is refused by line
    and column); in the others a text cell reads as NaN (a column the caller does not use: a log's sensors for its
    carriages alone) and a Parquet column of text is left out."""
    source = str(path)
    if channel_kind(path) is not None:
        table = read_channels(path, map, WHAT, TrajectoryError)
        samples = 1 + np.arange(table.values.shape[0])
        return list(table.names), {name: table.values[:, c] for c, name in enumerate(table.names)}, samples
    if map is not None:
        raise TrajectoryError(
            "a column map of channels (--columns GROUP/CHANNEL) applies to TDMS and HDF5 logs", source=source
        )
    if Path(path).suffix.lower() in (".parquet", ".pq"):
        return _parquet(path, needed)
    numbered = data_lines(read_text_lines(path, WHAT, TrajectoryError))
    if not numbered:
        raise TrajectoryError("empty: no header and no rows", source=source)
    header_line, header_text = numbered[0]
    try:
        separator = detect_separator(header_text, numbered[1][1] if len(numbered) > 1 else None)
        header = [c.strip() for c in cells(header_text, separator)]
    except ValueError as error:
        raise TrajectoryError(str(error), source=source, line=header_line) from None
    wanted = {name: k for k, name in enumerate(header)}
    optional = set(sum(KNOWN_COLUMNS, ()))
    names = ("t_s",) + CARRIAGE_COLUMNS + MOTOR_COLUMNS + sum(SENSOR_COLUMNS, ()) + sum(KNOWN_COLUMNS, ())
    keep = [name for name in names + COMMAND_COLUMNS + DESIRED_COLUMNS if name in wanted]
    values = np.full(
        (len(numbered) - 1, len(keep)), math.nan
    )  # NaN: an empty cell of a fixture, a text cell not needed
    decimal_comma = separator != ","
    for row, (line, text) in enumerate(numbered[1:]):
        try:
            row_cells = cells(text, separator)
        except ValueError as error:
            raise TrajectoryError(str(error), source=source, line=line) from None
        for c, name in enumerate(keep):
            k = wanted[name]
            cell = row_cells[k] if k < len(row_cells) else ""
            if name in optional and not cell.strip():
                continue  # the platform is free on this row
            try:
                values[row, c] = number(cell, decimal_comma)
            except ValueError:
                if name in needed:
                    raise TrajectoryError(
                        f"'{cell.strip()}' is not a number", source=source, line=line, column=name
                    ) from None
    lines = np.array([line for line, _ in numbered[1:]])
    return header, {name: values[:, c] for c, name in enumerate(keep)}, lines


def _parquet(path: str | Path, needed: Collection[str]) -> tuple[list[str], dict[str, np.ndarray], None]:
    """:func:`_table` of a Parquet file: its columns of numbers by name (no lines)."""
    table = open_parquet(path, WHAT, TrajectoryError).read()
    columns = {}
    for name in table.column_names:
        try:
            columns[name] = np.asarray(table.column(name).to_numpy(), dtype=float)
        except (TypeError, ValueError):
            if name in needed:
                raise TrajectoryError(
                    f"holds {table.schema.field(name).type}, not numbers", source=str(path), column=name
                ) from None
    return list(table.column_names), columns, None


def _read(
    path: str | Path, lead: float, sensors: bool | None, map: str | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]:
    """(t [s], carriages [m] (N, 3), sensors [rad] (N, 2, 3) or None when not asked for, known [rad] (N, 2, 3) or None).

    ``sensors`` None: the sensors when the log has any of their columns (then all of them), else None.
    """
    source = str(path)
    if not math.isfinite(lead) or lead <= 0:
        raise TrajectoryError(f"the screw lead must be positive, got {lead!r}", source=source)
    needed = ("t_s",) + CARRIAGE_COLUMNS + MOTOR_COLUMNS
    if sensors is not False:
        needed += sum(SENSOR_COLUMNS, ()) + sum(KNOWN_COLUMNS, ())
    header, columns, lines = _table(path, map, needed)

    def missing(names, what):
        absent = [name for name in names if name not in columns]
        if absent:
            raise TrajectoryError(
                f"no {what}: missing column(s) {', '.join(absent)} (the header has {', '.join(header) or 'nothing'})",
                source=source,
            )

    missing(("t_s",), "time")
    encoders = all(name in columns for name in CARRIAGE_COLUMNS)
    if not encoders and not all(name in columns for name in MOTOR_COLUMNS):
        missing(CARRIAGE_COLUMNS, "carriage encoders (or motor angles motor_1_deg, motor_2_deg, motor_3_deg)")
    used = CARRIAGE_COLUMNS if encoders else MOTOR_COLUMNS  # the encoders when both are logged
    carriages = np.stack([columns[name] for name in used], axis=1)
    carriages = carriages * 1e-3 if encoders else carriages / 360.0 * lead
    if sensors is None:
        sensors = any(name in columns for name in sum(SENSOR_COLUMNS, ()))
    if sensors:
        for j, names in enumerate(SENSOR_COLUMNS, start=1):
            missing(names, f"attitude sensor of platform {j}")
        used = used + sum(SENSOR_COLUMNS, ())
    t = columns["t_s"]
    for name in ("t_s", *used):
        bad = ~np.isfinite(columns[name])
        if bad.any():
            row = int(np.argmax(bad))
            raise TrajectoryError(
                "not a finite number", source=source, line=None if lines is None else int(lines[row]), column=name
            )
    if len(t) < 2:
        raise TrajectoryError(f"{len(t)} row(s): a log needs at least 2", source=source)
    steps = np.diff(t)
    if np.any(steps <= 0):
        row = int(np.argmax(steps <= 0)) + 1
        raise TrajectoryError(
            f"time does not increase (t = {t[row]:.6g} s after {t[row - 1]:.6g} s)",
            source=source,
            line=None if lines is None else int(lines[row]),
            column="t_s",
        )
    if not sensors:
        return t, carriages, None, None
    angles = np.radians(np.stack([np.stack([columns[n] for n in names], axis=1) for names in SENSOR_COLUMNS], axis=1))
    return t, carriages, angles, _known(columns, lines, source, missing)


def _known(columns: dict[str, np.ndarray], lines: np.ndarray | None, source: str, missing) -> np.ndarray | None:
    """A fixture's known attitudes in [rad] (N, 2, 3), NaN where a platform is free; None without the columns."""
    if not any(name in columns for name in sum(KNOWN_COLUMNS, ())):
        return None
    known = np.full((len(columns["t_s"]), 2, 3), np.nan)
    for j, names in enumerate(KNOWN_COLUMNS):
        if not any(name in columns for name in names):
            continue
        missing(names, f"fixture's known attitude of platform {j + 1}")
        block = np.stack([columns[n] for n in names], axis=1)
        partial = np.isfinite(block).any(axis=1) & ~np.isfinite(block).all(axis=1)
        if partial.any():
            row = int(np.argmax(partial))
            raise TrajectoryError(
                f"a fixture's known attitude needs all three angles of platform {j + 1} on a row, or none",
                source=source,
                line=None if lines is None else int(lines[row]),
                column=names[int(np.argmax(~np.isfinite(block[row])))],
            )
        known[:, j] = np.radians(block)
    return known


def read_calibration_log(path: str | Path, lead: float, columns: str | None = None) -> CalibrationLog:
    """A calibration log from its file (module docstring), SI.

    Args:
        path: the file (CSV, Parquet, TDMS or HDF5: :mod:`hipsim.channels`).
        lead: the screw's lead p in [m] per motor turn, for motor-angle columns.
        columns: a TDMS or HDF5 file's column map (``NAME=GROUP/CHANNEL,…``), or None.

    Raises:
        TrajectoryError: a missing column (a platform's sensor, the carriages), a cell that is no finite number,
            time that does not increase, too few rows.
    """
    t, carriages, sensors, known = _read(path, lead, sensors=True, map=columns)
    assert sensors is not None
    return CalibrationLog(str(path), t, carriages, sensors, known)


def read_slider_log(
    path: str | Path, lead: float, columns: str | None = None
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """A log's times [s] (N,), carriages [m] (N, 3) and, when it has their columns, both attitude sensors [rad] (N, 2, 3).

    Raises:
        TrajectoryError: as :func:`read_calibration_log`; a log with some sensor columns must have all six.
    """
    t, carriages, sensors, _ = _read(path, lead, sensors=None, map=columns)
    return t, carriages, sensors


def read_desired(path: str | Path, columns: str | None = None) -> np.ndarray | None:
    """The desired attitude [rad] (N, 3) of a log that carries it (``alpha_des_deg`` …, as ``hipsim simulate`` writes);
    None for a log without those columns (or with a cell that is no finite number)."""
    _, table, _ = _table(path, columns, DESIRED_COLUMNS)
    if not all(name in table for name in DESIRED_COLUMNS):
        return None
    desired = np.radians(np.stack([table[name] for name in DESIRED_COLUMNS], axis=1))
    return desired if np.all(np.isfinite(desired)) else None


def read_carriage_log(path: str | Path, lead: float, columns: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """A log's times in [s] (N,) and carriage readings in [m] (N, 3), the sensors not needed (``stations --sliders``).

    Raises:
        TrajectoryError: as :func:`read_calibration_log`, but for the sensors.
    """
    t, carriages, _, _ = _read(path, lead, sensors=False, map=columns)
    return t, carriages


def read_run_log(
    path: str | Path, lead: float, platforms: tuple[int, ...]
) -> tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray]:
    """A run's log for learning (``hipsim learn``): the encoders, the commands when logged, the sensors it has.

    Args:
        path: the file (CSV or Parquet).
        lead: the screw's lead p in [m] per motor turn, for motor-angle columns.
        platforms: the platforms whose attitude sensors must be in the log (1, 2 or both).

    Returns:
        t [s] (N,), encoders [m] (N, 3), commands ``L_11_cmd_mm``… [m] (N, 3) or None when not all three logged,
        sensors [rad] (N, 2, 3) (NaN for a platform whose sensor the log does not have).

    Raises:
        TrajectoryError: as :func:`read_carriage_log`; the sensor of a platform in ``platforms`` missing; a command
            or sensor cell that is no finite number (naming line and column).
    """
    t, carriages = read_carriage_log(path, lead)
    header, columns, lines = _table(path, None, sum(SENSOR_COLUMNS, ()) + COMMAND_COLUMNS)  # t: read above
    source = str(path)
    for j in platforms:
        absent = [name for name in SENSOR_COLUMNS[j - 1] if name not in columns]
        if absent:
            raise TrajectoryError(
                f"no attitude sensor of platform {j}: missing column(s) {', '.join(absent)} "
                f"(the header has {', '.join(header)})",
                source=source,
            )
    present = [j for j in (1, 2) if all(name in columns for name in SENSOR_COLUMNS[j - 1])]
    logged = all(name in columns for name in COMMAND_COLUMNS)
    used = sum((SENSOR_COLUMNS[j - 1] for j in present), ()) + (COMMAND_COLUMNS if logged else ())
    for name in used:
        bad = ~np.isfinite(columns[name])
        if bad.any():
            row = int(np.argmax(bad))
            raise TrajectoryError(
                "not a finite number", source=source, line=None if lines is None else int(lines[row]), column=name
            )
    sensors = np.full((len(t), 2, 3), np.nan)
    for j in present:
        sensors[:, j - 1] = np.radians(np.stack([columns[name] for name in SENSOR_COLUMNS[j - 1]], axis=1))
    commands = np.stack([columns[name] for name in COMMAND_COLUMNS], axis=1) * 1e-3 if logged else None
    return t, carriages, commands, sensors

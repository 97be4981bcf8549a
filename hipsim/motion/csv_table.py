"""Trajectories from CSV tables: hipsim's own columns, or any lab's table through a column mapping.

The text is read by :mod:`hipsim.tables`' rules: UTF-8 (a byte-order mark
skipped); lines starting with ``#`` and blank lines skipped; separated by
commas, semicolons or tabs (read from the header and the first row) and,
when not by commas, possibly with decimal commas. The header is matched
against the mapping by :mod:`hipsim.motion.headers`; the numbers go through
the steps every reader shares (:func:`hipsim.motion.build.build_trajectory`).
Every problem is reported on one line naming the file, its line and column.
"""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Literal, Unpack, overload

import numpy as np

from ..exceptions import TrajectoryError
from ..tables import cells, data_lines, decimals, detect_separator, number, read_text_lines
from .build import SampledMotion, Table, build_trajectory
from .columns import Column, ColumnMap, column_options
from .headers import table_columns
from .read_options import ReadOptions, build_options
from .trajectories import MIN_SAMPLES, Trajectory

__all__ = ["load_trajectory_csv"]

#: Excel's first line naming the separator of a CSV it writes or reads ("sep=;").
_EXCEL_SEPARATOR = re.compile(r"sep=(;|,|\t|\\t)", re.IGNORECASE)


@overload
def load_trajectory_csv(
    path: str | Path, *, lazy: Literal[False] = False, **options: Unpack[ReadOptions]
) -> Trajectory: ...
@overload
def load_trajectory_csv(path: str | Path, *, lazy: Literal[True], **options: Unpack[ReadOptions]) -> SampledMotion: ...
@overload
def load_trajectory_csv(
    path: str | Path, *, lazy: bool, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion: ...
def load_trajectory_csv(
    path: str | Path, *, lazy: bool = False, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion:
    """Read a trajectory from a CSV table and differentiate it.

    Without ``columns`` the header names hipsim's columns with their unit:
    ``t_s``, then ``alpha_deg``, ``beta_deg``, ``gamma_deg`` (or ``_rad`` for
    all three), optionally ``Fe_N`` (the load; 0 N when absent), and no
    others. With ``columns`` any header: the mapping names the columns to
    read, and the others are ignored.

    Args:
        path: the CSV file (comma, semicolon or tab separated).
        lazy: return a :class:`~hipsim.motion.build.SampledMotion` to evaluate piece by piece instead.
        options: :class:`hipsim.motion.read_options.ReadOptions` (periodic, columns, load_column,
            body_weight, frequency, period, resample, cutoff, load_curve).

    Returns:
        The trajectory, named by the path as given.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    source = str(path)
    rest = build_options(options, "load_trajectory_csv")
    mapping, load = column_options(options.get("columns"), options.get("load_column"), source)
    table = _read_csv_table(source, path, mapping, load)
    return build_trajectory(table, lazy=lazy, **rest)


def _read_csv_table(source: str, path, mapping: ColumnMap | None, load: Column | None) -> Table:
    numbered = data_lines(read_text_lines(path, "trajectory file", TrajectoryError))
    if not numbered:
        raise TrajectoryError("the file is empty", source=source)
    # Stripped of spaces only: "sep=" and a tab is Excel's line for a tab-separated file.
    declared = _EXCEL_SEPARATOR.fullmatch(numbered[0][1].strip(" \r\n"))
    if declared:  # Excel's "sep=;" line names the separator: the header follows
        numbered = numbered[1:]
        if not numbered:
            raise TrajectoryError("the file holds only Excel's 'sep=' line", source=source)
    header_line, header_text = numbered[0]
    try:
        separator = (
            declared.group(1).replace("\\t", "\t")
            if declared
            else detect_separator(header_text, numbered[1][1] if len(numbered) > 1 else None)
        )
    except ValueError as error:  # a cell beyond the field size limit
        raise TrajectoryError(str(error), source=source, line=header_line) from None
    header = [cell.strip() for cell in _cells(header_text, separator, 0, source, header_line)]
    mapping, index = table_columns(header, mapping, load, source, header_line)
    data = numbered[1:]
    if len(data) < MIN_SAMPLES:
        raise TrajectoryError(f"{len(data)} samples; at least {MIN_SAMPLES} are needed", source=source)
    decimal_comma = separator != ","
    used = sorted(set(index.values()))
    values = np.empty((len(data), len(header)))
    time_decimals: int | None = 0  # None once a time's decimals cannot be told
    for k, (number_of_line, line) in enumerate(data):
        row = _cells(line, separator, len(header), source, number_of_line)
        if len(row) != len(header):
            hint = (
                " (decimal commas? a comma-separated file needs decimal points)"
                if separator == "," and len(row) > len(header)
                else ""
            )
            raise TrajectoryError(
                f"{len(row)} cells, the header has {len(header)}{hint}", source=source, line=number_of_line
            )
        for c in used:
            try:
                values[k, c] = number(row[c], decimal_comma)
            except ValueError:
                raise TrajectoryError(
                    f"'{row[c].strip()}' is not a number", source=source, line=number_of_line, column=header[c]
                ) from None
            if not math.isfinite(values[k, c]):
                raise TrajectoryError(
                    f"'{row[c].strip()}' is not finite", source=source, line=number_of_line, column=header[c]
                )
        places = decimals(row[index["time"]])
        time_decimals = max(time_decimals, places) if places is not None and time_decimals is not None else None
    return Table(
        source=source,
        lines=np.array([n for n, _ in data]),
        time=values[:, index["time"]],
        angles=np.column_stack(
            [values[:, index[key]] if key in index else np.zeros(len(data)) for key in mapping.angle_keys]
        ),
        load=values[:, index["load"]] if "load" in index else None,
        columns=mapping,
        time_quantum=10.0**-time_decimals if time_decimals is not None else 0.0,
    )


def _cells(line: str, separator: str, width: int, source: str, line_number: int) -> list[str]:
    """The line's cells (:func:`hipsim.tables.cells`), a cell beyond the field size limit named by its line."""
    try:
        return cells(line, separator, width)
    except ValueError as error:
        raise TrajectoryError(str(error), source=source, line=line_number) from None

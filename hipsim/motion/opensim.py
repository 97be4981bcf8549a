"""OpenSim motion and storage files (.mot, .sto): a hip's coordinates in, the platform trajectory out.

The format (OpenSim's "Storage" text files, as its inverse kinematics writes
them): a header of free lines up to a line ``endheader``, in which
``inDegrees=yes|no`` says the unit of the rotational coordinates (radians
when absent, as OpenSim reads it) and ``nRows=``/``nColumns=`` (or the older
``datarows``/``datacolumns``) the table's size; then a line of column labels
and rows of numbers, separated by tabs or spaces. The first column is
``time``.

The hip's coordinates are read by their names in OpenSim's gait models
(gait2392, Rajagopal 2016 and their kin): ``hip_flexion_r``,
``hip_adduction_r``, ``hip_rotation_r`` (``_l`` for the left hip), or a
state's full path ending in ``/hip_flexion_r/value``. They are the angles of
the ISB hip's Z–X–Y joint chain, not α, β, γ: :mod:`hipsim.motion.hip_angles`
turns them into the platform angles, the left hip as its mirror image (its
OpenSim axes are mirrored so that adduction and internal rotation are
positive on both sides). No OpenSim installation is needed.
"""

from __future__ import annotations

import re
import warnings
from pathlib import Path
from typing import Literal, Unpack, overload

import numpy as np

from ..exceptions import TrajectoryError
from ..tables import decimals, number, read_text_lines
from .build import SampledMotion, Table, TrajectoryWarning, build_trajectory
from .columns import Column, ColumnMap, as_column_map, as_load_column
from .read_options import ReadOptions, build_options
from .trajectories import MIN_SAMPLES, Trajectory

__all__ = ["HIP_COORDINATES", "load_opensim"]

#: OpenSim's hip coordinates, in the order of the ISB chain (flexion about Z, adduction about X, rotation about Y).
HIP_COORDINATES = ("hip_flexion", "hip_adduction", "hip_rotation")
_SIDES = {"right": "r", "r": "r", "left": "l", "l": "l"}


@overload
def load_opensim(
    path: str | Path, side: str = "right", *, lazy: Literal[False] = False, **options: Unpack[ReadOptions]
) -> Trajectory: ...
@overload
def load_opensim(
    path: str | Path, side: str = "right", *, lazy: Literal[True], **options: Unpack[ReadOptions]
) -> SampledMotion: ...
@overload
def load_opensim(
    path: str | Path, side: str = "right", *, lazy: bool, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion: ...
def load_opensim(
    path: str | Path, side: str = "right", *, lazy: bool = False, **options: Unpack[ReadOptions]
) -> Trajectory | SampledMotion:
    """Read one hip's motion from an OpenSim .mot or .sto file.

    Args:
        path: the file.
        side: ``"right"`` or ``"left"``: whose hip coordinates to read.
        lazy: return a :class:`hipsim.motion.build.SampledMotion` to evaluate piece by piece instead.
        options: :class:`hipsim.motion.read_options.ReadOptions`, where for an OpenSim file
            ``columns`` is a column mapping (:func:`hipsim.motion.columns.parse_columns`) instead of the hip
            coordinates' names: angles without a unit in the file's (``inDegrees``),
            ``zero`` for a coordinate the file does not have (a planar model).

    Returns:
        The platform trajectory, named by the path as given; 0 N of load
        without ``load_column``.

    Raises:
        TrajectoryError: naming the file, line and column of the first problem.
    """
    source = str(path)
    rest = build_options(options, "load_opensim")
    if not isinstance(side, str) or side.strip().lower() not in _SIDES:
        raise TrajectoryError(f"side must be 'right' or 'left', got {side!r}", source=source)
    suffix = _SIDES[side.strip().lower()]
    mapping, load = as_column_map(options.get("columns")), as_load_column(options.get("load_column"))
    if mapping is not None and load is not None:
        if mapping.load is not None:
            raise TrajectoryError(
                "the load column is named twice (in the column mapping and on its own)", source=source
            )
        mapping = ColumnMap(mapping.time, mapping.angles, mapping.hip_chain, load)
    table = _read(source, path, suffix, load, mapping)
    return build_trajectory(table, lazy=lazy, **rest)


def _read(source: str, path, suffix: str, load: Column | None, mapping: ColumnMap | None = None) -> Table:
    lines = read_text_lines(path, "OpenSim file", TrajectoryError)
    end = next((k for k, line in enumerate(lines) if line.strip().lower() == "endheader"), None)
    if end is None:
        raise TrajectoryError("no 'endheader' line: not an OpenSim .mot/.sto file", source=source)
    in_degrees, rows_declared, columns_declared = _header(lines[:end], source)
    body = [(k, line) for k, line in enumerate(lines[end + 1 :], start=end + 2) if line.strip()]
    if not body:
        raise TrajectoryError("no column labels after 'endheader'", source=source, line=end + 1)
    label_line, label_text = body[0]
    labels = [label.strip() for label in (label_text.split("\t") if "\t" in label_text else label_text.split())]
    while labels and not labels[-1]:  # a trailing tab
        labels.pop()
    data = body[1:]
    by_comma = [label.strip() for label in label_text.split(",")]
    if len(by_comma) > len(labels) and len(by_comma) >= 2 and all(by_comma):
        raise TrajectoryError(
            f"the labels are separated by commas ({len(by_comma)} of them): a .mot/.sto file is tab- or space-separated, "
            "as OpenSim writes it; save it with tabs, or as a .csv read with --columns",
            source=source,
            line=label_line,
        )
    # OpenSim writes such headers itself (its tutorials' crouch2.mot): the data win, with a warning.
    if columns_declared is not None and columns_declared[1] != len(labels):
        warnings.warn(
            f"{source}, line {columns_declared[0]}: the header says {columns_declared[1]} columns, the labels are {len(labels)}: "
            "the labels are read",
            TrajectoryWarning,
            stacklevel=4,
        )
    if rows_declared is not None and rows_declared[1] != len(data):
        warnings.warn(
            f"{source}, line {rows_declared[0]}: the header says {rows_declared[1]} rows, the file has {len(data)}: "
            "the rows are read",
            TrajectoryWarning,
            stacklevel=4,
        )
    unit = "deg" if in_degrees else "rad"
    if mapping is not None:
        return _read_mapped(source, labels, label_line, data, mapping, unit)
    index = {"time": _find(labels, ("time",), "the time", source, label_line)}
    angles = []
    for coordinate in HIP_COORDINATES:
        name = f"{coordinate}_{suffix}"
        index[coordinate] = _find(
            labels, (name,), f"the {'right' if suffix == 'r' else 'left'} hip's coordinate", source, label_line
        )
        angles.append(Column(labels[index[coordinate]], unit))
    if load is not None:
        index["load"] = _find(labels, (load.name,), "the load", source, label_line)
        load = Column(labels[index["load"]], load.unit, load.sign)
    first, second, third = angles  # one per hip coordinate: always three
    columns = ColumnMap(Column(labels[index["time"]], "s"), (first, second, third), hip_chain=True, load=load)
    return _table(source, labels, data, index, HIP_COORDINATES, columns)


def _read_mapped(source: str, labels: list[str], label_line: int, data, mapping: ColumnMap, unit: str) -> Table:
    """The columns a mapping names (an angle without a unit in the file's, ``zero`` for one the file lacks)."""
    index = {"time": _find(labels, (mapping.time.name,), "the time", source, label_line)}
    angles = []
    for key, column in zip(mapping.angle_keys, mapping.angles):
        if not column.zero:
            index[key] = _find(labels, (column.name,), f"mapped to {key}", source, label_line)
        angles.append(Column(labels[index[key]] if key in index else column.name, column.unit or unit, column.sign))
    load = mapping.load
    if load is not None:
        index["load"] = _find(labels, (load.name,), "the load", source, label_line)
        load = Column(labels[index["load"]], load.unit, load.sign)
    first, second, third = angles  # one per angle key: always three
    columns = ColumnMap(mapping.time, (first, second, third), mapping.hip_chain, load)
    return _table(source, labels, data, index, mapping.angle_keys, columns)


def _table(source: str, labels: list[str], data, index: dict[str, int], angle_keys, columns: ColumnMap) -> Table:
    """The numbers of the columns in ``index`` (angles absent from it are 0), checked, as a Table."""
    if len(data) < MIN_SAMPLES:
        raise TrajectoryError(f"{len(data)} samples; at least {MIN_SAMPLES} are needed", source=source)
    used = sorted(set(index.values()))
    values = np.empty((len(data), len(labels)))
    places = []
    for k, (line_number, line) in enumerate(data):
        row = line.split()
        if len(row) != len(labels):
            raise TrajectoryError(f"{len(row)} values, the labels are {len(labels)}", source=source, line=line_number)
        for c in used:
            try:
                values[k, c] = number(row[c])
            except ValueError:
                raise TrajectoryError(
                    f"'{row[c]}' is not a number", source=source, line=line_number, column=labels[c]
                ) from None
            if not np.isfinite(values[k, c]):
                raise TrajectoryError(f"'{row[c]}' is not finite", source=source, line=line_number, column=labels[c])
        places.append(decimals(row[index["time"]]))
    known = [p for p in places if p is not None]  # a time whose decimals cannot be told: no quantum
    return Table(
        source=source,
        lines=np.array([n for n, _ in data]),
        time=values[:, index["time"]],
        angles=np.column_stack([values[:, index[c]] if c in index else np.zeros(len(data)) for c in angle_keys]),
        load=values[:, index["load"]] if "load" in index else None,
        columns=columns,
        time_quantum=0.0 if not known or len(known) < len(places) else 10.0 ** -max(known),
    )


def _header(lines: list[str], source: str) -> tuple[bool, tuple[int, int] | None, tuple[int, int] | None]:
    """(inDegrees, (line, rows declared), (line, columns declared)) from the header's lines."""
    in_degrees = False  # OpenSim's reading when the header does not say
    rows = columns = None
    for k, line in enumerate(lines, start=1):
        match = re.fullmatch(r"\s*(\w+)\s*(?:=|\s)\s*(\S+)\s*", line)
        if not match:
            continue
        key, value = match.group(1).lower(), match.group(2)
        if key == "indegrees":
            if value.lower() not in ("yes", "no"):
                raise TrajectoryError(f"inDegrees must be yes or no, got '{value}'", source=source, line=k)
            in_degrees = value.lower() == "yes"
        elif key in ("nrows", "datarows", "ncolumns", "datacolumns"):
            try:
                count = int(value)
            except ValueError:
                raise TrajectoryError(
                    f"{match.group(1)} must be a whole number, got '{value}'", source=source, line=k
                ) from None
            if key in ("nrows", "datarows"):
                rows = (k, count)
            else:
                columns = (k, count)
    return in_degrees, rows, columns


def _find(labels: list[str], names: tuple[str, ...], what: str, source: str, line: int) -> int:
    """The index of the label called ``name`` (or a state path ending in ``/name/value``)."""
    for name in names:
        exact = [c for c, label in enumerate(labels) if label == name]
        path = [c for c, label in enumerate(labels) if label.endswith(f"/{name}/value")]
        loose = [c for c, label in enumerate(labels) if label.lower() == name.lower()]
        found = exact or path or loose
        if len(found) > 1:
            raise TrajectoryError(f"column '{name}' appears {len(found)} times", source=source, line=line, column=name)
        if found:
            return found[0]
    name = names[0]
    hips = [label for label in labels if "hip_" in label.lower()]
    present = (
        f"its hip columns are {', '.join(hips[:6])}"
        if hips
        else f"its columns are {', '.join(labels[:8])}" + (" …" if len(labels) > 8 else "")
    )
    other = name[:-2] + ("_l" if name.endswith("_r") else "_r")
    side = "left" if other.endswith("_l") else "right"
    hint = (
        f' (the other hip\'s are there: read them with --side {side}, side="{side}" in Python)'
        if any(label == other or label.endswith(f"/{other}/value") for label in labels)
        else ""
    )
    flexion = f"hip_flexion{name[-2:]}"
    if not hint and name.startswith(("hip_adduction", "hip_rotation")) and flexion in labels:
        hint = f" (a planar model? read it with --columns time=time,flexion={flexion},adduction=zero,rotation=zero)"
    raise TrajectoryError(f"no column '{name}' ({what}); {present}{hint}", source=source, line=line)

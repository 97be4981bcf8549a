"""Column mappings: which column of a table holds the time, the three angles and the load, in which unit and sign.

A mapping is written ``time=Time,alpha=FE,beta=-AA,gamma=IE:rad,load=Fz:%BW``
(:func:`parse_columns`), given as a mapping of quantity to column, or built as
a :class:`ColumnMap` of :class:`Column`. The readers of CSV and Parquet tables
take one (:func:`column_options`); an OpenSim file's columns are found by
their names.
"""

from __future__ import annotations

import re
from collections.abc import Mapping
from dataclasses import dataclass

from ..exceptions import TrajectoryError
from .trajectories import ANGLE_NAMES

__all__ = [
    "HIP_ANGLE_NAMES",
    "STANDARD_GRAVITY",
    "ZERO",
    "UNITS",
    "Column",
    "ColumnMap",
    "as_column_map",
    "as_load_column",
    "column_options",
    "parse_columns",
    "stated_unit",
]

#: The column name that stands for an angle the file does not have: 0 throughout.
ZERO = "zero"
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
#: Each unit by its spelling in lower case, for reading units case-blind.
UNIT_SPELLINGS = {unit.lower(): unit for units in UNITS.values() for unit in units}


#: Spellings of % body weight in a column's name.
_BODY_WEIGHT = {"%bw": "%BW", "bw%": "%BW", "%body weight": "%BW", "%bodyweight": "%BW", "°": "deg"}


def stated_unit(name: str, key: str) -> str | None:
    """The unit a column's name states for quantity ``key`` (``Fz [kN]``, ``Fz (%BW)``, ``Fz_%BW``, ``Load %BW``), or None.

    Only units of the quantity (:data:`UNITS`) count: ``[N]`` for a load, not for an angle.
    """
    match = re.search(r"[\[(]\s*([^\])]+?)\s*[\])]", name)
    if match:
        spelled = re.sub(r"\s+", "", match.group(1)).lower()
    else:  # a unit after the last underscore or space: Fz_%BW, Load %BW, Fz_kN
        parts = re.split(r"[_\s]+", name.strip())
        spelled = parts[-1].lower() if len(parts) > 1 else ""
        if spelled in ("bw", "%"):  # Fz_% BW, Fz %_BW
            spelled = "".join(parts[-2:]).lower()
    unit = _BODY_WEIGHT.get(spelled, UNIT_SPELLINGS.get(spelled))
    return unit if unit in UNITS[key] else None


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
            raise TrajectoryError(
                f"column '{self.name}': sign must be +1 or -1, got {self.sign!r}", source="column mapping"
            )

    @classmethod
    def parse(cls, text: str, key: str) -> Column:
        """``[-]NAME[:UNIT]`` → Column; ``key`` (time, alpha, …, load) says which units are allowed."""
        text = text.strip()
        sign = -1.0 if text.startswith("-") else 1.0
        text = text[1:].strip() if sign < 0 else text
        unit = None
        if ":" in text:
            text, _, given = text.rpartition(":")
            unit = UNIT_SPELLINGS.get(given.strip().lower())
            if unit not in UNITS[key]:
                raise TrajectoryError(
                    f"'{given.strip()}' is not a unit of {key} (expected {', '.join(UNITS[key])})",
                    source="column mapping",
                )
        if not text.strip():
            raise TrajectoryError(f"no column name given for {key}", source="column mapping")
        return cls(text.strip(), unit, sign)

    @property
    def zero(self) -> bool:
        """True for the name ``zero``: an angle the file does not have (a planar model's), read as 0 throughout."""
        return self.name.strip().lower() == ZERO

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
    def from_mapping(cls, mapping: Mapping[str, str | Column]) -> ColumnMap:
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
            if column.zero and key in ("time", "load"):
                raise TrajectoryError(
                    f"'{ZERO}' stands for an angle the file does not have, not for the {key}", source="column mapping"
                )
            if column.unit is not None and column.unit not in UNITS[key]:
                raise TrajectoryError(
                    f"'{column.unit}' is not a unit of {key} (expected {', '.join(UNITS[key])})",
                    source="column mapping",
                )
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
            raise TrajectoryError(
                f"{', '.join(missing)} not mapped (time and all three angles are needed)", source="column mapping"
            )
        if "time" in columns and columns["time"].sign < 0:
            raise TrajectoryError("the time column cannot have its sign flipped", source="column mapping")
        first, second, third = (columns[k] for k in names)
        return cls(columns["time"], (first, second, third), bool(hip), columns.get("load"))


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
        raise TrajectoryError(
            "empty column mapping (expected e.g. time=Time,alpha=FE,beta=AA,gamma=IE)", source="column mapping"
        )
    mapping: dict[str, str] = {}
    for entry in text.split(","):
        key, sep, value = entry.partition("=")
        if not sep or not key.strip():
            raise TrajectoryError(f"'{entry.strip()}' is not QUANTITY=COLUMN", source="column mapping")
        if key.strip().lower() in mapping:
            raise TrajectoryError(f"{key.strip()} is mapped twice", source="column mapping")
        mapping[key.strip().lower()] = value
    return ColumnMap.from_mapping(mapping)


def as_column_map(columns) -> ColumnMap | None:
    """The column mapping a reader was given (a ColumnMap, a mapping, :func:`parse_columns` text or None), as a ColumnMap or None."""
    if columns is None or isinstance(columns, ColumnMap):
        return columns
    if isinstance(columns, str):
        return parse_columns(columns)
    if isinstance(columns, Mapping):
        return ColumnMap.from_mapping(columns)
    raise TypeError(f"columns must be a ColumnMap, a mapping or text, got {type(columns).__name__}")


def as_load_column(load_column) -> Column | None:
    """The load column a reader was given (a Column, ``[-]NAME[:UNIT]`` text or None), as a Column or None."""
    if load_column is None or isinstance(load_column, Column):
        return load_column
    return Column.parse(str(load_column), "load")


def column_options(columns, load_column, source: str) -> tuple[ColumnMap | None, Column | None]:
    """The column mapping and load column a reader was given, merged (refused when both name the load)."""
    mapping, load = as_column_map(columns), as_load_column(load_column)
    if mapping is not None and load is not None:
        if mapping.load is not None:
            raise TrajectoryError(
                "the load column is named twice (in the column mapping and on its own)", source=source
            )
        mapping = ColumnMap(mapping.time, mapping.angles, mapping.hip_chain, load)
    return mapping, load

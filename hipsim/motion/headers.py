"""A table's header against a column mapping: where each mapped column sits, hipsim's own header checked, a mapping suggested.

Without a mapping the header must be hipsim's own (``t_s``, ``alpha_deg``,
``beta_deg``, ``gamma_deg`` or all three in ``_rad``, optionally ``Fe_N``),
checked strictly; a header that does not match is answered with a mapping
guessed from its names (:func:`suggest_mapping`). With a mapping each column
is found by its name, exactly or else ignoring case and spaces.
"""

from __future__ import annotations

import re

from ..exceptions import TrajectoryError
from .columns import HIP_ANGLE_NAMES, UNITS, Column, ColumnMap, stated_unit
from .trajectories import ANGLE_NAMES

__all__ = ["suggest_mapping", "table_columns"]


def table_columns(
    header: list[str], mapping: ColumnMap | None, load: Column | None, source: str, line: int
) -> tuple[ColumnMap, dict[str, int]]:
    """The mapping (hipsim's own header checked when none is given) and where each mapped column sits in the header."""
    if mapping is None:
        mapping = _canonical_columns(header, source, line, load)
    return mapping, _column_indices(header, mapping, source, line)


def _column_indices(header: list[str], mapping: ColumnMap, source: str, line: int) -> dict[str, int]:
    """Where each mapped column is in the header (exactly, else ignoring case and spaces if that is unique)."""
    index = {}
    for key, column in mapping.items():
        if column.zero:  # an angle the file does not have: no column
            continue
        exact = [c for c, name in enumerate(header) if name == column.name]
        loose = [c for c, name in enumerate(header) if _loose(name) == _loose(column.name)]
        found = exact or loose
        if len(found) > 1:
            raise TrajectoryError(
                f"column '{column.name}' appears {len(found)} times", source=source, line=line, column=column.name
            )
        if not found:
            raise TrajectoryError(
                f"no column '{column.name}' (mapped to {key}); the header has {_listing(header)}",
                source=source,
                line=line,
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
            (
                c
                for pattern in patterns
                for c, name in enumerate(header)
                if c not in taken and re.search(pattern, name.strip().lower())
            ),
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
    unit = "%" if key == "time" and "%" in name and not re.search(r"[\[(]", name) else stated_unit(name, key)
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
            source=source,
            line=line,
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
        raise TrajectoryError(
            f"both 'Fe_N' and the load column '{load.name}' are given: which is the load?", source=source, line=line
        )
    load = load if load is not None else (Column("Fe_N", "N") if "Fe_N" in columns else None)
    known = {"t_s", *(f"{a}_{unit}" for a in ANGLE_NAMES)} | ({load.name} if load is not None else set())
    for c in header:
        if c not in known:
            raise TrajectoryError(
                f"unknown column (expected t_s, {', '.join(f'{a}_{unit}' for a in ANGLE_NAMES)}, optionally Fe_N; "
                "map the columns to read any others)",
                source=source,
                line=line,
                column=c,
            )
    alpha, beta, gamma = (Column(f"{a}_{unit}", unit) for a in ANGLE_NAMES)
    return ColumnMap(Column("t_s", "s"), (alpha, beta, gamma), False, load)

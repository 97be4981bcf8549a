"""A wear test's weighings (ISO 14242-2's gravimetric method), read and checked: each cup's mass at every stop.

The file is a CSV table (comma, semicolon or tab; ``#`` comments; decimal
commas with ``;``) with the columns ``cycle`` (the machine's cycle counter at
the stop), ``station`` (a name) and ``mass_mg`` (the cup's mass in [mg], the
mean of the balance's readings). The soak control, a cup under the same load
and fluid that does not move, is given either

- as its own station: ``soak`` serves every station, ``soak_NAME`` only
  station NAME (it wins over ``soak``), weighed at the same stops; or
- as a column ``soak_mg``: each row's soak control mass in [mg].

Refused, with the file's line: a row out of order (a station's cycles must
increase down the file), a station without a soak control (or one not weighed
at a stop of the station), a mass that is not positive, and a mass that jumps
from one stop to the next by more than the lighter of the two readings weighs
(more than a whole cup: a reading in grams among milligrams, two cups mixed up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..exceptions import FileRowError
from ..tables import cells, data_lines, detect_separator, number, read_text_lines

__all__ = ["SOAK", "StationWeighings", "Weighings", "read_weighings"]

#: The station name of a soak control that serves every station (``soak_NAME`` serves station NAME only).
SOAK = "soak"
_COLUMNS = ("cycle", "station", "mass_mg")


@dataclass(frozen=True, eq=False)
class StationWeighings:
    """One station's stops, with its soak control's masses at the same stops.

    Attributes:
        station: the station's name.
        soak_control: where its soak control came from (a station name, or ``soak_mg``).
        cycles: the cycle counter at each stop, increasing, (N,).
        mass_mg: the cup's mass at each stop in [mg], (N,).
        soak_mg: the soak control's mass at each stop in [mg], (N,).
        lines: each stop's line in the file, (N,).
    """

    station: str
    soak_control: str
    cycles: np.ndarray
    mass_mg: np.ndarray
    soak_mg: np.ndarray
    lines: np.ndarray

    @property
    def loss_mg(self) -> np.ndarray:
        """The soak-corrected mass loss since the first stop in [mg], (N,): the cup's loss plus the soak control's gain."""
        return (self.mass_mg[0] - self.mass_mg) + (self.soak_mg - self.soak_mg[0])


@dataclass(frozen=True, eq=False)
class Weighings:
    """A test's weighings: per station, its stops (soak controls are not stations here).

    Attributes:
        source: the file.
        stations: per station, in the order of their first row.
    """

    source: str
    stations: tuple[StationWeighings, ...]


def _rows(path: str | Path) -> tuple[list[tuple[int, float, str, float, float | None]], bool]:
    """(line, cycle, station, mass, soak or None) per row, and whether the file has a ``soak_mg`` column."""
    source = str(path)
    rows = data_lines(read_text_lines(path, "weighings file", FileRowError))
    if len(rows) < 2:
        raise FileRowError("expected a header cycle, station, mass_mg (soak_mg) and rows", source=source)
    separator = detect_separator(rows[0][1], rows[1][1])
    header = [cell.strip() for cell in cells(rows[0][1], separator)]
    missing = [name for name in _COLUMNS if name not in header]
    if missing:
        raise FileRowError(
            f"no column {', '.join(missing)} (the header has {', '.join(header)})", source=source, line=rows[0][0]
        )
    has_soak = "soak_mg" in header
    index = {name: header.index(name) for name in (*_COLUMNS, *(("soak_mg",) if has_soak else ()))}
    out = []
    for line, text in rows[1:]:
        row = cells(text, separator)

        def value(name: str, row=row, line=line) -> float | None:
            cell = row[index[name]].strip() if index[name] < len(row) else ""
            if cell == "" and name == "soak_mg":
                return None
            try:
                x = number(cell, decimal_comma=separator != ",")
            except ValueError:
                raise FileRowError(f"expected a number, got '{cell}'", source=source, line=line, column=name) from None
            if not math.isfinite(x):
                raise FileRowError(f"expected a finite number, got '{cell}'", source=source, line=line, column=name)
            return x

        cycle, mass = value("cycle"), value("mass_mg")
        assert cycle is not None and mass is not None
        station = row[index["station"]].strip() if index["station"] < len(row) else ""
        if not station:
            raise FileRowError("no station name", source=source, line=line, column="station")
        if cycle < 0 or cycle != round(cycle):
            raise FileRowError(
                f"cycle {cycle:g}: a cycle counter is a whole number ≥ 0", source=source, line=line, column="cycle"
            )
        soak = value("soak_mg") if has_soak else None
        for name, x in (("mass_mg", mass), ("soak_mg", soak)):
            if x is not None and x <= 0:
                raise FileRowError(
                    f"a mass of {x:g} mg: a cup weighs more than 0", source=source, line=line, column=name
                )
        out.append((line, cycle, station, mass, soak))
    return out, has_soak


def _check_series(source: str, station: str, rows: list[tuple[int, float, float]], column: str) -> None:
    """A station's (line, cycle, mass) rows: cycles increasing down the file, no jump heavier than a cup."""
    for (line0, cycle0, mass0), (line, cycle, mass) in zip(rows, rows[1:], strict=False):
        if cycle <= cycle0:
            raise FileRowError(
                f"station {station}: cycle {cycle:.0f} after {cycle0:.0f} (line {line0}): weighings out of order "
                "(each station's cycles must increase down the file)",
                source=source,
                line=line,
                column="cycle",
            )
        if abs(mass - mass0) > min(mass, mass0):
            raise FileRowError(
                f"station {station}: {mass:g} mg after {mass0:g} mg at cycle {cycle0:.0f}: a change larger than the "
                "cup weighs (a reading in g among mg, or two cups mixed up?)",
                source=source,
                line=line,
                column=column,
            )


def read_weighings(path: str | Path) -> Weighings:
    """The weighings of a test, checked (module docstring).

    Raises:
        FileRowError: naming the file, line and column.
    """
    source = str(path)
    rows, has_soak = _rows(path)
    series: dict[str, list[tuple[int, float, float]]] = {}
    soaks: dict[str, list[tuple[int, float, float]]] = {}
    for line, cycle, station, mass, soak in rows:
        series.setdefault(station, []).append((line, cycle, mass))
        if soak is not None:
            soaks.setdefault(station, []).append((line, cycle, soak))
    for station, values in series.items():
        _check_series(source, station, values, "mass_mg")
    for station, values in soaks.items():
        _check_series(source, station, values, "soak_mg")
    stations = []
    for station, values in series.items():
        if station == SOAK or station.startswith(SOAK + "_"):
            continue
        lines = np.array([line for line, _, _ in values])
        cycles = np.array([cycle for _, cycle, _ in values])
        if has_soak:
            if len(soaks.get(station, ())) != len(values):
                line = next(line for line, _, st, _, soak in rows if st == station and soak is None)
                raise FileRowError(
                    f"station {station} has no soak control at this stop: give its soak_mg",
                    source=source,
                    line=line,
                    column="soak_mg",
                )
            control, soak_mass = "soak_mg", np.array([m for _, _, m in soaks[station]])
        else:
            control = f"{SOAK}_{station}" if f"{SOAK}_{station}" in series else SOAK
            if control not in series:
                raise FileRowError(
                    f"station {station} has no soak control: add rows of station '{SOAK}' (for every station) or "
                    f"'{SOAK}_{station}', or a soak_mg column",
                    source=source,
                    line=int(lines[0]),
                    column="station",
                )
            by_cycle = {cycle: mass for _, cycle, mass in series[control]}
            absent = [k for k, cycle in enumerate(cycles) if cycle not in by_cycle]
            if absent:
                k = absent[0]
                raise FileRowError(
                    f"station {station} is weighed at cycle {cycles[k]:.0f} and its soak control '{control}' is not",
                    source=source,
                    line=int(lines[k]),
                    column="cycle",
                )
            soak_mass = np.array([by_cycle[cycle] for cycle in cycles])
        if len(values) < 2:
            raise FileRowError(
                f"station {station} is weighed once: a wear rate needs at least two stops",
                source=source,
                line=int(lines[0]),
            )
        stations.append(
            StationWeighings(station, control, cycles, np.array([m for _, _, m in values]), soak_mass, lines)
        )
    if not stations:
        raise FileRowError("no station besides soak controls", source=source)
    return Weighings(source, tuple(stations))

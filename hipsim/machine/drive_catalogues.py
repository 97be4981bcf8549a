"""Drive catalogues (CSV): motors with their amplifiers, lead screws and gearboxes, one part a line.

Read by :mod:`hipsim.tables`' rules, as trajectory files are: UTF-8, ``#``
starts a comment line, blank lines skipped, separated by commas, semicolons
or tabs (then possibly with decimal commas), no line longer than
:data:`hipsim.tables.MAX_LINE_BYTES`. Each cell takes the names and units of
:data:`hipsim.machine.drive_fields.FIELDS` (a list's numbers separated by
spaces, or by ``;`` in a comma-separated file). A bad entry is one
:class:`~hipsim.exceptions.CatalogueError` naming the file, line and column.
"""

from __future__ import annotations

from pathlib import Path
from typing import NoReturn

from ..exceptions import CatalogueError
from ..tables import cells, data_lines, detect_separator, number, read_text
from .drive_fields import (
    FIELDS,
    MOTOR_CATALOGUE,
    REQUIRED_COLUMNS,
    Fail,
    Field,
    checked_value,
    field_lookup,
    gearbox_from,
    motor_parts,
)
from .drive_parts import Amplifier, Gearbox, LeadScrew, Motor

__all__ = ["MAX_NAME", "load_gearbox_catalogue", "load_motor_catalogue", "load_screw_catalogue"]

#: The longest text cell (a part's name, an end fixing), in characters: a longer one is another file's content.
MAX_NAME = 200


def _read_catalogue(
    path: str | Path, tables: tuple[str, ...], required: tuple[str, ...], what: str, exclude: tuple[str, ...] = ()
):
    """Rows of a catalogue as (line number, values by base name, column names by base name, fail)."""
    source = str(path)
    text = read_text(path, what, CatalogueError, not_text="not a UTF-8 text file")
    numbered = data_lines(text.split("\n"), "")  # a row of empty cells is an entry's error
    lookup = field_lookup(tables, exclude)
    header: list[str] | None = None
    header_line = 0
    rows = []
    separator = detect_separator(numbered[0][1], numbered[1][1] if len(numbered) > 1 else None) if numbered else ","
    decimal_comma = separator != ","
    for line_number, line in numbered:
        row = [cell.strip() for cell in cells(line, separator)]
        if header is None:
            header, header_line = row, line_number
            for column in header:
                if column not in lookup:
                    raise CatalogueError(f"unknown column (known: {', '.join(lookup)})", source, line_number, column)
            bases = [lookup[c][1] for c in header]
            for k, base in enumerate(bases):
                if base in bases[:k]:
                    raise CatalogueError("the same quantity in two columns", source, line_number, header[k])
            for base in required:
                if base not in bases:
                    spec = next(FIELDS[t][base] for t in tables if base in FIELDS[t])
                    alternatives = " or ".join(f"'{n}'" for n in spec.names(base))
                    raise CatalogueError(f"missing column {alternatives} ({spec.meaning})", source, line_number)
            continue
        if len(row) != len(header):
            raise CatalogueError(f"{len(row)} cells for {len(header)} columns", source, line_number)

        def fail(message: str, column: str, line_number=line_number) -> NoReturn:
            raise CatalogueError(message, source, line_number, column)

        values, names = {}, {}
        for column, cell in zip(header, row):
            _, base, spec, factor = lookup[column]
            names[base] = column
            if not cell:
                if base in required:
                    fail("empty, but this column is required", column)
                continue
            values[base] = checked_value(
                spec, factor, _parse_cell(cell, spec, column, fail, decimal_comma), column, fail
            )
        rows.append((line_number, values, names, fail))
    if header is None or not rows:
        raise CatalogueError(
            f"no entries (expected a header line and one {what.split()[0]} a line)", source, header_line or None
        )
    seen: dict[str, int] = {}
    for line_number, values, names, fail in rows:
        if values["name"] in seen:
            fail(f"name '{values['name']}' already used on line {seen[values['name']]}", names["name"])
        seen[values["name"]] = line_number
    return rows


def _parse_cell(cell: str, spec: Field, column: str, fail: Fail, decimal_comma: bool = False):
    """A CSV cell as TOML would give it: text, a number, or (lists) numbers separated by ';' or spaces."""
    if spec.kind in ("text", "choice"):
        if len(cell) > MAX_NAME:
            fail(f"{len(cell):,} characters; a name is at most {MAX_NAME}", column)
        return cell
    parts = cell.replace(";", " ").split()
    numbers = []
    for part in parts:
        try:
            numbers.append(number(part, decimal_comma))  # refuses 1_0, which float() reads as 10
        except ValueError:
            fail(f"'{part}' is not a number", column)
    return numbers if spec.kind == "list" else (numbers[0] if len(numbers) == 1 else numbers)


def load_motor_catalogue(path: str | Path) -> list[tuple[Motor, Amplifier | None]]:
    """Motors, each with its servo amplifier's figures, one a line.

    Columns (units in the names; see :func:`file_fields` for all): ``name``,
    ``s1_torque_Nm`` or ``s1_torque_Nmm`` and ``peak_torque_Nm`` or
    ``peak_torque_Nmm`` are required (with ``s1_speed_rpm`` and
    ``peak_speed_rpm``, point lists separated by ``;``; a torque alone is a flat
    curve); ``max_speed_rpm``, ``rotor_inertia_kgcm2``, ``torque_constant_Nm_A``,
    ``winding_resistance_ohm``, ``thermal_time_constant_s`` (or ``_min``),
    ``thermal_resistance_K_W``, ``amplifier_peak_current_A``,
    ``amplifier_continuous_current_A``, ``dc_bus_energy_J``, ``braking_power_W``,
    ``braking_peak_power_W`` are optional (an empty cell: not given).

    Raises:
        CatalogueError: one line naming the file, line and column.
    """
    out = []
    # A catalogue line gives whole curves: no scalar rated torque; the module ratings belong to the screws.
    exclude = ("rated_torque", "stroke", "axial_force")
    for _line, values, names, fail in _read_catalogue(
        path, MOTOR_CATALOGUE, REQUIRED_COLUMNS["motor"], "motor catalogue", exclude
    ):
        motor, amplifier, _ = motor_parts(values, names, fail, default_name="")
        out.append((motor, amplifier))
    return out


def load_screw_catalogue(path: str | Path) -> list[LeadScrew]:
    """Lead screws, one a line: ``name``, ``lead_mm`` required; ``inertia_kgmm2``, ``dynamic_load_rating_N``,
    ``preload_N``, ``root_diameter_mm``, ``free_length_mm``, ``end_fixing``, ``stroke_mm``, ``axial_force_N`` optional.

    Raises:
        CatalogueError: one line naming the file, line and column.
    """
    rows = _read_catalogue(path, ("lead_screw",), REQUIRED_COLUMNS["lead_screw"], "screw catalogue")
    return [
        LeadScrew(name=v["name"], **{FIELDS["lead_screw"][k].attribute: x for k, x in v.items() if k != "name"})
        for _, v, _, _ in rows
    ]


def load_gearbox_catalogue(path: str | Path) -> list[Gearbox]:
    """Gearboxes, one a line: ``name``, ``ratio`` required; ``efficiency``, ``inertia_kgcm2`` optional (a ratio-1 line for direct drive).

    Raises:
        CatalogueError: one line naming the file, line and column.
    """
    rows = _read_catalogue(path, ("gearbox",), REQUIRED_COLUMNS["gearbox"], "gearbox catalogue")
    return [gearbox_from(v, n, f, v["name"]) for _, v, n, f in rows]

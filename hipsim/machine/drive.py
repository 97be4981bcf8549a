"""The drive train of each linear module: motor, servo amplifier, gearbox and lead screw, and the sizing rules.

Three ways in, all with the same names and units (the unit is in every name):

- a **drive file** (TOML): one ``[motor]`` table and optional ``[amplifier]``,
  ``[gearbox]``, ``[lead_screw]`` and ``[rules]`` tables (:func:`load_drive`;
  ``models/drive_example.toml`` is an annotated example). A parameter file's
  own ``[motor]`` table (the five scalar ratings) is read by
  :func:`drive_from_motor_table`.
- **catalogues** (CSV, one part a line, ``#`` starts a comment line): motors
  (with their amplifier's figures on the same line), lead screws, gearboxes
  (:func:`load_motor_catalogue`, :func:`load_screw_catalogue`,
  :func:`load_gearbox_catalogue`, from :mod:`hipsim.machine.drive_catalogues`).
  A bad entry is one line naming the file, line and column.
- the dataclasses themselves, in SI units (:mod:`hipsim.machine.drive_parts`,
  which also says how a torque–speed curve is read).

This module reads the drive files and is the door to the rest: every name of
the drive train is importable from here. The fields both kinds of file take
are in :mod:`hipsim.machine.drive_fields`.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any, NoReturn

from ..exceptions import ParameterError
from .drive_catalogues import load_gearbox_catalogue, load_motor_catalogue, load_screw_catalogue
from .drive_fields import FIELDS, checked_value, field_lookup, file_fields, gearbox_from, motor_parts
from .drive_parts import END_FIXINGS, Amplifier, Drive, Gearbox, LeadScrew, Motor, SizingRules, TorqueSpeedCurve
from .parameters import SCHEMA, read_toml

__all__ = [
    "END_FIXINGS",
    "Amplifier",
    "Drive",
    "Gearbox",
    "LeadScrew",
    "Motor",
    "SizingRules",
    "TorqueSpeedCurve",
    "drive_from_motor_table",
    "file_fields",
    "load_drive",
    "load_gearbox_catalogue",
    "load_motor_catalogue",
    "load_screw_catalogue",
]


def load_drive(path: str | Path) -> Drive:
    """Read a drive file: TOML with a ``[motor]`` table and optional ``[amplifier]``, ``[gearbox]``, ``[lead_screw]``, ``[rules]``.

    A parameter file serves too: its ``[motor]`` table is read and its other
    tables ignored. Example (every key optional but one in ``[motor]``)::

        [motor]
        name = "200 W servo"
        s1_speed_rpm = [0, 3000]
        s1_torque_Nmm = [640, 640]
        peak_speed_rpm = [0, 3000, 5000]
        peak_torque_Nmm = [1910, 1910, 900]
        rotor_inertia_kgcm2 = 0.14
        [lead_screw]
        dynamic_load_rating_N = 9000
        root_diameter_mm = 13.0
        free_length_mm = 400
        end_fixing = "fixed-supported"

    Raises:
        ParameterError: naming the file and key of anything missing, unknown or invalid.
    """
    source = str(path)
    raw = read_toml(path, "drive file")
    for section, table in raw.items():
        if section not in FIELDS and section not in SCHEMA:
            raise ParameterError(f"unknown section (expected [{'], ['.join(FIELDS)}])", key=section, source=source)
        if section in FIELDS and not isinstance(table, dict):
            raise ParameterError("expected a table", key=section, source=source)
    motor_table = raw.get("motor")
    if not isinstance(motor_table, dict) or not motor_table:
        known = ", ".join(file_fields("motor"))
        raise ParameterError(f"expected a [motor] table with any of {known}", key="motor", source=source)

    def fail(message: str, name: str) -> NoReturn:
        raise ParameterError(message, key=name, source=source)

    def read(section: str, tables: tuple[str, ...]) -> tuple[dict[str, Any], dict[str, str]]:
        lookup = field_lookup(tables)
        values: dict[str, Any] = {}
        names: dict[str, str] = {}
        for key, raw_value in raw.get(section, {}).items():
            if key not in lookup:
                fail(f"unknown key (known in [{section}]: {', '.join(lookup)})", f"{section}.{key}")
            _, base, spec, factor = lookup[key]
            if base in values:
                fail(f"given twice (also as {names[base]})", f"{section}.{key}")
            values[base] = checked_value(spec, factor, raw_value, f"{section}.{key}", fail)
            names[base] = f"{section}.{key}"
        return values, names

    values, names = read("motor", ("motor",))
    amp_values, amp_names = read("amplifier", ("amplifier",))
    motor, amplifier, module = motor_parts(values | amp_values, names | amp_names, fail, default_name=Path(source).stem)
    gearbox = None
    if "gearbox" in raw:
        g, g_names = read("gearbox", ("gearbox",))
        gearbox = gearbox_from(g, g_names, fail, default_name="gearbox")
    screw = None
    s, s_names = read("lead_screw", ("lead_screw",))
    if s or module:
        for key in module:
            if key in s:
                fail("given in [motor] and in [lead_screw]", s_names[key])
        s = s | module
        screw = LeadScrew(
            **{FIELDS["lead_screw"][k].attribute: v for k, v in s.items() if k != "name"},
            name=s.get("name", "lead screw"),
        )
    r, _ = read("rules", ("rules",))
    rules = SizingRules(**{FIELDS["rules"][k].attribute: v for k, v in r.items()})
    return Drive(motor, amplifier, gearbox, screw, rules, source)


def drive_from_motor_table(table: Mapping[str, float], source: str) -> Drive:
    """The drive of a parameter file's ``[motor]`` table (``Parameters.motor``: the scalar ratings, in the file's units)."""

    def fail(message: str, name: str) -> NoReturn:
        raise ParameterError(message, key=f"motor.{name}", source=source)

    lookup = field_lookup(("motor",))
    values, names = {}, {}
    for key, raw in table.items():
        if key not in lookup:
            fail("unknown key", key)
        _, base, spec, factor = lookup[key]
        values[base] = checked_value(spec, factor, raw, key, fail)
        names[base] = key
    motor, amplifier, module = motor_parts(values, names, fail, default_name="motor of the parameter file")
    screw = LeadScrew(name="lead screw of the parameter file", **module) if module else None
    return Drive(motor, amplifier, None, screw, SizingRules(), source)

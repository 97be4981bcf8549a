"""The entries of drive files and catalogues: each field's names, units (in the name), meaning and bounds, and their conversion to the parts in SI.

One table of fields (:data:`FIELDS`) serves the drive file (TOML,
:mod:`hipsim.machine.drive`) and the catalogues (CSV,
:mod:`hipsim.machine.drive_catalogues`), so both take the same names and units.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any, NoReturn

import numpy as np

from ..physics.units import RAD_S_PER_RPM
from ..plausibility import drive_slip
from .drive_parts import END_FIXINGS, Amplifier, Gearbox, Motor, TorqueSpeedCurve

__all__ = [
    "FIELDS",
    "MOTOR_CATALOGUE",
    "REQUIRED_COLUMNS",
    "Fail",
    "Field",
    "checked_value",
    "field_lookup",
    "file_fields",
    "gearbox_from",
    "motor_parts",
    "torque_speed_curve",
]


@dataclass(frozen=True)
class Field:
    """One entry: its base name, the units it may be given in (suffix → SI factor), kind and bound."""

    attribute: str
    units: dict[str, float]
    meaning: str
    kind: str = "number"  # number, list, text, choice
    bound: str = "positive"  # positive, nonnegative, fraction, atleast1

    def names(self, base: str) -> list[str]:
        return [f"{base}_{unit}" if unit else base for unit in self.units]


_TORQUE = {"Nm": 1.0, "Nmm": 1e-3}
_INERTIA = {"kgcm2": 1e-4, "kgmm2": 1e-6}

#: Every table and its fields: base name → field. A field's file name is base + "_" + unit.
FIELDS: dict[str, dict[str, Field]] = {
    "motor": {
        "name": Field("name", {"": 1.0}, "the motor's name", "text"),
        "s1_speed": Field(
            "s1_speed", {"rpm": RAD_S_PER_RPM}, "speeds of the S1 (continuous) curve", "list", "nonnegative"
        ),
        "s1_torque": Field("s1_torque", _TORQUE, "torques of the S1 curve (one value: flat)", "list", "nonnegative"),
        "peak_speed": Field("peak_speed", {"rpm": RAD_S_PER_RPM}, "speeds of the peak curve", "list", "nonnegative"),
        "peak_torque": Field(
            "peak_torque", _TORQUE, "torques of the peak curve (one value: flat)", "list", "nonnegative"
        ),
        "rated_torque": Field("rated_torque", _TORQUE, "rated (continuous) torque: a flat S1 curve"),
        "max_speed": Field("max_speed", {"rpm": RAD_S_PER_RPM}, "highest permitted speed"),
        "rotor_inertia": Field("rotor_inertia", _INERTIA, "rotor inertia J_m"),
        "torque_constant": Field("torque_constant", {"Nm_A": 1.0}, "torque constant k_t"),
        "winding_resistance": Field("winding_resistance", {"ohm": 1.0}, "phase-to-phase winding resistance"),
        "thermal_time_constant": Field(
            "thermal_time_constant", {"s": 1.0, "min": 60.0}, "winding thermal time constant"
        ),
        "thermal_resistance": Field("thermal_resistance", {"K_W": 1.0}, "winding-to-ambient thermal resistance"),
        "rated_power": Field("rated_power", {"W": 1.0, "kW": 1e3}, "rated power (ranks a catalogue)"),
        "cost": Field(
            "cost", {"": 1.0}, "price or any cost figure (breaks ties in a ranked catalogue)", bound="nonnegative"
        ),
        # The module ratings of the parameter file's [motor] table; they belong to the screw.
        "stroke": Field("stroke", {"mm": 1e-3}, "usable stroke of the linear module"),
        "axial_force": Field("axial_force", {"N": 1.0}, "permissible axial screw load"),
    },
    "amplifier": {
        "amplifier_peak_current": Field("peak_current", {"A": 1.0}, "amplifier peak current"),
        "amplifier_continuous_current": Field("continuous_current", {"A": 1.0}, "amplifier continuous current"),
        "dc_bus_energy": Field("dc_bus_energy", {"J": 1.0}, "regenerated energy the DC link takes in"),
        "braking_power": Field("braking_power", {"W": 1.0}, "continuous braking resistor power"),
        "braking_peak_power": Field("braking_peak_power", {"W": 1.0}, "peak braking resistor power"),
    },
    "gearbox": {
        "name": Field("name", {"": 1.0}, "the gearbox's name", "text"),
        "ratio": Field("ratio", {"": 1.0}, "ratio i = motor speed / screw speed"),
        "efficiency": Field("efficiency", {"": 1.0}, "efficiency η", bound="fraction"),
        "inertia": Field("inertia", _INERTIA, "inertia referred to the motor shaft", bound="nonnegative"),
    },
    "lead_screw": {
        "name": Field("name", {"": 1.0}, "the screw's name", "text"),
        "lead": Field("lead", {"mm": 1e-3}, "lead p"),
        "inertia": Field("inertia", {"kgmm2": 1e-6, "kgcm2": 1e-4}, "screw inertia I_L", bound="nonnegative"),
        "dynamic_load_rating": Field("dynamic_load_rating", {"N": 1.0}, "dynamic load rating C_a (ISO 3408-5)"),
        "preload": Field("preload", {"N": 1.0}, "nut preload F_pr", bound="nonnegative"),
        "root_diameter": Field("root_diameter", {"mm": 1e-3}, "root diameter d_2"),
        "free_length": Field("free_length", {"mm": 1e-3}, "unsupported length"),
        "end_fixing": Field("end_fixing", {"": 1.0}, f"end fixing ({', '.join(END_FIXINGS)})", "choice"),
        "stroke": Field("stroke", {"mm": 1e-3}, "usable stroke of the linear module"),
        "axial_force": Field("axial_force", {"N": 1.0}, "permissible axial load"),
    },
    "rules": {
        "inertia_ratio_max": Field("inertia_ratio_max", {"": 1.0}, "largest load-to-rotor inertia ratio"),
        "life_target": Field("life_target_cycles", {"cycles": 1.0}, "screw L10 life to reach"),
        "winding_rise_max": Field("winding_rise_max", {"K": 1.0}, "largest winding temperature rise"),
        "rated_winding_rise": Field("rated_winding_rise", {"K": 1.0}, "rise at which the S1 stall torque is rated"),
        "critical_speed_factor": Field(
            "critical_speed_factor", {"": 1.0}, "fraction of the critical speed allowed", bound="fraction"
        ),
        "buckling_factor": Field(
            "buckling_factor", {"": 1.0}, "fraction of the buckling load allowed", bound="fraction"
        ),
    },
}

#: The catalogue CSVs: table, the fields each line may carry, and the columns it must have.
MOTOR_CATALOGUE = ("motor", "amplifier")
REQUIRED_COLUMNS = {
    "motor": ("name", "s1_torque", "peak_torque"),
    "lead_screw": ("name", "lead"),
    "gearbox": ("name", "ratio"),
}


def file_fields(table: str) -> dict[str, str]:
    """Every name a table's field may take in a file, with its meaning and unit: for help texts and the README."""
    out = {}
    for base, spec in FIELDS[table].items():
        for unit, name in zip(spec.units, spec.names(base)):
            out[name] = spec.meaning + (f" [{unit}]" if unit else "")
    return out


def field_lookup(tables: tuple[str, ...], exclude: tuple[str, ...] = ()) -> dict[str, tuple[str, str, Field, float]]:
    """File name → (table, base, field, SI factor), leaving out the ``exclude`` bases."""
    out = {}
    for table in tables:
        for base, spec in FIELDS[table].items():
            if base in exclude:
                continue
            for (_unit, factor), name in zip(spec.units.items(), spec.names(base)):
                out[name] = (table, base, spec, factor)
    return out


Fail = Callable[[str, str], NoReturn]  # (message, name) → raises


def checked_value(spec: Field, factor: float, raw: Any, name: str, fail: Fail):
    """One entry checked and converted to SI: a float, an array (lists), or text."""
    if spec.kind == "text":
        text = str(raw).strip() if isinstance(raw, (str, int, float)) and not isinstance(raw, bool) else None
        if not text:
            fail(f"expected a name, got {raw!r}", name)
        return text
    if spec.kind == "choice":
        text = str(raw).strip().lower() if isinstance(raw, str) else None
        if text not in END_FIXINGS:
            fail(f"expected one of {', '.join(END_FIXINGS)}, got {raw!r}", name)
        return text
    items = raw if isinstance(raw, list) else [raw]
    if spec.kind != "list" and isinstance(raw, list):
        fail(f"expected one number, got a list {raw!r}", name)
    if not items or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in items):
        fail(f"expected {'numbers' if spec.kind == 'list' else 'a number'}, got {raw!r}", name)
    values = np.array(items, dtype=float)
    if not np.all(np.isfinite(values)):
        fail(f"expected finite numbers, got {raw!r}", name)
    if spec.bound == "positive" and np.any(values <= 0):
        fail(f"must be positive, got {raw!r}", name)
    if spec.bound in ("nonnegative", "fraction", "positive") and np.any(values < 0):
        fail(f"must not be negative, got {raw!r}", name)
    if spec.bound == "fraction" and np.any((values <= 0) | (values > 1)):
        fail(f"must lie in (0, 1], got {raw!r}", name)
    if np.any(np.abs(values) > 1e9):
        fail(f"out of range (a unit slip?): {raw!r}", name)
    values = values * factor
    stem = spec.attribute + "_"
    key = name.rsplit(".", 1)[-1]
    written = key[len(stem) :] if key.startswith(stem) else (key.rsplit("_", 1)[-1] if "_" in key else "")
    slip = drive_slip(spec.attribute, values, written.replace("Nm_A", "N·m/A"), factor)
    if slip is not None:
        fail(slip, name)
    return values if spec.kind == "list" else float(values[0])


def torque_speed_curve(
    values: dict[str, Any], names: dict[str, str], prefix: str, fail: Fail
) -> TorqueSpeedCurve | None:
    """The S1 or peak curve from ``<prefix>_speed`` and ``<prefix>_torque`` (one torque alone: flat)."""
    speed, torque = values.get(f"{prefix}_speed"), values.get(f"{prefix}_torque")
    if torque is None:
        if speed is not None:
            fail(f"speeds without torques: give {prefix}_torque too", names[f"{prefix}_speed"])
        return None
    if speed is None:
        if torque.size != 1:
            fail(
                f"{torque.size} torques without speeds: give {prefix}_speed_rpm too (or one torque for a flat curve)",
                names[f"{prefix}_torque"],
            )
        return TorqueSpeedCurve(np.zeros(1), torque)
    if speed.size != torque.size:
        fail(f"{torque.size} torques for {speed.size} speeds", names[f"{prefix}_torque"])
    steps = np.diff(speed)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        fail(
            f"speeds must rise strictly (point {k + 2} is at {speed[k + 1] / RAD_S_PER_RPM:g} rpm after {speed[k] / RAD_S_PER_RPM:g} rpm)",
            names[f"{prefix}_speed"],
        )
    return TorqueSpeedCurve(speed, torque)


def motor_parts(values: dict[str, Any], names: dict[str, str], fail: Fail, default_name: str):
    """Motor, amplifier and the module ratings (stroke, axial force) from checked values by base name."""
    continuous = torque_speed_curve(values, names, "s1", fail)
    if "rated_torque" in values:
        if continuous is not None:
            fail("give either rated_torque or an S1 curve, not both", names["rated_torque"])
        continuous = TorqueSpeedCurve(np.zeros(1), np.array([values["rated_torque"]]))
    motor = Motor(
        name=values.get("name", default_name),
        continuous=continuous,
        peak=torque_speed_curve(values, names, "peak", fail),
        **{
            FIELDS["motor"][k].attribute: values[k]
            for k in (
                "max_speed",
                "rotor_inertia",
                "torque_constant",
                "winding_resistance",
                "thermal_time_constant",
                "thermal_resistance",
                "rated_power",
                "cost",
            )
            if k in values
        },
    )
    amplifier_values = {FIELDS["amplifier"][k].attribute: values[k] for k in FIELDS["amplifier"] if k in values}
    amplifier = Amplifier(**amplifier_values) if amplifier_values else None
    module = {k: values[k] for k in ("stroke", "axial_force") if k in values}
    return motor, amplifier, module


def gearbox_from(values: dict[str, Any], names: dict[str, str], fail: Fail, default_name: str) -> Gearbox:
    """A :class:`Gearbox` from checked SI values by field name (``name`` defaults to ``default_name``)."""
    attributes = {FIELDS["gearbox"][k].attribute: v for k, v in values.items() if k != "name"}
    return Gearbox(name=values.get("name", default_name), **attributes)

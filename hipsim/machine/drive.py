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
  :func:`load_gearbox_catalogue`). A bad entry is one line naming the file,
  line and column.
- the dataclasses themselves, in SI units.

A torque–speed curve is a list of speeds and a list of torques: the S1
(continuous) and the peak curve of a motor data sheet. Speeds must rise
strictly; torques must not be negative; between points the curve is linear,
below the first point it holds the first torque, beyond the last point it is
zero (the motor cannot go faster). A single torque without speeds is a flat
curve at every speed (the old scalar ratings ``rated_torque_Nmm`` and
``peak_torque_Nmm`` are read that way).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable, Mapping, NoReturn

import numpy as np

from ..arrays import readonly
from ..exceptions import CatalogueError, ParameterError
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

_RPM = 2.0 * math.pi / 60.0  # rad/s per rpm

#: End fixings of a lead screw: (λ of the first bending mode, Euler buckling factor m = π²/(K·l)²·l²/π², i.e. 1/K²).
#: λ·l are the roots of the beam equations (Euler–Bernoulli); 1/K² from the effective length K·l.
END_FIXINGS = {
    "fixed-free": (1.8751, 0.25),
    "supported-supported": (math.pi, 1.0),
    "fixed-supported": (3.9266, 2.046),
    "fixed-fixed": (4.7300, 4.0),
}


# ---------------------------------------------------------------------------
# The parts


@dataclass(frozen=True, eq=False)
class TorqueSpeedCurve:
    """A motor's torque limit against speed.

    Attributes:
        speed: speeds in [rad/s], (K,), rising strictly, ≥ 0; a single point with ``flat`` for a flat curve.
        torque: torques in [N·m], (K,), ≥ 0.
    """

    speed: np.ndarray
    torque: np.ndarray

    def __post_init__(self):
        speed = readonly(np.atleast_1d(np.asarray(self.speed, dtype=float)))
        torque = readonly(np.atleast_1d(np.asarray(self.torque, dtype=float)))
        if speed.ndim != 1 or speed.shape != torque.shape or speed.size == 0:
            raise ValueError(f"TorqueSpeedCurve: speed {speed.shape} and torque {torque.shape} must be equal non-empty 1-D arrays")
        if np.any(np.diff(speed) <= 0) or np.any(speed < 0) or np.any(torque < 0):
            raise ValueError("TorqueSpeedCurve: speeds must rise strictly from ≥ 0 and torques must not be negative")
        object.__setattr__(self, "speed", speed)
        object.__setattr__(self, "torque", torque)

    @property
    def flat(self) -> bool:
        """True for a single point: the same torque at every speed."""
        return self.speed.size == 1

    @property
    def end_speed(self) -> float:
        """The last speed of the curve in [rad/s]; infinity for a flat curve."""
        return math.inf if self.flat else float(self.speed[-1])

    def at(self, speed) -> np.ndarray:
        """The torque limit in [N·m] at speeds in [rad/s] (either sign), zero beyond the curve's end."""
        speed = np.abs(np.asarray(speed, dtype=float))
        if self.flat:
            return np.full(speed.shape, float(self.torque[0]))
        return np.interp(speed, self.speed, self.torque, left=float(self.torque[0]), right=0.0)


@dataclass(frozen=True, eq=False)
class Motor:
    """A servo motor; None for a figure the data sheet does not give (the checks that need it say so).

    Attributes:
        name: the motor's name.
        continuous: the S1 (continuous duty) torque–speed curve.
        peak: the peak torque–speed curve.
        max_speed: the highest permitted speed in [rad/s] (default: the end of the peak curve).
        rotor_inertia: J_m in [kg·m²].
        torque_constant: k_t in [N·m/A] (per RMS phase current).
        winding_resistance: R_pp, phase-to-phase, in [Ω] (copper loss 3/2·R_pp·I², star winding).
        thermal_time_constant: τ_th of the winding in [s].
        thermal_resistance: R_th, winding to ambient, in [K/W].
    """

    name: str
    continuous: TorqueSpeedCurve | None = None
    peak: TorqueSpeedCurve | None = None
    max_speed: float | None = None
    rotor_inertia: float | None = None
    torque_constant: float | None = None
    winding_resistance: float | None = None
    thermal_time_constant: float | None = None
    thermal_resistance: float | None = None

    @property
    def top_speed(self) -> float | None:
        """The highest speed in [rad/s]: ``max_speed``, else the end of the peak (or S1) curve; None if unknown."""
        if self.max_speed is not None:
            return self.max_speed
        for curve in (self.peak, self.continuous):
            if curve is not None and not curve.flat:
                return curve.end_speed
        return None


@dataclass(frozen=True)
class Amplifier:
    """The servo amplifier (drive) of a motor and its DC link; None for a figure not given.

    Attributes:
        peak_current: in [A] (RMS phase current).
        continuous_current: in [A].
        dc_bus_energy: regenerated energy the DC link capacitors take in without a braking resistor, in [J].
        braking_power: continuous power of the braking resistor in [W].
        braking_peak_power: peak power of the braking resistor (chopper) in [W].
    """

    peak_current: float | None = None
    continuous_current: float | None = None
    dc_bus_energy: float | None = None
    braking_power: float | None = None
    braking_peak_power: float | None = None


@dataclass(frozen=True)
class Gearbox:
    """A gearbox (or belt stage) between motor and screw.

    Attributes:
        name: its name.
        ratio: i = motor speed / screw speed [–].
        efficiency: η in (0, 1], the same in both directions of power flow.
        inertia: its inertia referred to the motor shaft in [kg·m²].
    """

    name: str
    ratio: float = 1.0
    efficiency: float = 1.0
    inertia: float = 0.0


#: The motor coupled straight to the screw.
DIRECT = Gearbox("direct", 1.0, 1.0, 0.0)


@dataclass(frozen=True)
class LeadScrew:
    """A lead (ball) screw and its nut; None for a figure not given.

    Attributes:
        name: its name.
        lead: p in [m] per turn; None to keep the machine's.
        inertia: I_L, the screw's inertia about its axis, in [kg·m²]; None to keep the machine's.
        dynamic_load_rating: C_a in [N] (ISO 3408-5; of one nut half for a preloaded double nut).
        preload: F_pr in [N], the nut's preload (0 for none).
        root_diameter: d_2 in [m], for the critical speed and buckling load.
        free_length: unsupported length l between the bearings (or bearing and nut) in [m].
        end_fixing: one of :data:`END_FIXINGS`.
        stroke: usable stroke of the linear module in [m].
        axial_force: permissible axial load in [N].
    """

    name: str
    lead: float | None = None
    inertia: float | None = None
    dynamic_load_rating: float | None = None
    preload: float = 0.0
    root_diameter: float | None = None
    free_length: float | None = None
    end_fixing: str | None = None
    stroke: float | None = None
    axial_force: float | None = None

    def __post_init__(self):
        if self.end_fixing is not None and self.end_fixing not in END_FIXINGS:
            raise ValueError(f"LeadScrew.end_fixing: expected one of {', '.join(END_FIXINGS)}, got {self.end_fixing!r}")


@dataclass(frozen=True)
class SizingRules:
    """What a design must meet (the defaults are the usual industrial rules; each settable).

    Attributes:
        inertia_ratio_max: largest load-to-rotor inertia ratio [–] (10:1 by default).
        life_target_cycles: lead screw L10 life to reach, in test cycles (ISO 14242-1: 5×10⁶).
        winding_rise_max: largest winding temperature rise in [K].
        rated_winding_rise: the rise at which the S1 stall torque is rated, in [K] (servo data sheets:
            100 K over 40 °C ambient); sets R_th when the motor gives none.
        critical_speed_factor: fraction of the screw's critical (whirling) speed allowed [–].
        buckling_factor: fraction of the screw's Euler buckling load allowed [–].
    """

    inertia_ratio_max: float = 10.0
    life_target_cycles: float = 5e6
    winding_rise_max: float = 100.0
    rated_winding_rise: float = 100.0
    critical_speed_factor: float = 0.8
    buckling_factor: float = 0.5


@dataclass(frozen=True)
class Drive:
    """One linear module's drive train: the same for all three modules.

    Attributes:
        motor: the motor.
        amplifier: its servo amplifier, or None.
        gearbox: the gearbox between motor and screw, or None for a direct coupling.
        screw: the lead screw, or None.
        rules: the sizing rules that came with it.
        source: where it came from.
    """

    motor: Motor
    amplifier: Amplifier | None = None
    gearbox: Gearbox | None = None
    screw: LeadScrew | None = None
    rules: SizingRules = field(default_factory=SizingRules)
    source: str = "<given>"

    @property
    def name(self) -> str:
        """"motor", "motor + gearbox", "motor + gearbox + screw"."""
        parts = [self.motor.name]
        if self.gearbox is not None and self.gearbox is not DIRECT:
            parts.append(self.gearbox.name)
        if self.screw is not None:
            parts.append(self.screw.name)
        return " + ".join(parts)


# ---------------------------------------------------------------------------
# The fields of files and catalogues


@dataclass(frozen=True)
class _Field:
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
FIELDS: dict[str, dict[str, _Field]] = {
    "motor": {
        "name": _Field("name", {"": 1.0}, "the motor's name", "text"),
        "s1_speed": _Field("s1_speed", {"rpm": _RPM}, "speeds of the S1 (continuous) curve", "list", "nonnegative"),
        "s1_torque": _Field("s1_torque", _TORQUE, "torques of the S1 curve (one value: flat)", "list", "nonnegative"),
        "peak_speed": _Field("peak_speed", {"rpm": _RPM}, "speeds of the peak curve", "list", "nonnegative"),
        "peak_torque": _Field("peak_torque", _TORQUE, "torques of the peak curve (one value: flat)", "list", "nonnegative"),
        "rated_torque": _Field("rated_torque", _TORQUE, "rated (continuous) torque: a flat S1 curve"),
        "max_speed": _Field("max_speed", {"rpm": _RPM}, "highest permitted speed"),
        "rotor_inertia": _Field("rotor_inertia", _INERTIA, "rotor inertia J_m"),
        "torque_constant": _Field("torque_constant", {"Nm_A": 1.0}, "torque constant k_t"),
        "winding_resistance": _Field("winding_resistance", {"ohm": 1.0}, "phase-to-phase winding resistance"),
        "thermal_time_constant": _Field("thermal_time_constant", {"s": 1.0, "min": 60.0}, "winding thermal time constant"),
        "thermal_resistance": _Field("thermal_resistance", {"K_W": 1.0}, "winding-to-ambient thermal resistance"),
        # The module ratings of the parameter file's [motor] table; they belong to the screw.
        "stroke": _Field("stroke", {"mm": 1e-3}, "usable stroke of the linear module"),
        "axial_force": _Field("axial_force", {"N": 1.0}, "permissible axial screw load"),
    },
    "amplifier": {
        "amplifier_peak_current": _Field("peak_current", {"A": 1.0}, "amplifier peak current"),
        "amplifier_continuous_current": _Field("continuous_current", {"A": 1.0}, "amplifier continuous current"),
        "dc_bus_energy": _Field("dc_bus_energy", {"J": 1.0}, "regenerated energy the DC link takes in"),
        "braking_power": _Field("braking_power", {"W": 1.0}, "continuous braking resistor power"),
        "braking_peak_power": _Field("braking_peak_power", {"W": 1.0}, "peak braking resistor power"),
    },
    "gearbox": {
        "name": _Field("name", {"": 1.0}, "the gearbox's name", "text"),
        "ratio": _Field("ratio", {"": 1.0}, "ratio i = motor speed / screw speed"),
        "efficiency": _Field("efficiency", {"": 1.0}, "efficiency η", bound="fraction"),
        "inertia": _Field("inertia", _INERTIA, "inertia referred to the motor shaft", bound="nonnegative"),
    },
    "lead_screw": {
        "name": _Field("name", {"": 1.0}, "the screw's name", "text"),
        "lead": _Field("lead", {"mm": 1e-3}, "lead p"),
        "inertia": _Field("inertia", {"kgmm2": 1e-6, "kgcm2": 1e-4}, "screw inertia I_L", bound="nonnegative"),
        "dynamic_load_rating": _Field("dynamic_load_rating", {"N": 1.0}, "dynamic load rating C_a (ISO 3408-5)"),
        "preload": _Field("preload", {"N": 1.0}, "nut preload F_pr", bound="nonnegative"),
        "root_diameter": _Field("root_diameter", {"mm": 1e-3}, "root diameter d_2"),
        "free_length": _Field("free_length", {"mm": 1e-3}, "unsupported length"),
        "end_fixing": _Field("end_fixing", {"": 1.0}, f"end fixing ({', '.join(END_FIXINGS)})", "choice"),
        "stroke": _Field("stroke", {"mm": 1e-3}, "usable stroke of the linear module"),
        "axial_force": _Field("axial_force", {"N": 1.0}, "permissible axial load"),
    },
    "rules": {
        "inertia_ratio_max": _Field("inertia_ratio_max", {"": 1.0}, "largest load-to-rotor inertia ratio"),
        "life_target": _Field("life_target_cycles", {"cycles": 1.0}, "screw L10 life to reach"),
        "winding_rise_max": _Field("winding_rise_max", {"K": 1.0}, "largest winding temperature rise"),
        "rated_winding_rise": _Field("rated_winding_rise", {"K": 1.0}, "rise at which the S1 stall torque is rated"),
        "critical_speed_factor": _Field("critical_speed_factor", {"": 1.0}, "fraction of the critical speed allowed", bound="fraction"),
        "buckling_factor": _Field("buckling_factor", {"": 1.0}, "fraction of the buckling load allowed", bound="fraction"),
    },
}

#: The catalogue CSVs: table, the fields each line may carry, and the columns it must have.
_MOTOR_CATALOGUE = ("motor", "amplifier")
_REQUIRED = {
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


def _lookup(tables: tuple[str, ...], exclude: tuple[str, ...] = ()) -> dict[str, tuple[str, str, _Field, float]]:
    """File name → (table, base, field, SI factor), leaving out the ``exclude`` bases."""
    out = {}
    for table in tables:
        for base, spec in FIELDS[table].items():
            if base in exclude:
                continue
            for (unit, factor), name in zip(spec.units.items(), spec.names(base)):
                out[name] = (table, base, spec, factor)
    return out


Fail = Callable[[str, str], NoReturn]  # (message, name) → raises


def _value(spec: _Field, factor: float, raw: Any, name: str, fail: Fail):
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
    return values if spec.kind == "list" else float(values[0])


def _curve(values: dict[str, Any], names: dict[str, str], prefix: str, fail: Fail) -> TorqueSpeedCurve | None:
    """The S1 or peak curve from ``<prefix>_speed`` and ``<prefix>_torque`` (one torque alone: flat)."""
    speed, torque = values.get(f"{prefix}_speed"), values.get(f"{prefix}_torque")
    if torque is None:
        if speed is not None:
            fail(f"speeds without torques: give {prefix}_torque too", names[f"{prefix}_speed"])
        return None
    if speed is None:
        if torque.size != 1:
            fail(f"{torque.size} torques without speeds: give {prefix}_speed_rpm too (or one torque for a flat curve)", names[f"{prefix}_torque"])
        return TorqueSpeedCurve(np.zeros(1), torque)
    if speed.size != torque.size:
        fail(f"{torque.size} torques for {speed.size} speeds", names[f"{prefix}_torque"])
    steps = np.diff(speed)
    if np.any(steps <= 0):
        k = int(np.argmax(steps <= 0))
        fail(f"speeds must rise strictly (point {k + 2} is at {speed[k + 1] / _RPM:g} rpm after {speed[k] / _RPM:g} rpm)", names[f"{prefix}_speed"])
    return TorqueSpeedCurve(speed, torque)


def _parts(values: dict[str, Any], names: dict[str, str], fail: Fail, default_name: str):
    """Motor, amplifier and the module ratings (stroke, axial force) from checked values by base name."""
    continuous = _curve(values, names, "s1", fail)
    if "rated_torque" in values:
        if continuous is not None:
            fail("give either rated_torque or an S1 curve, not both", names["rated_torque"])
        continuous = TorqueSpeedCurve(np.zeros(1), np.array([values["rated_torque"]]))
    motor = Motor(
        name=values.get("name", default_name),
        continuous=continuous,
        peak=_curve(values, names, "peak", fail),
        **{FIELDS["motor"][k].attribute: values[k] for k in (
            "max_speed", "rotor_inertia", "torque_constant", "winding_resistance", "thermal_time_constant", "thermal_resistance",
        ) if k in values},
    )
    amplifier_values = {FIELDS["amplifier"][k].attribute: values[k] for k in FIELDS["amplifier"] if k in values}
    amplifier = Amplifier(**amplifier_values) if amplifier_values else None
    module = {k: values[k] for k in ("stroke", "axial_force") if k in values}
    return motor, amplifier, module


# ---------------------------------------------------------------------------
# Drive files (TOML)


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
        names = ", ".join(file_fields("motor"))
        raise ParameterError(f"expected a [motor] table with any of {names}", key="motor", source=source)

    def fail(message: str, name: str) -> NoReturn:
        raise ParameterError(message, key=name, source=source)

    def read(section: str, tables: tuple[str, ...]) -> tuple[dict[str, Any], dict[str, str]]:
        lookup = _lookup(tables)
        values, names = {}, {}
        for key, raw_value in raw.get(section, {}).items():
            if key not in lookup:
                fail(f"unknown key (known in [{section}]: {', '.join(lookup)})", f"{section}.{key}")
            _, base, spec, factor = lookup[key]
            if base in values:
                fail(f"given twice (also as {names[base]})", f"{section}.{key}")
            values[base] = _value(spec, factor, raw_value, f"{section}.{key}", fail)
            names[base] = f"{section}.{key}"
        return values, names

    values, names = read("motor", ("motor",))
    amp_values, amp_names = read("amplifier", ("amplifier",))
    motor, amplifier, module = _parts(values | amp_values, names | amp_names, fail, default_name=Path(source).stem)
    gearbox = None
    if "gearbox" in raw:
        g, g_names = read("gearbox", ("gearbox",))
        gearbox = _gearbox(g, g_names, fail, default_name="gearbox")
    screw = None
    s, s_names = read("lead_screw", ("lead_screw",))
    if s or module:
        for key in module:
            if key in s:
                fail(f"given in [motor] and in [lead_screw]", s_names[key])
        s = s | module
        screw = LeadScrew(**{FIELDS["lead_screw"][k].attribute: v for k, v in s.items() if k != "name"}, name=s.get("name", "lead screw"))
    r, _ = read("rules", ("rules",))
    rules = SizingRules(**{FIELDS["rules"][k].attribute: v for k, v in r.items()})
    return Drive(motor, amplifier, gearbox, screw, rules, source)


def _gearbox(values: dict[str, Any], names: dict[str, str], fail: Fail, default_name: str) -> Gearbox:
    attributes = {FIELDS["gearbox"][k].attribute: v for k, v in values.items() if k != "name"}
    return Gearbox(name=values.get("name", default_name), **attributes)


def drive_from_motor_table(table: Mapping[str, float], source: str) -> Drive:
    """The drive of a parameter file's ``[motor]`` table (``Parameters.motor``: the scalar ratings, in the file's units)."""

    def fail(message: str, name: str) -> NoReturn:
        raise ParameterError(message, key=f"motor.{name}", source=source)

    lookup = _lookup(("motor",))
    values, names = {}, {}
    for key, raw in table.items():
        if key not in lookup:
            fail("unknown key", key)
        _, base, spec, factor = lookup[key]
        values[base] = _value(spec, factor, raw, key, fail)
        names[base] = key
    motor, amplifier, module = _parts(values, names, fail, default_name="motor of the parameter file")
    screw = LeadScrew(name="lead screw of the parameter file", **module) if module else None
    return Drive(motor, amplifier, None, screw, SizingRules(), source)


# ---------------------------------------------------------------------------
# Catalogues (CSV)


def _read_catalogue(path: str | Path, tables: tuple[str, ...], required: tuple[str, ...], what: str, exclude: tuple[str, ...] = ()):
    """Rows of a catalogue as (line number, values by base name, column names by base name, fail)."""
    source = str(path)
    try:
        text = Path(path).read_bytes().removeprefix(b"\xef\xbb\xbf").decode("utf-8")
    except FileNotFoundError:
        raise CatalogueError(f"no such {what}", source) from None
    except IsADirectoryError:
        raise CatalogueError(f"is a folder, not a {what}", source) from None
    except OSError as error:
        raise CatalogueError(f"cannot read ({error.strerror})", source) from None
    except UnicodeDecodeError:
        raise CatalogueError("not a UTF-8 text file", source) from None
    lookup = _lookup(tables, exclude)
    header: list[str] | None = None
    header_line = 0
    rows = []
    for number, line in enumerate(text.splitlines(), start=1):
        if not line.strip() or line.lstrip().startswith("#"):
            continue
        cells = [cell.strip() for cell in next(csv.reader([line]))]
        if header is None:
            header, header_line = cells, number
            for column in header:
                if column not in lookup:
                    raise CatalogueError(f"unknown column (known: {', '.join(lookup)})", source, number, column)
            bases = [lookup[c][1] for c in header]
            for k, base in enumerate(bases):
                if base in bases[:k]:
                    raise CatalogueError("the same quantity in two columns", source, number, header[k])
            for base in required:
                if base not in bases:
                    spec = next(FIELDS[t][base] for t in tables if base in FIELDS[t])
                    alternatives = " or ".join(f"'{n}'" for n in spec.names(base))
                    raise CatalogueError(f"missing column {alternatives} ({spec.meaning})", source, number)
            continue
        if len(cells) != len(header):
            raise CatalogueError(f"{len(cells)} cells for {len(header)} columns", source, number)

        def fail(message: str, column: str, number=number) -> NoReturn:
            raise CatalogueError(message, source, number, column)

        values, names = {}, {}
        for column, cell in zip(header, cells):
            _, base, spec, factor = lookup[column]
            names[base] = column
            if not cell:
                if base in required:
                    fail("empty, but this column is required", column)
                continue
            values[base] = _value(spec, factor, _parse_cell(cell, spec, column, fail), column, fail)
        rows.append((number, values, names, fail))
    if header is None or not rows:
        raise CatalogueError(f"no entries (expected a header line and one {what.split()[0]} a line)", source, header_line or None)
    seen: dict[str, int] = {}
    for number, values, names, fail in rows:
        if values["name"] in seen:
            fail(f"name '{values['name']}' already used on line {seen[values['name']]}", names["name"])
        seen[values["name"]] = number
    return rows


def _parse_cell(cell: str, spec: _Field, column: str, fail: Fail):
    """A CSV cell as TOML would give it: text, a number, or (lists) numbers separated by ';' or spaces."""
    if spec.kind in ("text", "choice"):
        return cell
    parts = cell.replace(";", " ").split()
    numbers = []
    for part in parts:
        try:
            if "_" in part:  # float() reads 1_0 as 10
                raise ValueError(part)
            numbers.append(float(part))
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
    for number, values, names, fail in _read_catalogue(path, _MOTOR_CATALOGUE, _REQUIRED["motor"], "motor catalogue", exclude):
        motor, amplifier, _ = _parts(values, names, fail, default_name="")
        out.append((motor, amplifier))
    return out


def load_screw_catalogue(path: str | Path) -> list[LeadScrew]:
    """Lead screws, one a line: ``name``, ``lead_mm`` required; ``inertia_kgmm2``, ``dynamic_load_rating_N``,
    ``preload_N``, ``root_diameter_mm``, ``free_length_mm``, ``end_fixing``, ``stroke_mm``, ``axial_force_N`` optional.

    Raises:
        CatalogueError: one line naming the file, line and column.
    """
    rows = _read_catalogue(path, ("lead_screw",), _REQUIRED["lead_screw"], "screw catalogue")
    return [LeadScrew(name=v["name"], **{FIELDS["lead_screw"][k].attribute: x for k, x in v.items() if k != "name"}) for _, v, _, _ in rows]


def load_gearbox_catalogue(path: str | Path) -> list[Gearbox]:
    """Gearboxes, one a line: ``name``, ``ratio`` required; ``efficiency``, ``inertia_kgcm2`` optional (a ratio-1 line for direct drive).

    Raises:
        CatalogueError: one line naming the file, line and column.
    """
    rows = _read_catalogue(path, ("gearbox",), _REQUIRED["gearbox"], "gearbox catalogue")
    return [_gearbox(v, n, f, v["name"]) for _, v, n, f in rows]
